/* pmslam — the front-end's tracking state (see Tracker.h). */
#include <pmslam/slam/Tracker.h>

namespace pmslam
{
double Tracker::lostFor(double now) const
{
	if (m_gaps.empty() || !m_gaps.back().open) return 0.0;
	TrackingGap g = m_gaps.back();
	g.to = std::max(g.to, now);
	return g.length();
}

bool Tracker::acceptable(const PerfectMatchMatcher::MatchInfo& info, bool afterGap) const
{
	// D56: after a logging gap the prediction itself is in doubt, and a pose that explains a part of
	// the scan (D7's share) may be a wrong one that the map contradicts everywhere else. There a match
	// is taken only where the part of the scan that overlaps the map agrees with it (D13's test); the
	// rest of the scan may still be new ground.
	if (afterGap && info.inlierGoodness < m_options.minOverlapGoodness) return false;
	if (info.goodness >= m_options.minGoodness) return true;
	// Mostly new ground: trust the part that overlaps the map, if there is enough of it.
	return m_options.minOverlapGoodness > 0 && info.inlierGoodness >= m_options.minOverlapGoodness &&
		   info.inlierFraction * info.nPoints >= m_options.minPoints;
}

TrackingState Tracker::judge(const PerfectMatchMatcher::MatchInfo& info, bool undecided, bool afterGap, double now,
							 const std::function<double()>& unexploredFraction) const
{
	if (!undecided && acceptable(info, afterGap)) return TrackingState::Tracking;
	// Lost for a while and the scan lies in space no scan has observed yet, at the prediction:
	// the robot is on new ground (after a gap it drove somewhere never mapped). Nothing can be
	// matched, so the scan goes in at the odometry pose and the map grows from there on. A scan
	// over mapped space that does not match (the prediction is off) keeps being rejected instead
	// of corrupting the map.
	if (m_options.newGroundUnexplored > 0 && (m_atKnownStart || lostFor(now) >= m_options.newGroundAfter) &&
		unexploredFraction() >= m_options.newGroundUnexplored)
		return TrackingState::NewGround;
	return undecided ? TrackingState::Ambiguous : TrackingState::Lost;
}

Tracker::KeyframeEvidence Tracker::keyframeEvidence(bool matched, bool relocalized, bool first) const
{
	return {(matched || first) && m_trackedSinceKeyframe, m_searchedSinceKeyframe || (matched && relocalized)};
}

void Tracker::update(const std::optional<TrackingState>& verdict, bool relocalized, bool keyframe, double now)
{
	const bool matched = verdict == TrackingState::Tracking;
	// A keyframe starts the back-end's record afresh; a match placed by a re-localisation since
	// makes the next keyframe's pose a hypothesis for it.
	if (keyframe)
	{
		m_trackedSinceKeyframe = true;
		m_searchedSinceKeyframe = false;
	}
	else if (matched && relocalized)
		m_searchedSinceKeyframe = true;
	if (!verdict) return;
	m_atKnownStart = false;
	m_state = *verdict;
	// A rejected match opens (or extends) a gap, an accepted one closes it.
	if (!matched)
	{
		m_trackedSinceKeyframe = false;
		if (m_gaps.empty() || !m_gaps.back().open) m_gaps.push_back({now, now, 0, true});
		m_gaps.back().to = now;
		++m_gaps.back().scans;
	}
	else
	{
		if (!m_gaps.empty() && m_gaps.back().open)
		{
			m_gaps.back().to = now;
			m_gaps.back().open = false;
		}
	}
}

}  // namespace pmslam
