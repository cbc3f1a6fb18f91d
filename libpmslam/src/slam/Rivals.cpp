/* pmslam — look-alike poses kept until the scans decide (see Rivals.h). */
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/Rivals.h>

#include <algorithm>

namespace pmslam
{
bool Rivals::distinct(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b) const
{
	return std::hypot(a.x - b.x, a.y - b.y) >= m_options.distinctLinear ||
		   std::abs(mrpt::math::wrapToPi(a.phi - b.phi)) >= m_options.distinctAngular;
}

void Rivals::add(const mrpt::math::TPose2D& pose, const mrpt::math::TPose2D& origin,
				 const PerfectMatchMatcher::MatchInfo& info, std::size_t tag)
{
	if (std::any_of(m_rivals.begin(), m_rivals.end(), [&](const Rival& r) { return !distinct(r.pose, pose); })) return;
	Rival r;
	r.pose = r.lastView = pose;
	r.origin = origin;
	r.info = info;
	r.goodnessSum = info.goodness;
	r.views = 1;
	r.path.emplace_back(tag, pose);
	m_rivals.push_back(r);
}

void Rivals::follow(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
					const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& motion,
					const mrpt::math::TPoint2D& shift, std::size_t tag)
{
	if (m_rivals.empty()) return;
	for (auto& r : m_rivals)
	{
		const auto moved = (mrpt::poses::CPose2D(r.pose) + mrpt::poses::CPose2D(motion)).asTPose();
		const auto p = matcher.alignPoints(map, points, {moved.x - shift.x, moved.y - shift.y, moved.phi}, &r.info);
		r.pose = {p.x + shift.x, p.y + shift.y, mrpt::math::wrapToPi(p.phi)};
		r.path.emplace_back(tag, r.pose);
	}
	// A new view for all when the leader has moved since its last one.
	const auto since = (mrpt::poses::CPose2D(m_rivals.front().pose) - mrpt::poses::CPose2D(m_rivals.front().lastView));
	if (std::hypot(since.x(), since.y()) >= m_options.viewLinear || std::abs(since.phi()) >= m_options.viewAngular)
		for (auto& r : m_rivals)
		{
			r.goodnessSum += r.info.goodness;
			++r.views;
			r.lastView = r.pose;
		}
	// A rival whose scans stopped fitting is not where the robot is; nor is the second of two that
	// have come together.
	std::vector<Rival> kept;
	for (const auto& r : m_rivals)
		if (r.mean() >= m_options.minGoodness && r.info.goodness >= m_options.minGoodness - 0.15 &&
			std::all_of(kept.begin(), kept.end(), [&](const Rival& k) { return distinct(k.pose, r.pose); }))
			kept.push_back(r);
	m_rivals = std::move(kept);
}

bool Rivals::decide()
{
	std::stable_sort(m_rivals.begin(), m_rivals.end(), [](const Rival& a, const Rival& b) { return a.mean() > b.mean(); });
	if (m_rivals.empty() || m_rivals[0].views < m_options.minViews ||
		m_rivals[0].mean() < m_options.minLeaderGoodness)
		return false;
	return m_rivals.size() == 1 ||
		   m_rivals[0].mean() - m_rivals[1].mean() >= m_options.decideMargin / std::sqrt(double(m_rivals[0].views));
}

}  // namespace pmslam
