/* pmslam — odometry as a measurement: the front-end's motion model.
 *
 * Odometry reaches the front-end in three ways: readings (processOdometry(), timed
 * or not), increments (MRPT actions) and a scan's own reading (Carmen FLASER lines).
 * This part turns them into the prediction of each scan's pose: the previous
 * scan's estimate moved by the odometry increment since that scan. It also says
 * how far the prediction can be trusted, for the search window of the match:
 * - a glitch: an increment no robot can make (a reset, a corrupt reading) is
 *   ignored, and the prediction is the previous estimate;
 * - a gap: a long time between two scans (scans missing, nothing logged);
 * - a jump: a long odometry step between two scans;
 * - a stale prediction: a gap without any odometry (a lidar alone), across which
 *   the robot went anywhere it could drive.
 * Without odometry (a lidar alone) the motion is the robot's own recent velocity,
 * measured by its accepted matches (matched()): the prediction is the previous
 * estimate moved at that velocity, for at most kMaxExtrapolation s since the last
 * match (a robot keeps going; it does not keep going for ever). Across a gap that
 * is where a robot that drove on would be; the search window around it also holds
 * where one that stopped would be.
 * Odometry is a measurement of the motion between its own readings: after a reading
 * that stood still while the scans moved the robot, the next one is also offered
 * counted from where it stood still (MotionPrediction::alternative), and the
 * match decides.
 * For the reported trajectory's smoother it moves a copied reading to the scan's
 * time (odometryToScanTime); the prediction keeps the reading as it is.
 *
 * Why a part of its own: every question about odometry (its source, its timing,
 * its glitches, its gaps) is answered here once; the rest of the front-end reads
 * a MotionPrediction.
 */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <cstddef>
#include <deque>
#include <optional>
#include <utility>

namespace pmslam
{
/** The MapBuilderOptions fields of the same names (see there for their defaults and why);
 * PerfectMatchSlam fills them. */
struct MotionModelOptions
{
	bool odometryToScanTime = false;
	double scanLatency = 0;	 ///< s
	double relocalizeAfterGap = 0;	///< s between two scans: longer is a gap
	double relocalizeAfterJump = 0;	 ///< m of odometry between two scans: longer is a jump
};

/** A scan's predicted pose and what is known of the motion since the previous scan. */
struct MotionPrediction
{
	mrpt::math::TPose2D pose;  ///< the previous estimate moved by the odometry increment, or velocity (map frame)
	std::optional<mrpt::math::TPose2D> odometry;  ///< the reading the prediction used (none: no odometry)
	std::optional<mrpt::math::TPose2D> odometryAtScanTime;	///< the same moved to the scan's time, for the smoother
	double time = std::nan("");	 ///< the scan's timestamp (s; NaN: unknown)
	double sincePrevious = std::nan("");  ///< s since the previous timed scan (NaN: unknown)
	double step = 0, turn = 0;	///< odometry's distance (m) and turn (rad) since the previous scan
	/** How far (m) and how much (rad) the robot may have driven and turned since the previous scan:
	 * the odometry's step and turn, and across a gap at least what the robot's own mean speed and turn
	 * rate so far cover in that time (the path between two readings a gap apart is unknown; their
	 * difference is only its least). The odometry's error grows with these, not with the difference. */
	double travelled = 0, turned = 0;
	bool glitch = false;  ///< the odometry step was implausible and is ignored
	bool gap = false;  ///< more than relocalizeAfterGap since the previous scan
	bool jump = false;	///< odometry stepped more than relocalizeAfterJump
	bool stale = false;	 ///< a gap without any odometry: the robot may have driven on, stopped, or turned
	bool extrapolated = false;	///< no odometry: moved at the velocity of the recent matches
	/** The previous estimate, unmoved: where an extrapolated robot would be had it stopped. */
	mrpt::math::TPose2D previous;
	/** The first reading after odometry stood still while the scans moved the robot: that reading's
	 * increment measures the motion since it stood still, which the scans may have measured already
	 * (a stalled reading catching up) or not (a robot carried while its wheels stood). `pose` counts it
	 * from the previous estimate; this, from the estimate where the reading stood still. */
	std::optional<mrpt::math::TPose2D> alternative;
};

class MotionModel
{
   public:
	explicit MotionModel(const MotionModelOptions& options) : m_options(options) {}

