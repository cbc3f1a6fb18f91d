/* pmslam — the Perfect Match scan matcher as an MRPT alignment algorithm.
 *
 * Aligns a point cloud (a laser scan in the robot frame) to an occupancy grid
 * (PerfectMatchMatcher.h) by maximising the Perfect Match likelihood field of Pedrosa, Lau and Reis:
 * an endpoint at distance Δ from the nearest obstacle has likelihood
 * p = σ²/(σ²+Δ²), so the pose minimises Σ ln(σ²+Δ²). Δ is read from a
 * truncated Euclidean distance map by bilinear interpolation, its gradient from
 * the same 4 samples, chained through each endpoint's pose Jacobian.
 *
 * Drop-in for mrpt::slam::CICP: AlignPDF(m1 = grid, m2 = points, initial).
 *  - m1 an OccupancyDistanceGridMap: its live distance layer is used directly.
 *  - m1 a stock COccupancyGridMap2D: a distance layer is built on demand and
 *    cached until the grid's contents change.
 * The result is a CPosePDFGaussian (pose of m2's frame in m1's frame) whose
 * covariance is the inverse curvature of the cost at the optimum.
 *
 * Units and frames: metres and radians throughout; m2's points are in its own
 * frame (the robot frame for a scan, sensorPose applied), poses are (x, y, θ)
 * of that frame in m1's (the map) frame. See share/examples/replace-icp/ for
 * the swap from CICP in a complete program.
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CMetricMapsAlignmentAlgorithm.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <cstdint>
#include <memory>

namespace pmslam
{
/** PerfectMatchMatcher (options, alignPoints(), cost(), the nested option and prior types) behind
 * MRPT's alignment interface. */
class PerfectMatchAligner : public mrpt::slam::CMetricMapsAlignmentAlgorithm, public PerfectMatchMatcher
{
   public:
	/** What AlignPDF reports, like CICP::TReturnInfo. */
	struct TReturnInfo : public mrpt::slam::TMetricMapAlignmentResult, public MatchInfo
	{
	};

	PerfectMatchAligner() = default;
	explicit PerfectMatchAligner(const TConfigParams& p) : PerfectMatchMatcher(p) {}

	mrpt::poses::CPosePDF::Ptr AlignPDF(const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
										const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
										mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo =
											std::nullopt) override;
	/** Not supported: Perfect Match is a planar matcher. Throws std::logic_error. */
	mrpt::poses::CPose3DPDF::Ptr Align3DPDF(const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
											const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
											mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo =
												std::nullopt) override;

   private:
	// Cache of the distance layer built for a stock grid.
	struct GridCache
	{
		const void* grid = nullptr;
		uint64_t contentHash = 0;
		double maxDistance = 0, threshold = 0;
		std::unique_ptr<DynamicDistanceMap> map;
	};
	GridCache m_cache;
	const DynamicDistanceMap& distanceLayerFor(const mrpt::maps::COccupancyGridMap2D& grid);
};

}  // namespace pmslam
