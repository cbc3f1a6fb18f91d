/* pm-slam-app — the SLAM of one run (see SlamRun.h). */
#include "SlamRun.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <utility>

namespace pmslam_app
{
SlamRun::SlamRun(const pmslam::SlamConfig& cfg)
	: m_odometry(cfg.odometrySource), m_startOdometry(cfg.odometrySource), m_startTrackerOdometry(cfg.odometrySource)
{
	m_slam.PM_options = cfg.mapping;
	m_slam.PM_params = cfg.matcher;
	m_slam.LC_options = cfg.loopClosure;
	m_slam.initialize();
}

namespace
{
// Seconds of log without an accepted match after which a robot localising on a fixed map is
// searched for on the whole map (D47): a gap of the length that makes the tracker's own window
// search re-localise (relocalizeAfterGap's default) did not find it.
constexpr double kSearchWhenLostAfter = 2.0;
}  // namespace

void SlamRun::localize(const mrpt::maps::COccupancyGridMap2D& map, const mrpt::math::TPose2D& initialPose,
					   bool checkStart)
{
	m_slam.initializeWithFixedMap(map, initialPose);
	m_prior = &map;
	m_checkStart = checkStart;
}

void SlamRun::findStart(const mrpt::maps::COccupancyGridMap2D& map)
{
	m_start = std::make_unique<pmslam::GlobalLocalizer>(map, m_slam.PM_params, m_slam.PM_options.grid.scan);
	m_startMap = &map;
}

void SlamRun::findStartAlong(const mrpt::maps::COccupancyGridMap2D& map)
{
	pmslam::GlobalLocalizerOptions o;
	o.searchAlong = true;
	m_start = std::make_unique<pmslam::GlobalLocalizer>(map, m_slam.PM_params, m_slam.PM_options.grid.scan, o);
	m_startMap = &map;
	m_startTracker = std::make_unique<pmslam::PerfectMatchSlam>();
	m_startTracker->PM_options = m_slam.PM_options;
	m_startTracker->PM_options.keepSimpleMap = false;
	m_startTracker->PM_params = m_slam.PM_params;
	m_startTracker->LC_options.enabled = false;
	m_startTracker->initialize();
}

bool SlamRun::offerForStart(const pmslam::LogEvent& ev)
{
	if (ev.kind == pmslam::LogEvent::Kind::Odometry)
	{
		m_startOdometry.takeReading(ev);
		if (m_startTracker && m_startTrackerOdometry.takeReading(ev))
			m_startTracker->processOdometry(ev.odometry, ev.timestamp);
		return false;
	}
	auto odometry = m_startOdometry.forScan(ev);
	if (m_startTracker) odometry = m_startTracker->processScan(*ev.scan, m_startTrackerOdometry.scanOdometry(ev)).pose;
	if (m_start->addScan(*ev.scan, odometry) != pmslam::GlobalLocalizer::State::Found) return false;
	m_startTracker.reset();
	if (m_session)
		startSession(m_start->best()->origin);
	else
		localize(*m_startMap, m_start->best()->origin);
	return true;
}

void SlamRun::continueSession(const pmslam::Session& session, const std::optional<mrpt::math::TPose2D>& hint)
{
	m_session = &session;
	if (hint)
		startSession(*hint);
	else
		findStartAlong(session.grid);
}

void SlamRun::startSession(const mrpt::math::TPose2D& start)
{
	m_slam.continueSession(m_session->keyframes, m_session->graph ? &*m_session->graph : nullptr, start);
}

pmslam::Trajectory SlamRun::earlierSessions() const
{
	// Each part's poses moved with the keyframes of that part, as the joint graph moved them.
	if (!m_session) return {};
	pmslam::Trajectory out = m_session->trajectory;
	std::size_t line = 0, keyframe = 0;
	for (const auto& part : m_session->parts)
	{
		std::vector<mrpt::math::TPose2D> poses;
		std::vector<double> times;
		for (std::size_t i = line; i < line + part.scans; ++i)
			poses.emplace_back(out[i].x, out[i].y, out[i].yaw), times.push_back(out[i].timestamp);
		poses = m_slam.correctedPriorPoses(poses, times, keyframe, part.keyframes);
		for (std::size_t i = 0; i < poses.size(); ++i)
			out[line + i].x = poses[i].x, out[line + i].y = poses[i].y, out[line + i].yaw = poses[i].phi;
		line += part.scans;
		keyframe += part.keyframes;
	}
	return out;
}

const pmslam::PerfectMatchSlam::ScanResult* SlamRun::process(const pmslam::LogEvent& ev)
{
	if (ev.kind == pmslam::LogEvent::Kind::Odometry)
	{
		if (m_odometry.takeReading(ev)) m_slam.processOdometry(ev.odometry, ev.timestamp);
		return nullptr;
	}
	const auto odometry = m_odometry.scanOdometry(ev);
	const auto& r = m_slam.processScan(*ev.scan, odometry);
	m_traj.push_back({ev.timestamp, r.pose.x, r.pose.y, r.pose.phi});
	const bool startCheck = std::exchange(m_checkStart, false);	 // the first scan, whatever the tracker did
	if (m_prior) searchWhenLost(ev, m_odometry.forScan(ev), r.relocalized || startCheck);
	applySmoothedPoses(false);
	return &r;
}

void SlamRun::searchWhenLost(const pmslam::LogEvent& ev, const std::optional<mrpt::math::TPose2D>& odometry,
							 bool check)
{
	// A robot lost on a fixed map is searched for as its start was: the whole map, then the scans
	// decide between the places found, from the first scan of the loss on (so that the place found
	// can revise every scan reported while lost). The tracker goes on meanwhile; a place found
	// where the tracker already is changes nothing. A given start pose and a re-localisation by the
	// tracker's own window search are places taken on one view, from the user's word or near the
	// prediction (a look-alike as often as not from a wrong start pose): each is checked the same
	// way, from that scan on (D47): `check`.
	if (!m_research && !m_slam.lost() && !check)
	{
		m_lost.clear();
		return;
	}
	if (check && !m_research) m_lost.clear();
	m_lost.push_back({ev, odometry});
	if (!m_research)
	{
		if (!check && m_slam.untrackedFor(ev.timestamp) < kSearchWhenLostAfter) return;
		m_research = std::make_unique<pmslam::GlobalLocalizer>(*m_prior, m_slam.PM_params, m_slam.PM_options.grid.scan);
		m_offered = 0;
		++m_searchesWhenLost;
	}
	auto state = m_research->state();
	for (; m_offered < m_lost.size() && state == pmslam::GlobalLocalizer::State::Searching; ++m_offered)
		state = m_research->addScan(*m_lost[m_offered].first.scan, m_lost[m_offered].second);
	if (state == pmslam::GlobalLocalizer::State::Searching) return;
	if (state == pmslam::GlobalLocalizer::State::Found) placeWhereFound(ev.timestamp);
	m_research.reset();	 // undecided: searched anew while still lost
	m_lost.clear();
}

void SlamRun::placeWhereFound(double now)
{
	// The scans the search took, placed as the winner has them: from where it had the first one,
	// by the odometry since; without odometry only the scan it decided at, where it had it.
	const auto& first = m_lost.front().second;
	std::vector<mrpt::math::TPose2D> poses;
	for (const auto& [ev, odo] : m_lost)
		if (first && odo)
			poses.push_back((mrpt::poses::CPose2D(m_research->best()->origin) +
							 (mrpt::poses::CPose2D(*odo) - mrpt::poses::CPose2D(*first)))
								.asTPose());
	if (poses.size() != m_lost.size()) poses.assign(1, m_research->best()->pose);
	const auto p = poses.back();
	const auto here = m_slam.currentPose();
	if (std::hypot(p.x - here.x, p.y - here.y) <= 0.3 && std::abs(mrpt::math::wrapToPi(p.phi - here.phi)) <= 0.09)
		return;
	m_slam.placeAt(p);
	m_placedFrom = m_traj.size() - poses.size();
	m_placedTo = m_traj.size();
	for (std::size_t k = 0; k < poses.size(); ++k)
	{
		auto& t = m_traj[m_traj.size() - poses.size() + k];
		t.x = poses[k].x, t.y = poses[k].y, t.yaw = poses[k].phi;
	}
	m_foundAgain.push_back({now, p});
}

void SlamRun::applySmoothedPoses(bool finish)
{
	for (const auto& [i, p] : m_slam.takeSmoothedPoses(finish))
		if (i < m_traj.size() && !(i >= m_placedFrom && i < m_placedTo))  // a global search's placement stays
			m_traj[i].x = p.x, m_traj[i].y = p.y, m_traj[i].yaw = p.phi;
}

void SlamRun::finish(pmslam::Trajectory& online)
{
	applySmoothedPoses(true);  // the last scans' poses wait for a look-ahead that will not come
	online = m_traj;
	m_slam.finishLoopClosure();
	m_traj = corrected(m_traj);
	// --lifelong: earlier keyframes this run covers (0.5 m, 30 degrees: the same view) give way to its own.
	if (m_lifelong && m_session) m_retired = m_slam.retireCoveredKeyframes(0.5, mrpt::DEG2RAD(30.0));
}

std::vector<pmslam::SessionPart> SlamRun::earlierParts() const
{
	// The continued session's parts, each counting the keyframes it keeps.
	if (!m_session) return {};
	std::vector<pmslam::SessionPart> parts = m_session->parts;
	std::size_t first = 0;
	for (auto& part : parts)
	{
		const std::size_t end = first + part.keyframes;
		for (std::size_t i = first; i < end && i < m_retired.size(); ++i) part.keyframes -= m_retired[i];
		first = end;
	}
	return parts;
}

pmslam::Trajectory SlamRun::corrected(const pmslam::Trajectory& t) const
{
	if (!m_slam.loopClosure()) return t;
	std::vector<mrpt::math::TPose2D> poses;
	poses.reserve(t.size());
	for (const auto& p : t) poses.emplace_back(p.x, p.y, p.yaw);
	poses = m_slam.correctedTrajectory(poses);
	pmslam::Trajectory out = t;
	for (std::size_t i = 0; i < out.size(); ++i) out[i].x = poses[i].x, out[i].y = poses[i].y, out[i].yaw = poses[i].phi;
	return out;
}

LoopLinks SlamRun::loopLinks() const { return m_slam.loopClosure() ? m_slam.loopClosure()->loopLinks() : LoopLinks(); }

}  // namespace pmslam_app
