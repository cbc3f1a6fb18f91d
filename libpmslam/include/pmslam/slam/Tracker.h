/* pmslam — the front-end's tracking state.
 *
 * Each scan that is matched leaves the front-end in one of four states:
 * - tracking: the match was accepted (it explains the scan well enough);
 * - ambiguous: a re-localisation found look-alike poses and decided nothing;
 * - lost: the match was rejected, and the pose is odometry only;
 * - new ground: lost for a while, and the scan lies in space no scan has
 *   observed (after a gap the robot drove somewhere never mapped): it goes into
 *   the map at the odometry pose so that the map grows again.
 * The Tracker judges each match into one of them (a scan not matched leaves the
 * state as it was), keeps the stretches of the log without an accepted match
 * (TrackingGap: what the application reports as untracked), and what the
 * loop-closure back-end needs to know of each keyframe: whether every scan since
 * the previous keyframe was tracked, and whether a re-localisation placed one.
 *
 * Why one part: the state was a handful of flags (lost, the last accepted time, the
 * open gap, tracked and searched since the keyframe), each set in another place of
 * the per-scan function; here they change together, once per scan.
 */
#pragma once

#include <pmslam/match/PerfectMatchMatcher.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

namespace pmslam
{
enum class TrackingState
{
	Tracking,
	Ambiguous,
	Lost,
	NewGround
};

/** A stretch of the log where no match was accepted: from the first rejected scan to the next
 * accepted one (or the last scan), in scan timestamps (s). Every pose in it is odometry only. */
struct TrackingGap
{
	double from = 0, to = 0;
	std::size_t scans = 0;	///< rejected scans in it
	bool open = true;  ///< still going at the last scan

	/** No lidar sends more scans than this per second (SICK's fastest, 100 Hz). */
	static constexpr double kMaxScanRate = 100;
	/** How long tracking was lost (s): the stamps' span, but at least the rejected scans at
	 * kMaxScanRate. A log whose stamps are not the sensor's (a simulator that stamps scans with the
	 * time it wrote them, 0.3 ms apart) would otherwise lose its robot for thousands of scans in
	 * under a second of "log time", and every rule that waits for seconds of loss (the new-ground
	 * insertion, the whole-map search, the exit status) would never fire. */
	double length() const
	{
		const double stamped = std::isfinite(to - from) ? to - from : 0.0;
		return std::max(stamped, double(scans) / kMaxScanRate);
	}
};

/** The MapBuilderOptions fields of the same names (see there for their defaults and why);
 * PerfectMatchSlam fills them. */
struct TrackerOptions
{
	double minGoodness = 0;
	double minOverlapGoodness = 0;
	unsigned minPoints = 0;
	double newGroundUnexplored = 0;
	double newGroundAfter = 0;	///< s
};

class Tracker
{
   public:
	explicit Tracker(const TrackerOptions& options) : m_options(options) {}

	TrackingState state() const { return m_state; }
	/** The last match was not accepted (ambiguous, lost or new ground). */
	bool lost() const { return m_state != TrackingState::Tracking; }
	/** How long the open stretch without an accepted match has lasted at `now` (TrackingGap::length(); 0 while tracking). */
	double lostFor(double now) const;

	/** The next scan is the first after a start pose given over a map made before (a continued
	 * session): its prediction is that pose, not odometry that may have drifted while the robot was
	 * lost, so a scan the map explains too little of is new ground at once (see judge()). */
	void startAtKnownPose() { m_atKnownStart = true; }

	/** The state a match leaves: tracking when accepted (and not `undecided`), new ground when
	 * lost for newGroundAfter (or at a known start) and `unexploredFraction()` (of the scan at the
	 * prediction; asked only then) is at least newGroundUnexplored, else ambiguous or lost.
	 * `afterGap`: the first scan after a logging gap, whose prediction is in doubt (D56). */
	TrackingState judge(const PerfectMatchMatcher::MatchInfo& info, bool undecided, bool afterGap, double now,
						const std::function<double()>& unexploredFraction) const;

	/** What the back-end is told of a keyframe taken at this scan (matched: the scan's match was
	 * accepted; relocalized: a re-localisation placed it; first: no keyframe before). */
	struct KeyframeEvidence
	{
		bool tracked = true;  ///< matched, and so was every scan since the previous keyframe
		bool searched = false;	///< a match since the previous keyframe was placed by a re-localisation
	};
	KeyframeEvidence keyframeEvidence(bool matched, bool relocalized, bool first) const;

	/** End of a scan: `verdict` is judge()'s (none: the scan was not matched, the state stays);
	 * `keyframe`: the scan became a keyframe. */
	void update(const std::optional<TrackingState>& verdict, bool relocalized, bool keyframe, double now);

	/** Every stretch without an accepted match so far, oldest first. */
	const std::vector<TrackingGap>& gaps() const { return m_gaps; }

   private:
	TrackerOptions m_options;
	TrackingState m_state = TrackingState::Tracking;
	std::vector<TrackingGap> m_gaps;
	bool m_trackedSinceKeyframe = true;
	bool m_searchedSinceKeyframe = false;  // a match since the last keyframe re-localised
	bool m_atKnownStart = false;  // startAtKnownPose(), until the next judged scan
	bool acceptable(const PerfectMatchMatcher::MatchInfo& info, bool afterGap) const;
};

}  // namespace pmslam
