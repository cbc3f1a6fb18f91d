/* pm-slam-app — the SLAM of one run (see SlamRun.h). */
#include "SlamRun.h"

namespace pmslam_app
{
SlamRun::SlamRun(const pmslam::SlamConfig& cfg) : m_odometry(cfg.odometrySource), m_startOdometry(cfg.odometrySource)
{
	m_slam.PM_options = cfg.mapping;
	m_slam.PM_params = cfg.matcher;
	m_slam.LC_options = cfg.loopClosure;
	m_slam.initialize();
}

void SlamRun::localize(const mrpt::maps::COccupancyGridMap2D& map, const mrpt::math::TPose2D& initialPose)
{
	m_slam.initializeWithFixedMap(map, initialPose);
}

void SlamRun::findStart(const mrpt::maps::COccupancyGridMap2D& map)
{
	m_start = std::make_unique<pmslam::GlobalLocalizer>(map, m_slam.PM_params, m_slam.PM_options.grid.scan);
	m_startMap = &map;
}

bool SlamRun::offerForStart(const pmslam::LogEvent& ev)
{
	if (ev.kind == pmslam::LogEvent::Kind::Odometry)
	{
		m_startOdometry.takeReading(ev);
		return false;
	}
	if (m_start->addScan(*ev.scan, m_startOdometry.forScan(ev)) != pmslam::GlobalLocalizer::State::Found) return false;
	localize(*m_startMap, m_start->best()->origin);
	return true;
}

const pmslam::PerfectMatchSlam::ScanResult* SlamRun::process(const pmslam::LogEvent& ev)
{
	if (ev.kind == pmslam::LogEvent::Kind::Odometry)
	{
		if (m_odometry.takeReading(ev)) m_slam.processOdometry(ev.odometry, ev.timestamp);
		return nullptr;
	}
	const auto& r = m_slam.processScan(*ev.scan, m_odometry.scanOdometry(ev));
	m_traj.push_back({ev.timestamp, r.pose.x, r.pose.y, r.pose.phi});
	applySmoothedPoses(false);
	return &r;
}

void SlamRun::applySmoothedPoses(bool finish)
{
	for (const auto& [i, p] : m_slam.takeSmoothedPoses(finish))
		if (i < m_traj.size()) m_traj[i].x = p.x, m_traj[i].y = p.y, m_traj[i].yaw = p.phi;
}

void SlamRun::finish(pmslam::Trajectory& online)
{
	applySmoothedPoses(true);  // the last scans' poses wait for a look-ahead that will not come
	online = m_traj;
	m_slam.finishLoopClosure();
	m_traj = corrected(m_traj);
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
