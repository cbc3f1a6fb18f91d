/* pmslam — the motion between two consecutive scans (see ScanToScan.h). */
#include <pmslam/slam/ScanToScan.h>

#include <cmath>

namespace pmslam
{
std::optional<mrpt::math::TPose2D> ScanToScan::motion(const PerfectMatchMatcher& matcher,
													  const std::vector<mrpt::math::TPoint2Df>& points,
													  const mrpt::math::TPose2D& guess, double minGoodness)
{
	std::optional<mrpt::math::TPose2D> out;
	if (!m_previous.empty() && !points.empty())
	{
		m_map.clear();
		const double r = m_map.resolution();
		for (const auto& p : m_previous) m_map.addObstacle(int(std::floor(p.x / r)), int(std::floor(p.y / r)));
		m_map.update();
		PerfectMatchMatcher::MatchInfo info;
		const mrpt::math::TPose2D m = matcher.alignPoints(m_map, points, guess, &info);
		if (info.goodness >= minGoodness) out = m;
	}
	m_previous = points;
	return out;
}

}  // namespace pmslam
