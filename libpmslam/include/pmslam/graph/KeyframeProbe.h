/* pmslam — a measurement tap on the loop closure's keyframes, for benchmarks.
 *
 * bench/calibrate_information.py needs each keyframe's time, pose and match curvature (the PM
 * Hessian the graph's edge information is made of). LoopClosure::addKeyframe() hands them to the
 * probe set here; none is set in any installed program (pm-slam-app-instrumented, built with the
 * tests and benchmarks, sets one), so a user's run costs one empty check per keyframe.
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <functional>

namespace pmslam
{
struct KeyframeSample
{
	double timestamp;
	mrpt::math::TPose2D pose;  ///< where the front-end put the keyframe (map frame)
	Eigen::Matrix3d hessian;   ///< the match's curvature (PerfectMatchMatcher::MatchInfo::hessian)
};

using KeyframeProbe = std::function<void(const KeyframeSample&)>;

/** Sets the process-wide probe (empty: none). Set it before a run starts: it is called from the
 * thread that adds keyframes, and not guarded against being replaced meanwhile. */
void setKeyframeProbe(KeyframeProbe probe);
const KeyframeProbe& keyframeProbe();

}  // namespace pmslam
