/* pmslam — a lidar's range noise from its own scans (see RangeNoise.h). */
#include <pmslam/sensor/RangeNoise.h>
#include <pmslam/util/RunStatistics.h>

#include <cmath>
#include <utility>

namespace pmslam
{
namespace
{
constexpr double kMaxSpan = 0.5;  // m: neighbours farther apart (+ 3 % of the range) span two surfaces
constexpr double kMinSinAngle = 0.5;  // surfaces seen at under 30° to the beam are left out (noise / small sine)
const double kMedianOfChordDistance = 0.6745 * std::sqrt(1.5);	// median |N(0, s·√1.5)| / s

double squared(double x, double y) { return x * x + y * y; }
}  // namespace

std::optional<double> scanRangeNoise(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPoint2D& origin,
									std::size_t minTriples)
{
	std::vector<double> along;	// per triple: the middle return's deviation along its beam
	along.reserve(points.size());
	for (std::size_t k = 1; k + 1 < points.size(); ++k)
	{
		const auto& a = points[k - 1];
		const auto& b = points[k];
		const auto& c = points[k + 1];
		const double bx = b.x - origin.x, by = b.y - origin.y, range = std::sqrt(squared(bx, by));
		const double span = kMaxSpan + 0.03 * range;
		const double acx = c.x - a.x, acy = c.y - a.y;
		const double chord = std::sqrt(squared(acx, acy));
		if (!(chord > 1e-6) || !(range > 1e-6) || squared(b.x - a.x, b.y - a.y) > span * span ||
			squared(c.x - b.x, c.y - b.y) > span * span)
			continue;
		// The surface's angle to the beam: a return moved by e along its beam is e·sin(angle) off the surface.
		const double sinAngle = std::abs(acx * by - acy * bx) / (chord * range);
		if (sinAngle < kMinSinAngle) continue;
		along.push_back(std::abs(acx * (b.y - a.y) - acy * (b.x - a.x)) / chord / sinAngle);
	}
	if (along.size() < minTriples) return std::nullopt;
	return percentile(std::move(along), 0.5) / kMedianOfChordDistance;
}

void RangeNoise::add(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPoint2D& origin)
{
	const auto s = scanRangeNoise(points, origin);
	if (!s) return;
	m_recent.push_back(*s);
	if (m_recent.size() > m_window) m_recent.pop_front();
	m_median = percentile(std::vector<double>(m_recent.begin(), m_recent.end()), 0.5);
}

}  // namespace pmslam
