/* pm-slam-app — the command line: what a run is asked to do (see kUsage in Options.cpp, or --help). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <pmslam/slam/SlamConfig.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pmslam_app
{
struct Options
{
	std::string log, config, out = "pmslam-out";
	std::vector<std::string> sets;
	std::size_t maxScans = 0;
	std::string localize;  // fixed map to localise on (empty: SLAM)
	std::string continueFrom;  // session folder whose map this run continues (empty: a new map)
	bool lifelong = false;	// --continue: earlier keyframes this run covers are retired
	mrpt::math::TPose2D initialPose{0, 0, 0};
	bool initialPoseGiven = false;	// else --localize searches the whole map for the start
	bool gui = false, quiet = false;
	bool logGiven = false, outGiven = false;
	double maxUntracked = 10.0;	 // s
	int progress = -1;	// -1 auto
	std::string live, follow, record;  // --live SENSORS.ini, --follow LOG.rawlog, --record FILE.rawlog
	double followTimeout = 0, snapshotEvery = -1, connectTimeout = 30;	// s; snapshotEvery -1: the mode's default
	std::size_t maxPending = 20;

	bool isLive() const { return !live.empty(); }
	bool localizing() const { return !localize.empty(); }
	bool continuing() const { return !continueFrom.empty(); }
	/** --live and --follow end with Ctrl-C (or SIGTERM): their normal end, not an interruption. */
	bool openEnded() const { return !live.empty() || !follow.empty(); }
};

/** Parses the command line; prints --help and exits 0, or exits 2 with one line on a usage error. */
Options parseOptions(int argc, char** argv);

/** An MRPT icp-slam file names its log and output folder: used when the command line names none. */
void takeIcpSlamNames(Options& options, const pmslam::SlamConfig& config);

/** Prints "pm-slam-app: MESSAGE" on stderr, with a library message's own "pmslam: " prefix dropped. */
void say(const std::string& message);

}  // namespace pmslam_app
