/* pm-slam-app — the SLAM of one run: the front-end fed the log's events, and the trajectory it gives,
 * one pose per scan. */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/Trajectory.h>
#include <pmslam/slam/OdometrySelector.h>
#include <pmslam/slam/PerfectMatchSlam.h>
#include <pmslam/slam/SlamConfig.h>

#include <utility>
#include <vector>

namespace pmslam_app
{
using LoopLinks = std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>;

class SlamRun
{
   public:
	explicit SlamRun(const pmslam::SlamConfig& config);
	/** --localize: tracks on the fixed `map` from `initialPose`. Throws std::invalid_argument. */
	void localize(const mrpt::maps::COccupancyGridMap2D& map, const mrpt::math::TPose2D& initialPose);

	/** One event of the log: odometry goes to the SLAM (when [Log] odometrySource uses it); a scan is
	 * processed and its pose appended to trajectory(). Returns the scan's result, null for odometry. */
	const pmslam::PerfectMatchSlam::ScanResult* process(const pmslam::LogEvent& event);
	/** The end of the log: the last smoothed poses, then the final loop closure (which moves
	 * trajectory() to the final pose graph). `online` is set first: each pose as known when its scan was
	 * processed. Throws when the loop closure fails (trajectory() stays the online one). */
	void finish(pmslam::Trajectory& online);

	const pmslam::Trajectory& trajectory() const { return m_traj; }
	const pmslam::PerfectMatchSlam& slam() const { return m_slam; }
	/** Each pose of `t` moved with its keyframe to where the pose graph has it now (unchanged without
	 * loop closure). */
	pmslam::Trajectory corrected(const pmslam::Trajectory& t) const;
	/** The loop closures (empty without loop closure), for pictures. */
	LoopLinks loopLinks() const;

   private:
	/** The smoothed poses (odometrySmoothing) replace each scan's pose once final. */
	void applySmoothedPoses(bool finish);

	pmslam::PerfectMatchSlam m_slam;
	pmslam::OdometrySelector m_odometry;
	pmslam::Trajectory m_traj;
};

}  // namespace pmslam_app
