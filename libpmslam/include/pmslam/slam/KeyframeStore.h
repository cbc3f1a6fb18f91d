/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * KeyframeStore: the scans inserted into the map with their corrected poses, kept
 * compactly, so the run can end with an MRPT simple map (.simplemap.gz) that
 * rebuilds the same grid.
 *
 * Why not a CSimpleMap from the start: each keyframe there is a CSensoryFrame holding
 * a CObservation2DRangeScan and a 6-D Gaussian pose, about 3.8 KB for a 180-beam scan,
 * and a SLAM run with a 1 cm insertion threshold inserts nearly every scan (47 MB on
 * intel). Here a keyframe is its pose, timestamp, ranges and validity flags (about 1 KB);
 * the sensor geometry shared by consecutive scans is stored once. The simple map is
 * made on demand (toSimpleMap) or written straight to a file one keyframe at a time
 * (saveSimpleMapGz), which never holds more than one keyframe as MRPT objects.
 *
 * Frames and units: poses are robot poses in the map frame (m, m, rad), as the
 * builder corrected them; every other scan field is kept exactly as it came.
 */
#pragma once

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cstdint>
#include <memory>
#include <string>
#include <deque>
#include <vector>

namespace pmslam
{
class KeyframeStore
{
   public:
	/** Appends a scan observed from robot pose `pose`. */
	void add(const mrpt::math::TPose2D& pose, const mrpt::obs::CObservation2DRangeScan& scan);
	void clear();
	std::size_t size() const { return m_frames.size(); }
	bool empty() const { return m_frames.empty(); }

	/** Pose and (rebuilt) scan of keyframe i. */
	mrpt::math::TPose2D pose(std::size_t i) const { return m_frames.at(i).pose; }
	/** Moves keyframe i (a loop closure corrected it). */
	void setPose(std::size_t i, const mrpt::math::TPose2D& pose) { m_frames.at(i).pose = pose; }
	mrpt::obs::CObservation2DRangeScan::Ptr scan(std::size_t i) const;

	/** All keyframes as an MRPT simple map (one sensory frame with one scan each, Gaussian
	 * poses with zero covariance), appended after the pairs of `prefix`. */
	mrpt::maps::CSimpleMap toSimpleMap(const mrpt::maps::CSimpleMap& prefix = {}) const;

	/** Writes what toSimpleMap(prefix) would hold, gz-compressed, atomically (temp file +
	 * rename), in the byte format MRPT's own CSimpleMap serialisation writes. */
	void saveSimpleMapGz(const std::string& path, const mrpt::maps::CSimpleMap& prefix = {}) const;

	/** Heap bytes held. */
	std::size_t memoryBytes() const;

   private:
	// Everything of a scan but its ranges: shared by the consecutive scans of one sensor.
	struct Geometry
	{
		float aperture = 0, maxRange = 0, stdError = 0, beamAperture = 0, deltaPitch = 0;
		bool rightToLeft = true;
		mrpt::poses::CPose3D sensorPose;
		std::string sensorLabel;
		bool sameAs(const mrpt::obs::CObservation2DRangeScan& s) const;
	};
	struct Frame
	{
		mrpt::math::TPose2D pose;
		mrpt::Clock::time_point stamp;
		uint32_t geometry;	// index into m_geometries
		uint32_t beams;
		std::size_t first;	// of its beams in m_ranges / m_valid (and m_intensity when it has them)
		int64_t firstIntensity;	 // -1: no intensities
	};
	std::vector<Geometry> m_geometries;
	std::vector<Frame> m_frames;
	// Beams of all keyframes in chunks (a vector would double, holding up to twice the data).
	std::deque<float> m_ranges;
	std::deque<uint8_t> m_valid;
	std::deque<int32_t> m_intensity;
};

}  // namespace pmslam
