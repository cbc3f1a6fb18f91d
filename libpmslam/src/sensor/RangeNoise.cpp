/* pmslam — a lidar's range noise from its own scans (see RangeNoise.h). */
#include <pmslam/sensor/RangeNoise.h>

#include <algorithm>
#include <cmath>

namespace pmslam
{
namespace
{
constexpr double kMaxSpan = 0.5;  // m: neighbours farther apart (+ 3 % of the range) span two surfaces
const double kMedianOfChordDistance = 0.6745 * std::sqrt(1.5);	// median |N(0, s·√1.5)| / s

double median(std::vector<double>& v)
{
	const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
	std::nth_element(v.begin(), mid, v.end());
	return *mid;
}

double squared(double x, double y) { return x * x + y * y; }
}  // namespace

std::optional<double> scanRangeNoise(const std::vector<mrpt::math::TPoint2Df>& points, std::size_t minTriples)
{
	std::vector<double> chord;
	chord.reserve(points.size());
	for (std::size_t k = 1; k + 1 < points.size(); ++k)
	{
		const auto& a = points[k - 1];
		const auto& b = points[k];
		const auto& c = points[k + 1];
		const double span = kMaxSpan + 0.03 * std::sqrt(squared(b.x, b.y));
		const double acx = c.x - a.x, acy = c.y - a.y;
		const double ac2 = squared(acx, acy);
		if (!(ac2 > 1e-12) || squared(b.x - a.x, b.y - a.y) > span * span || squared(c.x - b.x, c.y - b.y) > span * span)
			continue;
		chord.push_back(std::abs(acx * (b.y - a.y) - acy * (b.x - a.x)) / std::sqrt(ac2));
	}
	if (chord.size() < minTriples) return std::nullopt;
	return median(chord) / kMedianOfChordDistance;
}

void RangeNoise::add(const std::vector<mrpt::math::TPoint2Df>& points)
{
	const auto s = scanRangeNoise(points);
	if (!s) return;
	m_recent.push_back(*s);
	if (m_recent.size() > m_window) m_recent.pop_front();
}

std::optional<double> RangeNoise::noise() const
{
	if (m_recent.empty()) return std::nullopt;
	std::vector<double> v(m_recent.begin(), m_recent.end());
	return median(v);
}

}  // namespace pmslam
