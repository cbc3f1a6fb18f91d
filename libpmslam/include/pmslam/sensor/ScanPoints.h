/* pmslam — a 2D range scan as points in the robot frame.
 *
 * The matcher and the mapper need the same thing from a scan: the beam
 * endpoints that hit something, and the directions of the beams that saw
 * nothing (to carve free space). Both are expressed in the robot base frame
 * using the scan's own sensorPose, so an offset or upside-down laser works.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <vector>

namespace pmslam
{
struct ScanPointsOptions
{
	double minRange = 0.05;	 ///< readings closer than this (m) are ignored (self-hits, dust)
	/** Valid readings farther than this (m) are used only to carve free space (0 = no limit). */
	double maxHitRange = 0.0;
	/** "No return" readings (invalid with range >= the scan's maxRange) carve free
	 * space up to this distance (m); 0 disables carving for them. */
	double noReturnCarveRange = 0.0;
};

struct ScanPoints
{
	mrpt::math::TPoint2D sensorOrigin{0, 0};  ///< laser centre in the robot frame (m)
	std::vector<mrpt::math::TPoint2Df> hits;  ///< endpoints of returns (robot frame, m)
	std::vector<mrpt::math::TPoint2Df> freeEnds;  ///< where no-return / far beams stop carving (robot frame, m)
};

/** Converts one scan, honouring aperture, direction, validity and sensorPose. */
ScanPoints scanToPoints(const mrpt::obs::CObservation2DRangeScan& scan, const ScanPointsOptions& opts = {});

}  // namespace pmslam
