/* pmslam — the Perfect Match matcher as an MRPT alignment algorithm (see PerfectMatchAligner.h). */
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/system/CTicTac.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/PerfectMatchAligner.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace pmslam
{
const DynamicDistanceMap& PerfectMatchAligner::distanceLayerFor(const mrpt::maps::COccupancyGridMap2D& grid)
{
	// FNV-1a over the raw cells and the geometry: rebuilding is O(cells) anyway,
	// hashing is much cheaper, so a grid that did not change is never rebuilt.
	uint64_t h = 1469598103934665603ull;
	auto mix = [&h](const void* p, std::size_t n) {
		const auto* b = static_cast<const unsigned char*>(p);
		for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
	};
	const auto& raw = grid.getRawMap();
	mix(raw.data(), raw.size() * sizeof(raw[0]));
	const float geom[5] = {grid.getXMin(), grid.getYMin(), grid.getXMax(), grid.getYMax(), grid.getResolution()};
	mix(geom, sizeof(geom));
	if (!m_cache.map || m_cache.grid != &grid || m_cache.contentHash != h ||
		m_cache.maxDistance != options.maxDistance || m_cache.threshold != options.occupiedThreshold)
	{
		m_cache.map = std::make_unique<DynamicDistanceMap>(
			distanceMapFromGrid(grid, options.maxDistance, options.occupiedThreshold));
		m_cache.grid = &grid;
		m_cache.contentHash = h;
		m_cache.maxDistance = options.maxDistance;
		m_cache.threshold = options.occupiedThreshold;
	}
	return *m_cache.map;
}

mrpt::poses::CPosePDF::Ptr PerfectMatchAligner::AlignPDF(const mrpt::maps::CMetricMap* m1,
														  const mrpt::maps::CMetricMap* m2,
														  const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
														  mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult> outInfo)
{
	mrpt::system::CTicTac timer;
	if (!m1 || !m2) throw std::invalid_argument("PerfectMatchAligner::AlignPDF: null map");
	const auto* grid = dynamic_cast<const mrpt::maps::COccupancyGridMap2D*>(m1);
	if (!grid)
		if (const auto* multi = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(m1))
			grid = multi->mapByClass<mrpt::maps::COccupancyGridMap2D>().get();
	if (!grid)
		throw std::invalid_argument(std::string("PerfectMatchAligner::AlignPDF: m1 must be an occupancy grid "
												"(COccupancyGridMap2D or a CMultiMetricMap holding one), got ") +
									m1->GetRuntimeClass()->className);
	const auto* pts = dynamic_cast<const mrpt::maps::CPointsMap*>(m2);
	if (!pts)
		throw std::invalid_argument(std::string("PerfectMatchAligner::AlignPDF: m2 must be a points map, got ") +
									m2->GetRuntimeClass()->className);

	// The distance layer and the grid share cells only when the grid origin lies
	// on the resolution lattice; otherwise work in the layer's frame, shifted.
	const DynamicDistanceMap* layer = nullptr;
	double shiftX = 0, shiftY = 0;
	if (const auto* live = dynamic_cast<const OccupancyDistanceGridMap*>(grid))
		layer = &live->distanceMap();
	else
	{
		layer = &distanceLayerFor(*grid);
		const double r = grid->getResolution();
		shiftX = grid->getXMin() - std::lround(grid->getXMin() / r) * r;
		shiftY = grid->getYMin() - std::lround(grid->getYMin() / r) * r;
	}

	const auto& xs = pts->getPointsBufferRef_x();
	const auto& ys = pts->getPointsBufferRef_y();
	std::vector<mrpt::math::TPoint2Df> points(xs.size());
	for (std::size_t i = 0; i < xs.size(); ++i) points[i] = {xs[i], ys[i]};

	mrpt::math::TPose2D init = initialEstimationPDF.mean.asTPose();
	init.x -= shiftX;
	init.y -= shiftY;
	TReturnInfo local;
	TReturnInfo* info = nullptr;
	if (outInfo)
		info = dynamic_cast<TReturnInfo*>(&outInfo.value().get());
	if (!info) info = &local;
	Eigen::Matrix3d cov;
	mrpt::math::TPose2D result = alignPoints(*layer, points, init, info, &cov);
	result.x += shiftX;
	result.y += shiftY;

	auto pdf = mrpt::poses::CPosePDFGaussian::Create();
	pdf->mean = mrpt::poses::CPose2D(result);
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) pdf->cov(r, c) = cov(r, c);
	info->executionTime = timer.Tac();
	if (outInfo) outInfo.value().get().executionTime = info->executionTime;
	return pdf;
}

mrpt::poses::CPose3DPDF::Ptr PerfectMatchAligner::Align3DPDF(const mrpt::maps::CMetricMap*,
															  const mrpt::maps::CMetricMap*,
															  const mrpt::poses::CPose3DPDFGaussian&,
															  mrpt::optional_ref<mrpt::slam::TMetricMapAlignmentResult>)
{
	throw std::logic_error(
		"PerfectMatchAligner::Align3DPDF: Perfect Match is a planar (2D) matcher; use AlignPDF with a 2D pose");
}

}  // namespace pmslam
