/* pmslam — returns another scan saw through: things that moved.
 *
 * A return is a surface the beam stopped at. When another scan, taken a moment before from
 * nearly the same place, looked in that direction and its beams went on well past that point,
 * the surface was not there then: a person walking by, a door swinging, a cart, or a spurious
 * return of the lidar. A wall is seen by both scans at the same range, and a pillar or a
 * misplaced look-alike feature too: what is part of the building stays put from one scan to the
 * next, what moves does not.
 *
 * The test is conservative: a point counts as seen through only when every beam of the other
 * scan within `maxBeamGap` of its bearing (from that scan's sensor), at least one on each side,
 * ends `margin` beyond it. At a wall seen at a grazing angle the beams on one side end short of the
 * point; a point on a pillar just behind its edge as the other scan sees it has the beams that
 * pass the edge on one side and one that hits it further on. A bearing without a beam on both
 * sides (outside the other scan's field of view, dropped readings) counts as not seen through.
 *
 * Units: metres and radians; points in the robot frame of their scan; the other scans' poses
 * relative to that frame.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/sensor/ScanPoints.h>

#include <utility>
#include <vector>

namespace pmslam
{
/** One scan as range by bearing from its sensor: every return, and how far no-return or far
 * beams saw free space (ScanPoints::freeEnds). */
class ScanView
{
   public:
	explicit ScanView(const ScanPoints& scan);

	/** Every beam within `maxBeamGap` of the bearing of `q` (this scan's robot frame), at least one
	 * on each side, ends more than `margin` beyond it. */
	bool seesThrough(const mrpt::math::TPoint2D& q, double margin, double maxBeamGap) const;

   private:
	mrpt::math::TPoint2D m_origin;
	std::vector<std::pair<double, double>> m_beams;	// (bearing, range), by bearing
};

struct SeenThroughOptions
{
	/** m a beam of another scan must reach beyond a return to have seen through it: a little more
	 * than the range noise and the relative pose's error together, so that a wall both scans see
	 * never counts. */
	double margin = 0.25;
	/** rad: the beams that must all have seen through a point lie this close to its bearing: two
	 * a side for a 1° lidar, wider than an edge's parallax between two scans a moment apart. */
	double maxBeamGap = 2.0 * M_PI / 180;
};

/** For each hit of `scan`: whether one of `others` (each a scan and its pose relative to `scan`'s
 * robot frame) saw through it. */
std::vector<bool> seenThrough(const ScanPoints& scan,
							  const std::vector<std::pair<mrpt::math::TPose2D, const ScanPoints*>>& others,
							  const SeenThroughOptions& options = {});

}  // namespace pmslam
