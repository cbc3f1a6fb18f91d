/* pm-slam-app — the SLAM of one run: the front-end fed the log's events, and the trajectory it gives,
 * one pose per scan. */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/Trajectory.h>
#include <pmslam/slam/GlobalLocalizer.h>
#include <pmslam/slam/OdometrySelector.h>
#include <pmslam/slam/PerfectMatchSlam.h>
#include <pmslam/slam/Session.h>
#include <pmslam/slam/SlamConfig.h>

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

namespace pmslam_app
{
using LoopLinks = std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>;

class SlamRun
{
   public:
	explicit SlamRun(const pmslam::SlamConfig& config);
	/** --localize: tracks on the fixed `map` from `initialPose`. With `checkStart` (a start pose the user gave)
	 * the first scans are also searched over the whole map, and a place they decide for elsewhere moves the
	 * robot there (D47). Throws std::invalid_argument. */
	void localize(const mrpt::maps::COccupancyGridMap2D& map, const mrpt::math::TPose2D& initialPose,
				  bool checkStart = false);
	/** --localize without --initial-pose: the start is searched on `map` (GlobalLocalizer) from the
	 * first scans, which offerForStart() takes until it is found. */
	void findStart(const mrpt::maps::COccupancyGridMap2D& map);
	/** The same for --continue: the log may begin off the map and come onto it later (a wing mapped
	 * apart, a second robot's session), so it is searched along (GlobalLocalizerOptions::searchAlong). */
	void findStartAlong(const mrpt::maps::COccupancyGridMap2D& map);
	/** --continue: maps on from `session`'s map (never changed), starting at `hint` or, without one, where a
	 * whole-map search on it finds the log (findStartAlong()). `session` must outlive the run. */
	void continueSession(const pmslam::Session& session, const std::optional<mrpt::math::TPose2D>& hint);
	/** The session continued, if any. */
	const pmslam::Session* session() const { return m_session; }
	/** Its trajectory (every earlier part), each pose moved with its keyframe as the graph of both
	 * sessions moved it (final after finish()); empty without a session. */
	pmslam::Trajectory earlierSessions() const;
	/** --lifelong: at finish(), earlier keyframes this run covers are retired (PerfectMatchSlam::retireCoveredKeyframes). */
	void setLifelong(bool on) { m_lifelong = on; }
	/** The continued session's parts, their keyframe counts less those retired (empty without a session). */
	std::vector<pmslam::SessionPart> earlierParts() const;
	/** Earlier keyframes retired at finish(). */
	std::size_t retiredKeyframes() const { return std::size_t(std::count(m_retired.begin(), m_retired.end(), true)); }
	bool findingStart() const { return m_start && m_start->state() == pmslam::GlobalLocalizer::State::Searching; }
	/** One event while findingStart(): true when it decided the start, and the tracker now starts
	 * there (the events offered so far are to be processed again, from the first). */
	bool offerForStart(const pmslam::LogEvent& event);
	bool startUndecided() const { return m_start && m_start->state() == pmslam::GlobalLocalizer::State::Undecided; }
	/** While localising: whole-map searches started because tracking was lost, and the places they
	 * moved the robot to (scan time, pose). */
	std::size_t searchesWhenLost() const { return m_searchesWhenLost; }
	const std::vector<std::pair<double, mrpt::math::TPose2D>>& foundAgain() const { return m_foundAgain; }
	/** The search for the start, if there was one (its state says how it ended). */
	const pmslam::GlobalLocalizer* startSearch() const { return m_start.get(); }

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
	/** The continued session's keyframes in the map, the robot at `start`. */
	void startSession(const mrpt::math::TPose2D& start);
	/** Localising: a whole-map search once tracking was lost long enough, or from this scan on with
	 * `check` (a given start, a re-localisation) (D47). */
	void searchWhenLost(const pmslam::LogEvent& ev, const std::optional<mrpt::math::TPose2D>& odometry, bool check);
	void placeWhereFound(double now);
	/** The smoothed poses (odometrySmoothing) replace each scan's pose once final. */
	void applySmoothedPoses(bool finish);

	pmslam::PerfectMatchSlam m_slam;
	pmslam::OdometrySelector m_odometry;
	pmslam::Trajectory m_traj;
	std::unique_ptr<pmslam::GlobalLocalizer> m_start;
	const mrpt::maps::COccupancyGridMap2D* m_startMap = nullptr;
	pmslam::OdometrySelector m_startOdometry;  // its own: the events are offered again to m_odometry after
	// --continue without a start: the log may begin off the map, so the search goes along it, and places
	// found far into it are carried back to its first scan by a front-end of its own (the scans' motion,
	// not the wheels' drift).
	std::unique_ptr<pmslam::PerfectMatchSlam> m_startTracker;
	pmslam::OdometrySelector m_startTrackerOdometry;
	const mrpt::maps::COccupancyGridMap2D* m_prior = nullptr;  // the fixed map, while localising
	bool m_checkStart = false;	// the next scan starts a whole-map search that checks the given start
	const pmslam::Session* m_session = nullptr;	 // the session continued
	bool m_lifelong = false;
	std::vector<bool> m_retired;  // per earlier keyframe (--lifelong)
	std::unique_ptr<pmslam::GlobalLocalizer> m_research;	// the search for a robot lost while localising
	// The scans since tracking was lost (with their odometry), the first m_offered of them given to m_research.
	std::vector<std::pair<pmslam::LogEvent, std::optional<mrpt::math::TPose2D>>> m_lost;
	std::size_t m_offered = 0;
	std::size_t m_placedFrom = 0, m_placedTo = 0;	// trajectory indices the last placement revised
	std::size_t m_searchesWhenLost = 0;
	std::vector<std::pair<double, mrpt::math::TPose2D>> m_foundAgain;
};

}  // namespace pmslam_app
