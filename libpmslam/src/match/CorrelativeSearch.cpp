/* pmslam — correlative search (see CorrelativeSearch.h). */
#include <mrpt/math/wrap2pi.h>
#include <pmslam/match/CorrelativeSearch.h>

#include <algorithm>
#include <cmath>

namespace pmslam
{
std::vector<CorrelativeSearch::Candidate> CorrelativeSearch::search(const DynamicDistanceMap& map,
																	const std::vector<mrpt::math::TPoint2Df>& points,
																	const mrpt::math::TPose2D& centre,
																	double linearWindow, double angularWindow) const
{
	std::vector<mrpt::math::TPoint2Df> pts;
	const std::size_t stride = std::max<std::size_t>(1, (points.size() + options.maxPoints - 1) / options.maxPoints);
	for (std::size_t i = 0; i < points.size(); i += stride)
		if (std::isfinite(points[i].x) && std::isfinite(points[i].y)) pts.push_back(points[i]);
	if (pts.empty() || !std::isfinite(centre.x + centre.y + centre.phi)) return {};

	// Rotation step: the far points (95th percentile of range) move about one linear step.
	std::vector<float> ranges;
	for (const auto& p : pts) ranges.push_back(std::hypot(p.x, p.y));
	const std::size_t k95 = std::min(ranges.size() - 1, ranges.size() * 95 / 100);
	std::nth_element(ranges.begin(), ranges.begin() + k95, ranges.end());
	const double far = std::max(0.5f, ranges[k95]);
	const double angStep = std::clamp(options.linearStep / far, options.minAngularStep, options.maxAngularStep);

	const double res = map.resolution();
	const int step = std::max(1, int(std::lround(options.linearStep / res)));	 // cells per lattice step
	const int nT = int(std::ceil(linearWindow / (step * res)));
	const int nA = int(std::ceil(angularWindow / angStep));
	const int side = 2 * nT + 1;

	// Likelihood per truncated distance, tabulated on a fine grid of distances.
	const double s2 = options.fieldSigma * options.fieldSigma;
	const int lutSize = 1024;
	const double lutScale = (lutSize - 1) / map.maxDistance();
	std::vector<float> lut(lutSize);
	for (int i = 0; i < lutSize; ++i)
	{
		const double d = i / lutScale;
		lut[i] = float(s2 / (s2 + d * d));
	}

	struct Peak
	{
		float score;
		int a, tx, ty;
	};
	std::vector<Peak> peaks;
	std::vector<float> acc(std::size_t(side) * side);
	std::vector<int> pcx(pts.size()), pcy(pts.size());
	for (int a = -nA; a <= nA; ++a)
	{
		const double th = centre.phi + a * angStep;
		const double c = std::cos(th), s = std::sin(th);
		for (std::size_t k = 0; k < pts.size(); ++k)
		{
			const double wx = centre.x + c * pts[k].x - s * pts[k].y, wy = centre.y + s * pts[k].x + c * pts[k].y;
			// A lattice step is a whole number of cells: shifting the pose shifts the cell.
			pcx[k] = map.worldToCell(wx);
			pcy[k] = map.worldToCell(wy);
		}
		std::fill(acc.begin(), acc.end(), 0.0f);
		for (std::size_t k = 0; k < pts.size(); ++k)
			for (int ty = -nT; ty <= nT; ++ty)
			{
				float* row = &acc[std::size_t(ty + nT) * side];
				map.forRowSamples(pcx[k] - nT * step, pcy[k] + ty * step, step, side,
								  [&](int tx, float d) { row[tx] += lut[int(d * lutScale + 0.5f)]; });
			}
		// Local maxima of this rotation's slice.
		for (int ty = 0; ty < side; ++ty)
			for (int tx = 0; tx < side; ++tx)
			{
				const float v = acc[std::size_t(ty) * side + tx];
				bool isMax = v > 0;
				for (int dy = -1; dy <= 1 && isMax; ++dy)
					for (int dx = -1; dx <= 1 && isMax; ++dx)
					{
						const int x = tx + dx, y = ty + dy;
						if ((dx || dy) && x >= 0 && y >= 0 && x < side && y < side && acc[std::size_t(y) * side + x] > v)
							isMax = false;
					}
				if (isMax) peaks.push_back({v, a, tx - nT, ty - nT});
			}
		// Keep the list short: only the best few per slice can matter.
		if (peaks.size() > 64 * options.candidates)
		{
			std::nth_element(peaks.begin(), peaks.begin() + 16 * options.candidates, peaks.end(),
							 [](const Peak& l, const Peak& r) { return l.score > r.score; });
			peaks.resize(16 * options.candidates);
		}
	}
	std::sort(peaks.begin(), peaks.end(), [](const Peak& l, const Peak& r) { return l.score > r.score; });
	std::vector<Candidate> out;
	std::vector<Peak> kept;
	for (const Peak& p : peaks)
	{
		// The same peak seen from a neighbouring rotation or lattice pose is not a new candidate.
		const bool dup = std::any_of(kept.begin(), kept.end(), [&](const Peak& q) {
			return std::abs(q.a - p.a) <= 2 && std::abs(q.tx - p.tx) <= 2 && std::abs(q.ty - p.ty) <= 2;
		});
		if (dup) continue;
		kept.push_back(p);
		out.push_back({mrpt::math::TPose2D(centre.x + p.tx * step * res, centre.y + p.ty * step * res,
										   mrpt::math::wrapToPi(centre.phi + p.a * angStep)),
					   p.score / pts.size()});
		if (out.size() >= options.candidates) break;
	}
	return out;
}

std::vector<CorrelativeSearch::Candidate> CorrelativeSearch::coarseToFine(
	const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& centre,
	double linearWindow, double angularWindow, std::size_t candidates)
{
	Options co;
	co.candidates = candidates;
	co.linearStep = std::max(0.1, linearWindow / 8);
	co.fieldSigma = std::min(map.maxDistance(), 1.5 * co.linearStep);
	co.maxAngularStep = std::max(co.maxAngularStep, std::min(2.0 * M_PI / 180, angularWindow / 45));
	std::vector<Candidate> starts = CorrelativeSearch(co).search(map, points, centre, linearWindow, angularWindow);
	if (co.linearStep <= 0.1 + 1e-9) return starts;
	Options fo;
	fo.candidates = 1;
	std::vector<Candidate> fine;
	for (const auto& c : starts)
	{
		const auto f = CorrelativeSearch(fo).search(map, points, c.pose, co.linearStep, 2 * co.maxAngularStep);
		if (!f.empty()) fine.push_back(f.front());
	}
	return fine;
}

}  // namespace pmslam
