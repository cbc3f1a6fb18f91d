/* pmslam — returns another scan saw through (see SeenThrough.h). */
#include <mrpt/math/wrap2pi.h>
#include <pmslam/sensor/SeenThrough.h>

#include <algorithm>
#include <cmath>

namespace pmslam
{
ScanView::ScanView(const ScanPoints& scan) : m_origin(scan.sensorOrigin)
{
	m_beams.reserve(scan.hits.size() + scan.freeEnds.size());
	auto add = [&](const mrpt::math::TPoint2Df& p) {
		const double dx = p.x - m_origin.x, dy = p.y - m_origin.y;
		if (std::isfinite(dx) && std::isfinite(dy)) m_beams.emplace_back(std::atan2(dy, dx), std::hypot(dx, dy));
	};
	for (const auto& p : scan.hits) add(p);
	for (const auto& p : scan.freeEnds) add(p);
	std::sort(m_beams.begin(), m_beams.end());
}

bool ScanView::seesThrough(const mrpt::math::TPoint2D& q, double margin, double maxBeamGap) const
{
	const std::size_t n = m_beams.size();
	if (n < 2) return false;
	const double dx = q.x - m_origin.x, dy = q.y - m_origin.y;
	const double bearing = std::atan2(dy, dx), range = std::hypot(dx, dy);
	// Every beam within maxBeamGap on either side of the bearing (wrapping round the circle: a 360°
	// lidar), at least one on each side, and each ending beyond the point. Not only the two
	// nearest: a point just behind an edge seen from here, by less than a beam's spacing, has both
	// nearest beams passing the edge, the next one hitting it.
	const std::size_t after = std::size_t(
		std::lower_bound(m_beams.begin(), m_beams.end(), std::make_pair(bearing, -1.0)) - m_beams.begin());
	auto sideSeesThrough = [&](bool forward) {
		std::size_t seen = 0;
		for (std::size_t step = 0; step < n; ++step)
		{
			const std::size_t k = forward ? (after + step) % n : (after + n - 1 - step) % n;
			if (std::abs(mrpt::math::wrapToPi(m_beams[k].first - bearing)) > maxBeamGap) break;
			if (m_beams[k].second <= range + margin) return false;
			++seen;
		}
		return seen > 0;
	};
	return sideSeesThrough(false) && sideSeesThrough(true);
}

std::vector<bool> seenThrough(const ScanPoints& scan,
							  const std::vector<std::pair<mrpt::math::TPose2D, const ScanPoints*>>& others,
							  const SeenThroughOptions& options)
{
	std::vector<bool> out(scan.hits.size(), false);
	for (const auto& [pose, other] : others)
	{
		const ScanView view(*other);
		// `scan`'s points in the other scan's robot frame.
		const double c = std::cos(pose.phi), s = std::sin(pose.phi);
		for (std::size_t k = 0; k < scan.hits.size(); ++k)
		{
			if (out[k]) continue;
			const double x = scan.hits[k].x - pose.x, y = scan.hits[k].y - pose.y;
			out[k] = view.seesThrough({c * x + s * y, -s * x + c * y}, options.margin, options.maxBeamGap);
		}
	}
	return out;
}

}  // namespace pmslam
