/* pmslam — online Perfect Match SLAM as an MRPT map builder.
 *
 * Follows mrpt::slam::CMetricMapBuilder the way CMetricMapBuilderICP does:
 * feed it action/observation pairs or plain observations and it keeps the
 * current pose, the map (an OccupancyDistanceGridMap inside a CMultiMetricMap)
 * and the keyframes that built it (a CSimpleMap). The SLAM itself is
 * PerfectMatchSlam (see PerfectMatchSlam.h for the loop, the options and the
 * frames); this class adds MRPT's interface to it: the CMetricMapBuilder
 * overrides, options.enableMapUpdating as the map-updating switch,
 * critZoneChangingMap held while a scan is processed, and warnings through
 * MRPT's logger.
 *
 * The loop (Pedrosa, Lau, Reis): the first scan is inserted at (0,0,0) without
 * matching. Each later scan's pose is predicted from odometry; once the robot
 * has moved more than the insertion thresholds since the last insertion, the
 * scan is matched against the map with the Perfect Match matcher starting from
 * the prediction, and inserted at the corrected pose. Scans below the threshold
 * keep the odometry-propagated pose. Every scan gets a pose.
 *
 * Localisation: initializeWithFixedMap() loads a prior COccupancyGridMap2D
 * and turns map updating off (options.enableMapUpdating = false); every scan
 * is then matched against that fixed map and nothing is inserted.
 *
 * Frames: poses are of the robot base in the map frame (metres, radians);
 * the first scan's pose is the origin of the map frame unless initialize()
 * is given x0 (or the fixed map's frame is used). Scans carry their own
 * sensorPose relative to the base (offset, yawed or upside-down lasers).
 * Odometry is used only through its increments, so its frame does not matter.
 */
#pragma once

#include <mrpt/slam/CMetricMapBuilder.h>
#include <pmslam/slam/PerfectMatchSlam.h>

#include <mutex>
#include <string>

namespace pmslam
{
class CMetricMapBuilderPM : public mrpt::slam::CMetricMapBuilder, public PerfectMatchSlam
{
   public:
	CMetricMapBuilderPM();
	~CMetricMapBuilderPM() override;

	// --- CMetricMapBuilder interface (the PerfectMatchSlam methods of the same names) ---
	/** Resets; optionally starts from an existing map (its scans are re-inserted) and pose x0. */
	void initialize(const mrpt::maps::CSimpleMap& initialMap = mrpt::maps::CSimpleMap(),
					const mrpt::poses::CPosePDF* x0 = nullptr) override;
	mrpt::poses::CPose3DPDF::Ptr getCurrentPoseEstimation() const override;
	void processActionObservation(mrpt::obs::CActionCollection& action, mrpt::obs::CSensoryFrame& in_SF) override;
	void getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const override;
	unsigned int getCurrentlyBuiltMapSize() override;
	const mrpt::maps::CMultiMetricMap* getCurrentlyBuiltMetricMap() const override;
	void saveCurrentEstimationToImage(const std::string& file, bool formatEMF_BMP = true) override;

	/** options.enableMapUpdating (MRPT's switch) is the map-updating switch. */
	bool mapUpdating() const override { return options.enableMapUpdating; }
	void setMapUpdating(bool on) override { options.enableMapUpdating = on; }

   protected:
	void warn(const std::string& message) const override;
	std::mutex& mapMutex() const override { return const_cast<std::mutex&>(critZoneChangingMap); }
};

}  // namespace pmslam
