/* pmslam — the motion between two consecutive scans (see ScanToScan.h). */
#include <pmslam/slam/ScanToScan.h>

namespace pmslam
{
std::optional<mrpt::math::TPose2D> ScanToScan::motion(const PerfectMatchMatcher& matcher,
													  const std::vector<mrpt::math::TPoint2Df>& points,
													  const mrpt::math::TPose2D& guess, double minGoodness)
{
	std::optional<mrpt::math::TPose2D> out;
	const mrpt::poses::CPose2D start = m_at + mrpt::poses::CPose2D(guess);
	mrpt::poses::CPose2D at = start;
	if (!m_previous.empty() && !points.empty())
	{
		m_map.clear();
		for (const auto& p : m_previous)
		{
			const auto q = m_at.composePoint(mrpt::math::TPoint2D(p.x, p.y));
			m_map.addObstacle(m_map.worldToCell(q.x), m_map.worldToCell(q.y));
		}
		m_map.update();
		PerfectMatchMatcher::MatchInfo info;
		const mrpt::poses::CPose2D m(matcher.alignPoints(m_map, points, start.asTPose(), &info));
		if (info.goodness >= minGoodness)
		{
			out = (m - m_at).asTPose();
			at = m;
		}
	}
	m_previous = points;
	m_at = at;
	return out;
}

}  // namespace pmslam
