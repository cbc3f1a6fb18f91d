/* pmslam — directions a scan leaves open (a plain corridor, along it).
 *
 * A match fixes the heading and the position across a plain corridor's walls, but
 * not along it: there, dots and wall ends in the map decide, and the pose slides.
 * With each point pulling only across its surface (SurfaceNormals.h), the match's
 * information on the position shows such a direction as an eigenvalue below
 * degenerateBelow times the largest. Along it the prediction is kept (the match is
 * run again with the position held there and free across it); up to five times
 * that ratio, the match gets a share growing linearly from none to all, so the
 * position does not jump between match and prediction as a far feature comes and
 * goes from one scan to the next. Only with odometry: without it the prediction is
 * where the robot was, and holding it would stop a lidar alone in a corridor.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace pmslam
{
/** The MapBuilderOptions field of the same name (see there for its default and why). */
struct DegenerateDirectionsOptions
{
	double degenerateBelow = 0;	 ///< 0 = off
};

class DegenerateDirections
{
   public:
	explicit DegenerateDirections(const DegenerateDirectionsOptions& options) : m_options(options) {}

	/** The match at `matched` of `hits` (robot frame) predicted at `predicted`, with the position
	 * along a direction the scan leaves open held at the prediction; none when there is no such
	 * direction (or the check is off). */
	std::optional<mrpt::math::TPose2D> hold(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
											const std::vector<mrpt::math::TPoint2Df>& hits,
											const mrpt::math::TPose2D& matched,
											const mrpt::math::TPose2D& predicted) const;

	/** The curvature of the match of `hits` at `pose` with each point pulling only across its surface. */
	static Eigen::Matrix3d surfaceCurvature(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
											const std::vector<mrpt::math::TPoint2Df>& hits,
											const mrpt::math::TPose2D& pose);

	/** The direction (unit, map frame) along which `hessian` leaves the position unconstrained. */
	struct WeakDirection
	{
		Eigen::Vector2d direction;	///< unit vector the scan barely constrains the position along
		double matchShare = 0;		///< 0: the prediction decides there; towards 1: the match does
	};
	std::optional<WeakDirection> weakDirection(const Eigen::Matrix3d& hessian) const;

   private:
	DegenerateDirectionsOptions m_options;
};

}  // namespace pmslam
