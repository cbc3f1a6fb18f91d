/* pmslam — the surface normal at each scan point, where the scan shows a surface.
 *
 * A point on a wall says where the wall is, not where along it the point lies (the aperture
 * problem). With these normals the matcher's curvature counts each point only across its
 * surface (PerfectMatchMatcher::evaluate): otherwise a wall the map holds as dots (sampled
 * sparsely at a grazing angle, or ending where the last scan stopped seeing it) seems to fix a
 * plain corridor along its length, and the SLAM cannot tell that it is sliding there.
 *
 * Normal of point i: across the line fitted (principal axis) to its scan neighbours within
 * 0.3 m (shorter pieces give a normal of range noise), and at least the next return each side
 * (up to 5 m away: far returns on a grazing wall are metres apart), when their RMS distance from
 * that line is within 1 cm + 0.5 % of the range; (0, 0) where no
 * surface is seen (ends, corners, depth jumps, clutter), and those points pull in every
 * direction as before. Units and frame: unit vectors in the points' own (robot) frame.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>

#include <vector>

namespace pmslam
{
/** One normal per point of `points` (taken in scan order), (0, 0) where there is none. */
std::vector<mrpt::math::TPoint2Df> surfaceNormals(const std::vector<mrpt::math::TPoint2Df>& points);

}  // namespace pmslam
