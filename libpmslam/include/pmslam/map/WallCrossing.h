/* pmslam — do a scan's beams pass through the map's walls? (D47)
 *
 * A pose can fit a scan's endpoints on a map (a wall of a look-alike corridor, a room turned by 90°, another
 * building's corridor) while its beams pass through obstacles the map holds: the scan cannot have been
 * taken there. The share of such beams is evidence a match score does not see.
 */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/sensor/ScanPoints.h>

namespace pmslam
{
/** The fraction of the beams of `scan` (robot frame) seen from `pose` (the map's frame) whose cells include
 * an obstacle cell of `map` before they end, each beam cut `margin` m short of its endpoint (so that the
 * wall it hit does not count). Beams shorter than the margin are not counted; 0 without any. */
double crossedObstacleFraction(const DynamicDistanceMap& map, const ScanPoints& scan, const mrpt::math::TPose2D& pose,
							   double margin);

}  // namespace pmslam
