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
				 const PerfectMatchMatcher::MatchInfo& info, std::size_t tag, double prior)
{
	if (std::any_of(m_rivals.begin(), m_rivals.end(), [&](const Rival& r) { return !distinct(r.pose, pose); })) return;
	Rival r;
	r.pose = r.lastView = pose;
	r.origin = origin;
	r.info = info;
	r.goodnessSum = info.goodness;
	r.inlierGoodnessSum = info.inlierGoodness;
	r.views = 1;
	r.prior = prior;
	r.path.emplace_back(tag, pose);
	if (m_rivals.empty()) m_sinceView = mrpt::poses::CPose2D();
	m_rivals.push_back(r);
}

void Rivals::follow(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
					const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& motion,
					const mrpt::math::TPoint2D& shift, std::size_t tag)
{
	if (m_rivals.empty()) return;
	// Each is matched with the motion as a prior (likelihood × motion prior): where the scan leaves a
	// direction open (along a corridor) the rival keeps to the motion instead of sliding.
	const double step = std::hypot(motion.x, motion.y);
	const double sl = m_options.motionNoiseLinear + m_options.motionNoiseShare * step;
	const double sa = m_options.motionNoiseAngular + m_options.motionNoiseShare * std::abs(motion.phi);
	for (auto& r : m_rivals)
	{
		const auto moved = (mrpt::poses::CPose2D(r.pose) + mrpt::poses::CPose2D(motion)).asTPose();
		const mrpt::math::TPose2D start{moved.x - shift.x, moved.y - shift.y, moved.phi};
		const auto prior = PerfectMatchMatcher::PosePrior::diagonal(start, sl, sa);
		const auto p = matcher.alignPoints(map, points, start, &r.info, nullptr,
										   m_options.motionNoiseShare > 0 ? &prior : nullptr);
		r.pose = {p.x + shift.x, p.y + shift.y, mrpt::math::wrapToPi(p.phi)};
		r.path.emplace_back(tag, r.pose);
	}
	// A new view for all once the robot has moved (by `motion`) since the last one. A rival's view
	// counts its goodness weighted by how well its own motion since its last view agrees with the
	// robot's: a look-alike that the matches pull back to one spot while the robot drives on is not
	// where the robot is, however well that spot fits each scan.
	m_sinceView = m_sinceView + mrpt::poses::CPose2D(motion);
	if (std::hypot(m_sinceView.x(), m_sinceView.y()) >= m_options.viewLinear ||
		std::abs(m_sinceView.phi()) >= m_options.viewAngular)
	{
		for (auto& r : m_rivals)
		{
			const double agreement = motionAgreement(r);
			r.goodnessSum += r.info.goodness * agreement;
			r.inlierGoodnessSum += r.info.inlierGoodness * agreement;
			++r.views;
			r.lastView = r.pose;
		}
		m_sinceView = mrpt::poses::CPose2D();
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

double Rivals::motionAgreement(const Rival& r) const
{
	if (m_options.motionNoiseShare <= 0) return 1.0;
	const mrpt::poses::CPose2D own = mrpt::poses::CPose2D(r.pose) - mrpt::poses::CPose2D(r.lastView);
	const double moved = std::hypot(m_sinceView.x(), m_sinceView.y());
	const double turn = std::abs(m_sinceView.phi());
	const double sl = m_options.motionNoiseLinear + m_options.motionNoiseShare * moved + m_options.motionNoisePerTurn * turn;
	const double sa = m_options.motionNoiseAngular + m_options.motionNoiseShare * turn;
	const double el = std::hypot(own.x() - m_sinceView.x(), own.y() - m_sinceView.y()) / sl;
	const double ea = mrpt::math::wrapToPi(own.phi() - m_sinceView.phi()) / sa;
	return std::exp(-0.5 * (el * el + ea * ea));
}

bool Rivals::decide()
{
	std::stable_sort(m_rivals.begin(), m_rivals.end(), [](const Rival& a, const Rival& b) { return a.score() > b.score(); });
	if (m_rivals.empty() || m_rivals[0].views < m_options.minViews ||
		m_rivals[0].inlierMean() < m_options.minLeaderGoodness)
		return false;
	return m_rivals.size() == 1 ||
		   m_rivals[0].score() - m_rivals[1].score() >= m_options.decideMargin / std::sqrt(double(m_rivals[0].views));
}

}  // namespace pmslam
