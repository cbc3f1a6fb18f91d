/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * ObservationEvents: turns MRPT objects, one at a time, into LogEvent — the
 * conversion that RawlogReader applies to a file's objects and LiveReader to
 * what sensor drivers deliver. One conversion for both is what makes a
 * --record'ed live run replay offline to exactly the same trajectory.
 *
 *  - CActionCollection: its best CActionRobotMovement2D increment is composed
 *    onto an accumulated odometry pose (from the origin) → Odometry event
 *    (stamped with the action, or with the next frame's first observation).
 *  - CSensoryFrame: each observation as below; a frame with scans before any
 *    odometry gets an Odometry event at the origin first.
 *  - CObservationOdometry → Odometry; CObservation2DRangeScan → Scan; 3D lidar
 *    and RGB-D observations → Scan through their horizontal slice (ScanSlice.h).
 *  - anything else is ignored.
 * Unusable objects (implausible poses, no valid beam, bad geometry) are
 * skipped with a one-line warning naming the source and the object index.
 */
#pragma once

#include <pmslam/io/LogReader.h>

#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <set>
#include <string>

namespace pmslam
{
class ObservationEvents
{
   public:
	/** `source` names the file or sensor set in warnings; `warn` receives them; `stats` counts skips. */
	ObservationEvents(const LogReaderOptions& opts, std::string source, std::function<void(const std::string&)> warn,
					  LogReadStats& stats);

	/** Converts object number `index` (1-based, for messages), appending its events to `out`. */
	void add(const mrpt::serialization::CSerializable::Ptr& obj, std::size_t index, std::deque<LogEvent>& out);
	/** No more objects: an odometry reading still waiting for a timestamp is delivered. */
	void finish(std::deque<LogEvent>& out) { flushHeld(m_lastTs, out); }

   private:
	void push(LogEvent&& e, std::deque<LogEvent>& out);
	/** Counts object `index` as skipped, with the warning "SOURCE: object INDEX: WHY, skipped". */
	void skip(std::size_t index, const std::string& why);
	void flushHeld(double ts, std::deque<LogEvent>& out);
	void addObservation(const mrpt::obs::CObservation::Ptr& o, std::size_t index, std::deque<LogEvent>& out);
	mrpt::obs::CObservation2DRangeScan::Ptr asScan(const mrpt::obs::CObservation::Ptr& o, std::size_t index);
	bool usableScan(mrpt::obs::CObservation2DRangeScan& scan, std::size_t index);

	LogReaderOptions m_opts;
	std::string m_source;
	std::function<void(const std::string&)> m_warn;
	LogReadStats& m_stats;
	std::optional<LogEvent> m_held;	 // odometry whose action had no timestamp
	mrpt::poses::CPose2D m_odom;  // accumulated action–observation odometry
	bool m_odomEmitted = false;
	bool m_fixWarned = false;
	std::set<std::string> m_sliceWarned;  // why a 3D observation could not be sliced, warned once each
	double m_lastTs = 0;
};

}  // namespace pmslam
