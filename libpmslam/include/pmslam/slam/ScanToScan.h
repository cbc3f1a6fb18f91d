/* pmslam — the motion between two consecutive scans, measured by the scans alone.
 *
 * A lidar without odometry has no measurement of its motion but its scans. While
 * look-alike poses are undecided (Rivals.h) each is moved by the robot's motion and
 * then matched on the map; the motion must not be the constant-velocity guess, which
 * is wrong for a robot that stopped or turned during a gap, nor any rival's own
 * match, which the look-alike may have pulled to its spot. So the new scan is
 * matched by Perfect Match against the previous scan (a distance map of its points,
 * built only when asked): the scans' own odometry.
 *
 * The distance map puts each point at the centre of its cell: a wall moves by up to half a
 * cell. Were the previous scan's map built in its own frame, every match would be pulled by
 * that same shift (a wall 2 cm off at each scan is 2 cm of sideways motion at each scan) and
 * the motion would drift by centimetres per step. So the scans are placed in a frame of their
 * own that the measured motions carry along: a wall falls into the same cells scan after scan,
 * its rounding becomes a constant offset of that frame, and the motions between scans do not
 * drift with it.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
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
	void keep(const std::vector<mrpt::math::TPoint2Df>& points)
	{
		m_previous = points;
		m_at = mrpt::poses::CPose2D();
	}

	/** The motion (robot frame) from the kept scan to `points`, Perfect Match from `guess`; none without
	 * a kept scan or where the two scans do not match (goodness below minGoodness). `points` are
	 * kept for the next one. */
	std::optional<mrpt::math::TPose2D> motion(const PerfectMatchMatcher& matcher,
											  const std::vector<mrpt::math::TPoint2Df>& points,
											  const mrpt::math::TPose2D& guess, double minGoodness = 0.5);

   private:
	DynamicDistanceMap m_map;
	std::vector<mrpt::math::TPoint2Df> m_previous;
	mrpt::poses::CPose2D m_at;	///< the previous scan's pose in the scans' own frame
};

}  // namespace pmslam
