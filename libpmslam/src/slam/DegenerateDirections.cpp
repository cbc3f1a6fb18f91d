/* pmslam — directions a scan leaves open (see DegenerateDirections.h). */
#include <pmslam/sensor/SurfaceNormals.h>
#include <pmslam/slam/DegenerateDirections.h>

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace pmslam
{
std::optional<mrpt::math::TPose2D> DegenerateDirections::hold(const PerfectMatchMatcher& matcher,
															   const DynamicDistanceMap& map,
															   const std::vector<mrpt::math::TPoint2Df>& hits,
															   const mrpt::math::TPose2D& matched,
															   const mrpt::math::TPose2D& predicted) const
{
	if (!(m_options.degenerateBelow > 0)) return std::nullopt;
	const auto weak = weakDirection(surfaceCurvature(matcher, map, hits, matched));
	if (!weak) return std::nullopt;
	// Match again with the position along the weak direction held at the prediction (a stiff
	// prior there and nowhere else): across it and in heading the scan decides. Where the scan
	// only just constrains that direction, the match has a share of the say there.
	const Eigen::Vector2d& dir = weak->direction;
	const Eigen::Vector2d off(matched.x - predicted.x, matched.y - predicted.y);
	const double keep = weak->matchShare * dir.dot(off);  // along dir, from the prediction
	PerfectMatchMatcher::PosePrior pin;
	pin.mean = mrpt::math::TPose2D(predicted.x + keep * dir[0], predicted.y + keep * dir[1], matched.phi);
	pin.information.topLeftCorner<2, 2>() = 1e6 * dir * dir.transpose();
	const Eigen::Vector2d start = Eigen::Vector2d(matched.x, matched.y) - (dir.dot(off) - keep) * dir;
	return matcher.alignPoints(map, hits, mrpt::math::TPose2D(start[0], start[1], matched.phi), nullptr, nullptr, &pin);
}

Eigen::Matrix3d DegenerateDirections::surfaceCurvature(const PerfectMatchMatcher& matcher,
													   const DynamicDistanceMap& map,
													   const std::vector<mrpt::math::TPoint2Df>& hits,
													   const mrpt::math::TPose2D& pose)
{
	// Each point pulling only across its surface: dots and wall ends in the map do not count as
	// constraints, so a plain corridor shows that it does not fix the pose along it.
	const std::vector<mrpt::math::TPoint2Df> normals = surfaceNormals(hits);
	return matcher.evaluate(map, hits, pose, &normals).hessian;
}

std::optional<DegenerateDirections::WeakDirection> DegenerateDirections::weakDirection(const Eigen::Matrix3d& hessian) const
{
	// The information on the position at the matched heading: a plain corridor fixes the heading
	// and the position across it, not along it. Below degenerateBelow x the largest the scan has no
	// say along it; up to five times that, a share growing linearly from none to all.
	if (!hessian.allFinite()) return std::nullopt;
	const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(hessian.topLeftCorner<2, 2>());
	if (eig.info() != Eigen::Success) return std::nullopt;
	const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
	constexpr double kAllAt = 5;  // x degenerateBelow: from there on the match alone decides
	const double t = m_options.degenerateBelow;
	if (!(lambda[1] > 0) || lambda[0] >= kAllAt * t * lambda[1]) return std::nullopt;
	const double ratio = std::max(lambda[0], 0.0) / lambda[1];
	return WeakDirection{Eigen::Vector2d(eig.eigenvectors().col(0)), std::clamp((ratio - t) / ((kAllAt - 1) * t), 0.0, 1.0)};
}

}  // namespace pmslam