	/** The latest odometry reading of the robot base (any frame; only increments are used), with
	 * its time (s; NaN = unknown). */
	void addReading(const mrpt::math::TPose2D& odometry, double timestamp);
	/** An odometry increment (an MRPT action), accumulated into a reading. */
	void addIncrement(const mrpt::poses::CPose2D& change);
	/** The prediction for a scan stamped `stamp` (INVALID_TIMESTAMP: unknown) from `estimate`, the
	 * previous scan's pose; `odometryAtScan`: the scan's own reading, which takes precedence over
	 * addReading()'s. Moves the model on to this scan. */
	MotionPrediction predict(const mrpt::Clock::time_point& stamp,
							 const std::optional<mrpt::math::TPose2D>& odometryAtScan,
							 const mrpt::math::TPose2D& estimate);
	/** An accepted match at `pose` (map frame) of the scan stamped `time` (s): the velocity a lidar
	 * alone is predicted with. */
	void matched(const mrpt::math::TPose2D& pose, double time);
	/** The map frame moved by `T` (a loop closure's correction): so do the recent matches and the anchor. */
	void correct(const mrpt::poses::CPose2D& T);

   private:
	MotionModelOptions m_options;
	std::optional<mrpt::math::TPose2D> m_odometry;	// latest reading
	// The last two timed readings (time s, pose), oldest first, for odometryToScanTime.
	std::optional<std::pair<double, mrpt::math::TPose2D>> m_timedOdometry[2];
	std::size_t m_timedReadings = 0, m_burstReadings = 0;
	std::optional<mrpt::math::TPose2D> m_odometryAtLastScan;
	// The estimate of the scan at which the current reading was first seen, and that reading (the
	// anchor of a reading that stands still); pending: seen at the last scan, whose estimate comes next.
	std::optional<std::pair<mrpt::math::TPose2D, mrpt::math::TPose2D>> m_anchor;
	std::optional<mrpt::math::TPose2D> m_anchorPending;
	double m_lastScanTime = std::nan("");
	// The odometry's path (m), turn (rad) and time (s) over the scan intervals that were not gaps:
	// the robot's mean speed and turn rate, for what it may have done during a gap.
	double m_path = 0, m_turning = 0, m_drivingTime = 0;
	// A lidar alone: the accepted matches of the last kVelocityWindow s (time, pose), oldest first,
	// and the time of the newest.
	std::deque<std::pair<double, mrpt::math::TPose2D>> m_matches;
	/** MotionPrediction::alternative for `odometry` (the scan's reading), `estimate` (the previous scan's)
	 * and `predicted`; moves the anchor on. */
	std::optional<mrpt::math::TPose2D> sinceStoodStill(const mrpt::math::TPose2D& odometry,
													   const mrpt::math::TPose2D& estimate,
													   const mrpt::math::TPose2D& predicted);
	/** The robot-frame motion per second (vx, vy, ω) over the recent matches (none: unknown). */
	std::optional<mrpt::math::TPose2D> velocity() const;
	/** `estimate` moved at the recent matches' velocity for the part of the `dt` s since the
	 * previous scan that lies within kMaxExtrapolation of the last match. */
	std::optional<mrpt::math::TPose2D> extrapolate(const mrpt::math::TPose2D& estimate, double dt) const;
	/** Odometry extrapolated to time `t` from the last two timed readings (none for a bursty stream). */
	std::optional<mrpt::math::TPose2D> odometryAtTime(double t) const;
};

}  // namespace pmslam
