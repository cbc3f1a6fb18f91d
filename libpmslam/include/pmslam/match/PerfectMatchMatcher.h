/* pmslam — the Perfect Match scan matcher.
 *
 * Aligns a point cloud (a laser scan in the robot frame) to a distance map
 * by maximising the Perfect Match likelihood field of Pedrosa, Lau and Reis:
 * an endpoint at distance Δ from the nearest obstacle has likelihood
 * p = σ²/(σ²+Δ²), so the pose minimises Σ ln(σ²+Δ²). Δ is read from a
 * truncated Euclidean distance map by bilinear interpolation, its gradient from
 * the same 4 samples, chained through each endpoint's pose Jacobian.
 *
 * This is the matcher itself, with no MRPT alignment interface, so that a program
 * that only maps (pm-slam-app) need not load mrpt-slam and the ~120 shared
 * libraries behind it (about 30 MB of resident memory). PerfectMatchAligner wraps
 * it as a mrpt::slam::CMetricMapsAlignmentAlgorithm, the drop-in for CICP.
 *
 * Units and frames: metres and radians throughout; points are in their own frame
 * (the robot frame for a scan, sensorPose applied), poses are (x, y, θ) of that
 * frame in the map frame.
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/util/ConfigKeys.h>

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace pmslam
{
class PerfectMatchMatcher
{
   public:
	enum class Optimizer
	{
		RPROP,	///< resilient back-propagation on the log-likelihood (the paper's choice)
		GaussNewton,  ///< iteratively reweighted least squares on Δ
		LevenbergMarquardt	///< as GaussNewton, damped
	};
	/** Weighting of the residuals Δ for GaussNewton / LevenbergMarquardt.
	 * PerfectMatch weights 1/(σ²+Δ²) minimise exactly the PM cost; None is plain
	 * least squares on Δ; Huber is quadratic below σ, linear beyond. RPROP always
	 * uses the PM cost. */
	enum class RobustKernel
	{
		PerfectMatch,
		None,
		Huber
	};

	/** Options; INI section [PerfectMatch] by convention. */
	struct TConfigParams : public mrpt::config::CLoadableOptions
	{
		Optimizer optimizer = Optimizer::RPROP;
		RobustKernel robustKernel = RobustKernel::PerfectMatch;
		double sigma = 0.055;  ///< σ of the likelihood field (m)
		unsigned maxIterations = 60;  ///< optimiser iterations at most
		double rpropInitialStepXY = 0.01;  ///< first RPROP step in x, y (m)
		double rpropInitialStepPhi = 0.01;	///< first RPROP step in θ (rad)
		double rpropIncrease = 1.2, rpropDecrease = 0.5;  ///< RPROP step factors η+, η−
		double rpropMaxStepXY = 0.2, rpropMaxStepPhi = 0.1;	 ///< RPROP step bounds (m, rad)
		/** Gauss-Newton steps on the same cost after RPROP, to settle on the minimum (0 = pure RPROP). */
		unsigned rpropRefineIterations = 0;
		double minStepXY = 1e-3, minStepPhi = 1e-3;	 ///< converged when every step is below these (D51)
		unsigned decimation = 1;  ///< use every k-th point of m2
		/** PerfectMatchAligner with a stock COccupancyGridMap2D: truncation (m) of the distance layer
		 * built on demand, and the occupancy probability above which a cell is an obstacle. */
		double maxDistance = 0.5;
		double occupiedThreshold = 0.5;

		/** Every INI key of this struct (ConfigKeys.h): loading, dumping and the documentation. */
		static const std::vector<config::Key<TConfigParams>>& keys();
		void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
		void dumpToTextStream(std::ostream& out) const override;
	};

	/** What a match reports. */
	struct MatchInfo
	{
		unsigned nIterations = 0;
		std::size_t nPoints = 0;	///< points used
		double finalCost = 0;  ///< mean over points of ln(1 + Δ²/σ²) at the result (0 = perfect)
		double inlierFraction = 0;	///< points closer to an obstacle than the truncation distance
		double goodness = 0;  ///< mean likelihood σ²/(σ²+Δ²), in [0,1]
		/** Mean likelihood over the inliers only: how well the scan agrees where it overlaps the
		 * map, whatever the share of new ground (a random pose scores ~0.2, a true one 0.7–0.95). */
		double inlierGoodness = 0;
		Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();	///< curvature of Σ ln(σ²+Δ²) at the result
	};

	PerfectMatchMatcher() = default;
	explicit PerfectMatchMatcher(const TConfigParams& p) : options(p) {}

	TConfigParams options;

	/** An optional Gaussian prior on the pose (e.g. the odometry prediction): adds
	 * ½ eᵀ·information·e to the cost, e = pose − mean (angle wrapped). Where the scan
	 * constrains the pose it barely matters; along a featureless corridor it keeps the
	 * pose where odometry put it instead of letting it slide. */
	struct PosePrior
	{
		mrpt::math::TPose2D mean;
		Eigen::Matrix3d information = Eigen::Matrix3d::Zero();	///< inverse covariance (x, y, θ)
		/** Diagonal prior from standard deviations (m, rad). */
		static PosePrior diagonal(const mrpt::math::TPose2D& mean, double sigmaXY, double sigmaPhi);
	};

	/** Aligns `points` (robot frame) to `map` starting at `initial`. Returns the pose;
	 * fills info and covariance if given. */
	mrpt::math::TPose2D alignPoints(const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& points,
									const mrpt::math::TPose2D& initial, MatchInfo* info = nullptr,
									Eigen::Matrix3d* covariance = nullptr, const PosePrior* prior = nullptr) const;

	/** What alignPoints() reports, for `points` at `pose` as it is (no optimisation). With `normals`
	 * (one per point, robot frame, (0, 0) = none; see SurfaceNormals.h) a point's gradient counts
	 * only along its normal in the curvature: a plain corridor then shows that it does not fix the
	 * pose along its length, where dots and wall ends in the map would otherwise seem to. */
	MatchInfo evaluate(const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& points,
					   const mrpt::math::TPose2D& pose, const std::vector<mrpt::math::TPoint2Df>* normals = nullptr) const;

	/** The PM cost Σ ln(1+Δ²/σ²) of `points` at `pose` (for tests and diagnostics). */
	double cost(const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& points,
				const mrpt::math::TPose2D& pose) const;

	/** Builds a distance layer from a stock MRPT grid (cells with occupancy above threshold are obstacles). */
	static DynamicDistanceMap distanceMapFromGrid(const mrpt::maps::COccupancyGridMap2D& grid, double maxDistance,
												  double occupiedThreshold);
};

std::string toString(PerfectMatchMatcher::Optimizer o);
std::string toString(PerfectMatchMatcher::RobustKernel k);

}  // namespace pmslam
