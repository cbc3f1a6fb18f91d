/* pmslam — the keyframe gate: which scans are matched, which go into the map.
 *
 * Two pairs of thresholds gate the front-end's work:
 * - a scan is matched once odometry says the robot moved matchLinDistance or
 *   turned matchAngDistance since the gate's origin (the last keyframe, or the
 *   last matched scan the map already explained); below that it keeps the odometry
 *   pose, and matching jitter does not accumulate while the robot stands still;
 * - a matched scan becomes a keyframe (inserted into the grid, handed to the loop
 *   closure) only once the robot moved mapInsertLinDistance or turned
 *   mapInsertAngDistance since the last keyframe, or when fewer than
 *   mapInsertBelowInliers of its points lie within the map's reach (new ground):
 *   redrawing the map at every slightly drifted pose blurs it, and lets the newest
 *   evidence overwrite the oldest.
 * Both origins move with the map when a loop closure corrects it.
 */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>

namespace pmslam
{
/** The MapBuilderOptions fields of the same names (see there for their defaults and why);
 * PerfectMatchSlam fills them. */
struct KeyframeGateOptions
{
	double matchLinDistance = 0, matchAngDistance = 0;	///< m, rad
	double mapInsertLinDistance = 0, mapInsertAngDistance = 0;	///< m, rad (0 and 0: every matched scan)
	double mapInsertBelowInliers = 0;
};

class KeyframeGate
{
   public:
	/** Both origins at `start`, the first scan's pose. */
	KeyframeGate(const KeyframeGateOptions& options, const mrpt::math::TPose2D& start)
		: m_options(options), m_lastInsertPose(start), m_lastMapPose(start)
	{
	}

	/** The prediction is far enough from the gate's origin to match the scan. */
	bool moved(const mrpt::math::TPose2D& predicted) const;
	/** A matched scan (at `pose`, `inlierFraction` of its points within the map's reach) is to be
	 * a keyframe; if not, the map already explains it and the next match is gated from `pose`. */
	bool admits(const mrpt::math::TPose2D& pose, double inlierFraction);
	/** A keyframe went into the map at `pose`. */
	void inserted(const mrpt::math::TPose2D& pose);
	/** The map moved by `correction` (a loop closure): the origins move with it. */
	void correct(const mrpt::poses::CPose2D& correction);

   private:
	KeyframeGateOptions m_options;
	mrpt::math::TPose2D m_lastInsertPose;  // the gate's origin for matching
	mrpt::math::TPose2D m_lastMapPose;	// pose of the last keyframe inserted into the grid
};

}  // namespace pmslam
