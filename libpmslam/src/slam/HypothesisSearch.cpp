/* pmslam — pose hypotheses for a scan (see HypothesisSearch.h). */
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <pmslam/match/BranchAndBoundSearch.h>
#include <pmslam/match/CorrelativeSearch.h>
#include <pmslam/match/LikelihoodPyramid.h>
#include <pmslam/slam/HypothesisSearch.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace pmslam
{
namespace
{
// Goodness below the best within which a re-localisation candidate is a rival: the margin a pose
// away from a trusted prediction must win by (HypothesisSearch::search).
constexpr double kRivalsWithin = 0.15;
// How much better than the match from the prediction a pose away from it must score (D12): in a
// look-alike place a somewhat better pose is as often the wrong one as the right one.
constexpr double kClearlyBetter = 0.15;
// D53: how much better than the window's answer after a gap a place elsewhere on the map must explain
// the scan to say that answer is wrong: twice a re-localisation's margin, for a place the motion
// model did not expect.
constexpr double kElsewhereBetter = 2 * kClearlyBetter;
}  // namespace

SearchWindow HypothesisSearch::window(const MotionPrediction& motion, bool lost, double lostFor) const
{
	SearchWindow w;
	w.stoppedAt = motion.extrapolated ? motion.previous : motion.pose;
	w.alternative = motion.alternative;
	w.linear = m_options.wideSearchLinear;
	w.angular = m_options.wideSearchAngular;
	if (lost)
	{
		// Matches rejected: the odometry may be what is wrong (a robot carried, a wheel slipping),
		// so the window grows with the time they have been rejected. Not with the time since the last
		// accepted one: across a drop-out or a gap that would open the whole circle and ±8 m at the
		// first rejection after it, where look-alikes win; the gap's own doubt is the odometry's
		// over it (below). (D16)
		w.linear += m_options.relocalizeSpeed * lostFor;
		w.angular += m_options.relocalizeTurnRate * lostFor;
	}
	if (motion.gap || motion.jump)
	{
		// A long step between two scans (no scan logged meanwhile): the prediction is as good as
		// the odometry over that step, off by a fraction of the distance and of the turn the robot
		// may have driven (over a gap more than the two readings' difference says).
		w.linear += m_options.relocalizeOdometryError * motion.travelled;
		w.angular += m_options.relocalizeOdometryError * motion.turned;
	}
	// A stale prediction (no odometry across a gap) is searched even when the match there looks
	// good, and, without odometry, until a search has decided where the robot is: the prediction
	// stays the stale one.
	w.alwaysSearch = motion.stale || (lost && !motion.odometry);
	w.afterGap = motion.gap;
	if (motion.stale)
	{
		w.linear += m_options.relocalizeSpeed * motion.sincePrevious;
		w.angular += m_options.relocalizeTurnRate * motion.sincePrevious;
	}
	w.linear = std::min(w.linear, m_options.relocalizeMaxLinear);
	w.angular = std::min(w.angular, M_PI);
	return w;
}

Hypothesis HypothesisSearch::search(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
									const std::vector<mrpt::math::TPoint2Df>& hits, const mrpt::math::TPose2D& predicted,
									const SearchWindow& window) const
{
	Hypothesis h;
	h.pose = matcher.alignPoints(map, hits, predicted, &h.info);
	if (window.alternative)
	{
		// Odometry that stood still and caught up: counted from where it stood still rather than from
		// the previous estimate where the scan clearly agrees (a stalled reading: the scans measured
		// that motion already; a robot carried while its wheels stood keeps the other).
		Hypothesis a;
		a.pose = matcher.alignPoints(map, hits, *window.alternative, &a.info);
		if (a.info.goodness > h.info.goodness + kClearlyBetter)
		{
			SearchWindow w = window;
			w.alternative.reset();
			Hypothesis best = search(matcher, map, hits, *window.alternative, w);
			best.fromAlternative = true;
			return best;
		}
		// Neither explains the scan: a reading that stood still through a long turn and caught up in
		// one step, whose own error over that turn (a tenth of it or more) leaves the alternative too
		// far off for a local match, while the prediction counts the turn twice. Each is searched in
		// the window, and the alternative wins where its search clearly does better.
		if (poor(h.info) && poor(a.info))
		{
			SearchWindow w = window;
			w.alternative.reset();
			const Hypothesis fromPrediction = search(matcher, map, hits, predicted, w);
			Hypothesis fromAlternative = search(matcher, map, hits, *window.alternative, w);
			if (!(fromAlternative.info.goodness > fromPrediction.info.goodness + kClearlyBetter)) return fromPrediction;
			fromAlternative.fromAlternative = true;
			return fromAlternative;
		}
	}
	// The cheap test: a match that explains the scan well needs no search, whatever came before
	// (after a gap, a jump or a rejection the window is only wider).
	const bool poor = this->poor(h.info);
	if ((!poor && !window.alwaysSearch) || (window.linear <= 0 && window.angular <= 0)) return h;
	h.wideSearch = true;

	const std::vector<CorrelativeSearch::Candidate> starts =
		CorrelativeSearch::coarseToFine(map, hits, predicted, window.linear, window.angular);
	// A pose away from the prediction must be clearly better than the match there, and explain
	// the scan as a normal match does: after a gap or in a look-alike place a mediocre candidate
	// is more often a wrong pose than a right one. A stale prediction (alwaysSearch) has no such
	// claim: the best explanation of the scan wins.
	const double margin = window.alwaysSearch ? 0.0 : kClearlyBetter;
	double bestGoodness = std::max(h.info.goodness + margin, m_options.wideSearchBelowGoodness);
	// A re-localisation window (wider than the wide basin's) holds look-alike places.
	const bool relocalizing = window.linear > m_options.wideSearchLinear + 1e-9 ||
							  window.angular > m_options.wideSearchAngular + 1e-9;
	std::vector<std::pair<mrpt::math::TPose2D, double>> refined;	 // every candidate, refined, and its score
	std::vector<PerfectMatchMatcher::MatchInfo> infos;	// and its match
	const Hypothesis atPrediction = h;
	for (const auto& c : starts)
	{
		PerfectMatchMatcher::MatchInfo info;
		const mrpt::math::TPose2D p = matcher.alignPoints(map, hits, c.pose, &info);
		refined.emplace_back(p, info.goodness);
		infos.push_back(info);
		if (info.goodness > bestGoodness)
		{
			bestGoodness = info.goodness;
			h.pose = p;
			h.info = info;
			h.relocalized = true;
		}
	}
	// A stale prediction's re-localisation (a lidar alone after a gap) is where look-alikes fool one
	// scan: every candidate nearly as good as the best, the prediction's own match among them, goes
	// to the next scans, which decide; the motion prior weighs in from the start.
	decltype(h.rivals) rivals;
	if (relocalizing && window.alwaysSearch)
	{
		refined.emplace_back(atPrediction.pose, atPrediction.info.goodness);
		infos.push_back(atPrediction.info);
		for (std::size_t i = 0; i < refined.size(); ++i)
			if (refined[i].second >= bestGoodness - kRivalsWithin)
				rivals.push_back({refined[i].first, infos[i], prior(refined[i].first, predicted, window)});
	}
	// In a re-localisation window, a clearly different pose that explains the scan nearly as well
	// (a look-alike room, a repetitive corridor) leaves the pose undecided: keep searching on the
	// next scans, from where the robot moves to somewhere that tells them apart.
	if (h.relocalized && relocalizing && m_options.relocalizeAmbiguity > 0 && lookAlike(refined, h.pose, bestGoodness))
	{
		h = atPrediction;
		// A stale prediction is no fallback: where a lidar alone was before a gap it is not now.
		h.undecided = window.alwaysSearch;
	}
	// D53: after a gap, a poor answer the window could not improve on may be a wrong pose that fits a
	// little of the scan (the robot carried beyond the window): where a place elsewhere on the map
	// explains the scan clearly better, nothing is decided, and the scans choose between those places.
	if (window.afterGap && rivals.empty() && h.info.goodness < m_options.minGoodness)
	{
		rivals = clearlyBetterElsewhere(matcher, map, hits, h, predicted, window);
		h.undecided = !rivals.empty();
	}
	h.rivals = std::move(rivals);
	return h;
}

std::vector<Candidate> HypothesisSearch::clearlyBetterElsewhere(const PerfectMatchMatcher& matcher,
																const DynamicDistanceMap& map,
																const std::vector<mrpt::math::TPoint2Df>& hits,
																const Hypothesis& h, const mrpt::math::TPose2D& predicted,
																const SearchWindow& window) const
{
	// The whole map's best places (branch and bound, coarse to fine, as the back-end searches a
	// stretch lost beyond its window: D46), refined by PM.
	const LikelihoodPyramid fine(map);
	const BranchAndBoundSearch search(fine, BranchAndBoundSearch::Options::wholeMap(8, 0.7));
	const LikelihoodPyramid coarse = search.coarsePyramid();
	const double needed = std::max(m_options.wideSearchBelowGoodness, h.info.goodness + kElsewhereBetter);
	std::vector<Candidate> better;
	for (const auto& c : search.searchGlobalCoarseToFine(hits, coarse).candidates)
	{
		PerfectMatchMatcher::MatchInfo info;
		const mrpt::math::TPose2D p = matcher.alignPoints(map, hits, c.pose, &info);
		if (info.goodness >= needed) better.push_back({p, info, prior(p, predicted, window)});
	}
	return better;
}

double HypothesisSearch::prior(const mrpt::math::TPose2D& pose, const mrpt::math::TPose2D& predicted,
							   const SearchWindow& window)
{
	// The nearest point of the stretch from stoppedAt to the prediction (a robot that stopped
	// somewhere on the way, or drove on), with the heading it had there.
	const mrpt::math::TPose2D& a = window.stoppedAt;
	const double ex = predicted.x - a.x, ey = predicted.y - a.y, len2 = ex * ex + ey * ey;
	const double f = len2 > 1e-12 ? std::clamp(((pose.x - a.x) * ex + (pose.y - a.y) * ey) / len2, 0.0, 1.0) : 1.0;
	const double nx = a.x + f * ex, ny = a.y + f * ey;
	const double nphi = a.phi + f * mrpt::math::wrapToPi(predicted.phi - a.phi);
	const double sl = std::max(window.linear, 1e-3) / 2, sa = std::max(window.angular, 1e-3) / 2;
	const double dl = std::hypot(pose.x - nx, pose.y - ny) / sl;
	const double da = mrpt::math::wrapToPi(pose.phi - nphi) / sa;
	return std::exp(-0.5 * (dl * dl + da * da));
}

bool HypothesisSearch::lookAlike(const std::vector<std::pair<mrpt::math::TPose2D, double>>& refined,
								 const mrpt::math::TPose2D& best, double bestGoodness) const
{
	for (const auto& [p, g] : refined)
	{
		const bool distinct = std::hypot(p.x - best.x, p.y - best.y) > 0.5 ||
							  std::abs(mrpt::math::wrapToPi(p.phi - best.phi)) > mrpt::DEG2RAD(5.0);
		if (distinct && g > bestGoodness - m_options.relocalizeAmbiguity) return true;
	}
	return false;
}

}  // namespace pmslam
