/* pmslam — the motion between two consecutive scans, measured by the scans alone.
 *
 * A lidar without odometry has no measurement of its motion but its scans. While
 * look-alike poses are undecided (Rivals.h) each is moved by the robot's motion and
 * then matched on the map; the motion must not be the constant-velocity guess, which
 * is wrong for a robot that stopped or turned during a gap, nor any rival's own
 * match, which the look-alike may have pulled to its spot. So the new scan is
 * matched by Perfect Match against the previous scan (a distance map of its points,
 * built only when asked): the scans' own odometry.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <optional>
#include <vector>

namespace pmslam
{
class ScanToScan
{
   public:
	/** The distance map of the previous scan: `resolution` (m) and its truncation `maxDistance` (m). */
	ScanToScan(double resolution, double maxDistance) : m_map(resolution, maxDistance) {}

	/** The scan (points in the robot frame) the next motion is measured from. */
	void keep(const std::vector<mrpt::math::TPoint2Df>& points) { m_previous = points; }

	/** The motion (robot frame) from the kept scan to `points`, Perfect Match from `guess`; none without
	 * a kept scan or where the two scans do not match (goodness below minGoodness). `points` are
	 * kept for the next one. */
	std::optional<mrpt::math::TPose2D> motion(const PerfectMatchMatcher& matcher,
											  const std::vector<mrpt::math::TPoint2Df>& points,
											  const mrpt::math::TPose2D& guess, double minGoodness = 0.5);

   private:
	DynamicDistanceMap m_map;
	std::vector<mrpt::math::TPoint2Df> m_previous;
};

}  // namespace pmslam
