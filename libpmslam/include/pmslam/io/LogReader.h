/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * LogReader: one interface over the robot logs pmslam reads, delivering their
 * odometry and laser scans as a single time-ordered stream of LogEvent.
 *
 *  - CarmenLogReader: Carmen text logs (.clf/.log/.txt; FLASER, RLASER,
 *    ROBOTLASER1, ODOM lines), plain, gz- or bzip2-compressed (.clf.bz2, as
 *    Radish distributes them).
 *  - RawlogReader: MRPT .rawlog files, plain or gz-compressed, in the
 *    action–observation or the observation-only format. MRPT reads no bzip2:
 *    a bzip2-compressed rawlog is refused with a message saying so.
 *  - SimpleMapLogReader: an MRPT simple map (or a pm-slam-app output folder),
 *    its keyframes replayed with their poses as odometry (merging sessions).
 *
 * LogReader::open() picks the reader from the file's content (and extension).
 * It is defined in src/io/OpenLog.cpp, not LogReader.cpp: as the factory it
 * needs both readers, which derive from LogReader, and in a unit of its own
 * it keeps the base free of them (no include cycle between base and readers).
 * Damaged input never throws from next(): the bad line is skipped (Carmen) or
 * reading stops at the damage (rawlog), with a one-line warning through
 * onWarning, counted in stats().
 *
 * Scan geometry (both readers): scan->sensorPose is the laser pose w.r.t. the
 * robot base, and beam i points at yaw(sensorPose) + scan->getScanAngle(i),
 * i.e. yaw(sensorPose) − aperture/2 + i·aperture/(N−1) with rightToLeft = true.
 * For Carmen logs the yaw of sensorPose therefore also carries the half-step
 * offset of a fan that is not symmetric about the laser's axis (see
 * CarmenLogReader.h). Readings with no return are invalid (validity false) and
 * keep their raw range, which is >= scan->maxRange.
 */
#pragma once

#include <pmslam/sensor/ScanSlice.h>

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

namespace pmslam
{
/** One time-ordered item of a robot log. */
struct LogEvent
{
	enum class Kind
	{
		Odometry,
		Scan
	};
	Kind kind = Kind::Scan;
	/** Seconds exactly as written in the log (Carmen: the ipc_timestamp
	 * field, prints back identically with %.6f); rawlog:
	 * mrpt::Clock::toDouble() of the object's timestamp (0 if it has none). */
	double timestamp = 0;
	/** Kind::Odometry: the accumulated odometry pose of the robot base. */
	mrpt::math::TPose2D odometry;
	/** Kind::Scan: ranges, validity, aperture, rightToLeft, sensorPose (sensor
	 * w.r.t. robot base), maxRange and timestamp all set. */
	mrpt::obs::CObservation2DRangeScan::Ptr scan;
	/** Kind::Scan from Carmen FLASER/RLASER/ROBOTLASER1: the robot odometry
	 * pose written on the same line. */
	bool scanHasOdometry = false;
	mrpt::math::TPose2D scanOdometry;
	/** 1-based line number (Carmen) or object index (rawlog), for messages. */
	std::size_t sourceIndex = 0;
};

struct LogReadStats
{
	/** Carmen: lines read (all of them, comments included); rawlog: objects read. */
	std::size_t linesOrObjects = 0;
	std::size_t scans = 0;	///< Scan events delivered
	std::size_t odometry = 0;  ///< Odometry events delivered
	std::size_t skipped = 0;  ///< malformed / unusable lines or objects dropped
	std::size_t warnings = 0;  ///< warnings emitted through onWarning
};

struct LogReaderOptions
{
	/** Carmen: readings >= this are "no return" (intel/fr079 write ~81.9 m,
	 * aces saturates at 50.00 m): scan->maxRange is set to it and such beams
	 * are invalid (validity false) but keep their raw range, so a mapper can
	 * still carve free space along them. Also applied to rawlog scans that
	 * carry MRPT's Carmen-import defects (see RawlogReader.h). */
	double noReturnRange = 49.9;
	/** Carmen: emit ODOM lines as Odometry events (if a log has no ODOM line
	 * at all, use LogEvent::scanOdometry instead). */
	bool useOdomLines = true;
	/** Rawlog: a child process reads each object first (see RawlogReader.h); one that
	 * takes longer than this (s) counts as damage, as MRPT's readers can spin on it. */
	double rawlogObjectTimeout = 10.0;
	/** Rawlog: 3D lidar and RGB-D observations are mapped through this horizontal slice (ScanSlice.h). */
	ScanSliceOptions slice;
	/** Rawlog: the file is still being written (rawlog-grabber; --follow): at its end, wait for it to
	 * grow, until followTimeout s pass without a new byte (0: no limit) or stopRequested() is true.
	 * The file is read in this process only (no read-ahead child: it would meet the end first). */
	bool follow = false;
	double followTimeout = 0;
	std::function<bool()> stopRequested;
};

/** Thrown by LogReader::open() and the reader constructors: one line naming
 * the file and what was expected. */
class LogError : public std::runtime_error
{
   public:
	using std::runtime_error::runtime_error;
};

class LogReader
{
   public:
	virtual ~LogReader() = default;

	/** Opens by content/extension: .rawlog (plain or gz-compressed,
	 * action–observation or observation-only), Carmen (.clf/.log/.txt, or
	 * anything whose first non-comment line starts with a Carmen keyword; may
	 * be gz- or bzip2-compressed, told by content). Throws pmslam::LogError with a one-line message
	 * naming the file and what was expected: missing file, directory, empty
	 * file, unknown format. With opts.follow the file is a rawlog still being
	 * written (it may be empty yet; a Carmen log's name is refused). */
	static std::unique_ptr<LogReader> open(const std::string& path, const LogReaderOptions& opts = {});

	/** Next event in file order; false at end of log (or at unrecoverable
	 * damage, after a warning). */
	virtual bool next(LogEvent& ev) = 0;

	/** Estimated number of laser scans in the whole file, for progress
	 * display (approximate for rawlogs; 0 if unknown). */
	virtual std::size_t estimatedScanCount() const = 0;

	const LogReadStats& stats() const { return m_stats; }
	const std::string& path() const { return m_path; }

	/** Called with one-line warnings ("file:line: what, skipped"). Default
	 * prints to std::cerr; set to an empty function to silence. */
	std::function<void(const std::string&)> onWarning;

   protected:
	explicit LogReader(std::string path);
	/** Counts the warning and hands it to onWarning. */
	void warn(const std::string& message);
	/** next()'s last step: moves the oldest of `queue` (not empty) into `ev` and counts it; true. */
	bool deliver(std::deque<LogEvent>& queue, LogEvent& ev);

	std::string m_path;
	LogReadStats m_stats;
};

}  // namespace pmslam
