/* pm-slam-app — online Perfect Match SLAM on a robot log.
 *
 *   pm-slam-app [options] [LOG]
 *
 * Reads an MRPT .rawlog or a Carmen log, builds the map and the trajectory
 * scan by scan, and writes them to --out (see --help and README.md).
 */
#include <pmslam/io/AtomicFile.h>
#include <pmslam/slam/PerfectMatchSlam.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/RawlogRecorder.h>
#include <pmslam/live/LiveReader.h>
#include <pmslam/live/PendingObservations.h>
#include <pmslam/util/LibraryPages.h>
#include <pmslam/util/RunStatistics.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/sensor/ScanPoints.h>
#include <pmslam/slam/SlamConfig.h>
#include <pmslam/io/Trajectory.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <filesystem>
#include <iostream>
#include <numeric>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "LiveSensors.h"
#include "LiveViewer.h"
#include "ProgressLine.h"

namespace
{
const char* kDefaultLog = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

const char* kUsage =
	R"(usage: pm-slam-app [options] [LOG]
       pm-slam-app [options] --live SENSORS.ini
       pm-slam-app [options] --follow LOG.rawlog

Online 2D laser SLAM with the Perfect Match scan matcher.
LOG is an MRPT .rawlog (action-observation or observation-only, plain or gz)
or a Carmen log (.clf/.log: FLASER, RLASER, ROBOTLASER1, ODOM). Without LOG,
the sample log that MRPT installs is mapped:
  )" "%s" R"(

options (before or after LOG):
  --config FILE           INI configuration (sections [PerfectMatch], [MappingApplication], [LoopClosure],
                          [Log]; every key is documented in config/default.ini). An MRPT icp-slam INI file
                          works too: what means the same is read (its rawlog_file is the LOG and its
                          logOutput_dir the --out when none is given), the rest is named in a note
  --set SECTION.KEY=VALUE override one configuration key (repeatable)
  --out DIR               output folder (default ./pmslam-out)
  --max-scans N           stop after N scans (0 = all)
  --localize MAP          track the robot on a fixed prior map (a .gridmap[.gz] written by pm-slam-app
                          or any serialised MRPT COccupancyGridMap2D) without changing it; writes
                          trajectory.txt, timing.txt and map.png (the fixed map with the path)
  --initial-pose X,Y,YAW_DEG  start pose on the --localize map (m, m, degrees; default 0,0,0)
  --gui                   live view of map, scan and trajectory (needs a display)
  --progress / --no-progress  force the progress line on or off (default: on when stderr is a terminal)
  --max-untracked S       exit with status 3 when no match was accepted for more than S seconds of log
                          (default 10; those poses are odometry only); spans over 3 s are warned about
  --quiet                 no summary, only warnings and errors

live runs:
  --live SENSORS.ini      map from live sensors, configured exactly as for MRPT's rawlog-grabber (one section
                          per sensor: driver = CHokuyoURG, CLMS100Eth, CSICKTim561Eth_2050101, CRoboPeakLidar,
                          ... with the driver's own keys and process_rate; [global] is ignored). Runs until
                          Ctrl-C (or SIGTERM), then writes every output and exits 0
  --follow LOG.rawlog     map a rawlog that rawlog-grabber is still writing, waiting for new objects at its
                          end; stops on Ctrl-C or after --follow-timeout
  --follow-timeout S      --follow: stop after S seconds without the file growing (default 0: only Ctrl-C)
  --record FILE.rawlog    --live: save everything received, as rawlog-grabber does (gz, observations only;
                          FILE.rawlog.part until the end); pm-slam-app on FILE.rawlog then reproduces the live
                          trajectory exactly (unless scans were dropped, which the summary says)
  --snapshot-every S      write pose.txt, trajectory.txt and the map (map.png, map.pgm + map.yaml) every S
                          seconds of wall time while running, each atomically (default 5 with --live or
                          --follow, 0 = never otherwise)
  --max-pending N         --live: at most N scans wait for the SLAM; when more arrive the oldest are dropped
                          (counted and warned about; default 20)
  --connect-timeout S     --live: each sensor must deliver data within S seconds of start-up (default 30:
                          MRPT's CLMS100Eth alone takes 15 s to start),
                          else the run stops with an error naming its section; a sensor silent for 2 s while
                          running is reconnected, with a warning
  -h, --help              this text

outputs in DIR: trajectory.txt (timestamp x y yaw, one line per scan; after loop closure),
trajectory_online.txt (each pose as known when its scan arrived), graph.graph (the pose graph,
MRPT .graph format), map.png, map.pgm + map.yaml (ROS map_server), map.gridmap.gz and
map.simplemap.gz (MRPT), timing.txt (per-scan milliseconds and tracking state). Exit status: 0 done, 2 bad input or
configuration, 1 failure while running, 3 done but tracking was lost (no match accepted) for more
than --max-untracked seconds of log somewhere (outputs written, each such span warned about),
130 interrupted (outputs still written; with --live and --follow, Ctrl-C is the normal end: 0).
)";

// The --gui view's longest side (pixels): a larger map is shown shrunk (each pixel its block's darkest cell).
constexpr int kGuiMaxSide = 1600;

// A stretch without an accepted match longer than this (s of log) is warned about.
constexpr double kWarnUntrackedSeconds = 3.0;

std::atomic<bool> g_stop{false};
std::atomic<long long> g_stopAtNs{0};  // CLOCK_MONOTONIC of the first signal
void onSignal(int sig)
{
	timespec ts{};
	::clock_gettime(CLOCK_MONOTONIC, &ts);  // async-signal-safe
	const long long now = (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
	if (g_stop)
	{
		// A second Ctrl-C / SIGTERM: stop now, without writing outputs. Not a repeat within half a
		// second: coreutils' timeout sends its signal to the process and to its group, so one timeout can
		// deliver it twice.
		if (now - g_stopAtNs.load() < 500000000LL) return;
		std::signal(sig, SIG_DFL);
		std::raise(sig);
	}
	g_stopAtNs = now;
	g_stop = true;
}

struct Args
{
	std::string log, config, out = "pmslam-out";
	std::vector<std::string> sets;
	std::size_t maxScans = 0;
	std::string localize;  // fixed map to localise on (empty: SLAM)
	mrpt::math::TPose2D initialPose{0, 0, 0};
	bool gui = false, quiet = false;
	bool logGiven = false, outGiven = false;
	double maxUntracked = 10.0;	 // s
	int progress = -1;	// -1 auto
	std::string live, follow, record;  // --live SENSORS.ini, --follow LOG.rawlog, --record FILE.rawlog
	double followTimeout = 0, snapshotEvery = -1, connectTimeout = 30;	// s; snapshotEvery -1: the mode's default
	std::size_t maxPending = 20;
};

[[noreturn]] void usageError(const std::string& msg)
{
	std::cerr << "pm-slam-app: " << msg << " (see --help)\n";
	std::exit(2);
}

Args parseArgs(int argc, char** argv)
{
	Args a;
	std::vector<std::string> positional;
	bool initialPoseGiven = false;
	for (int i = 1; i < argc; ++i)
	{
		const std::string s = argv[i];
		auto value = [&](const char* name) -> std::string {
			if (i + 1 >= argc) usageError(std::string(name) + " needs a value");
			return argv[++i];
		};
		auto wholeNumber = [&](const char* name, long least) {
			const std::string v = value(name);
			char* end = nullptr;
			const long n = std::strtol(v.c_str(), &end, 10);
			if (end == v.c_str() || *end || n < least)
				usageError(std::string(name) + " '" + v + "': expected a whole number >= " + std::to_string(least));
			return static_cast<std::size_t>(n);
		};
		auto seconds = [&](const char* name) {
			const std::string v = value(name);
			char* end = nullptr;
			const double x = std::strtod(v.c_str(), &end);
			if (end == v.c_str() || *end || !(x >= 0) || !std::isfinite(x))
				usageError(std::string(name) + " '" + v + "': expected seconds >= 0");
			return x;
		};
		if (s == "-h" || s == "--help")
		{
			std::printf(kUsage, kDefaultLog);
			std::exit(0);
		}
		else if (s == "--config") a.config = value("--config");
		else if (s == "--set") a.sets.push_back(value("--set"));
		else if (s == "--out") a.out = value("--out"), a.outGiven = true;
		else if (s == "--max-scans") a.maxScans = wholeNumber("--max-scans", 0);
		else if (s == "--localize") a.localize = value("--localize");
		else if (s == "--initial-pose")
		{
			const std::string v = value("--initial-pose");
			double x = 0, y = 0, yawDeg = 0;
			char tail = 0;
			if (std::sscanf(v.c_str(), "%lf,%lf,%lf%c", &x, &y, &yawDeg, &tail) != 3 ||
				!std::isfinite(x + y + yawDeg))
				usageError("--initial-pose '" + v + "': expected X,Y,YAW_DEG (m, m, degrees), e.g. 1.5,-2,90");
			a.initialPose = {x, y, mrpt::DEG2RAD(yawDeg)};
			initialPoseGiven = true;
		}
		else if (s == "--max-untracked") a.maxUntracked = seconds("--max-untracked");
		else if (s == "--live") a.live = value("--live");
		else if (s == "--follow") a.follow = value("--follow");
		else if (s == "--follow-timeout") a.followTimeout = seconds("--follow-timeout");
		else if (s == "--record") a.record = value("--record");
		else if (s == "--snapshot-every") a.snapshotEvery = seconds("--snapshot-every");
		else if (s == "--connect-timeout") a.connectTimeout = seconds("--connect-timeout");
		else if (s == "--max-pending") a.maxPending = wholeNumber("--max-pending", 1);
		else if (s == "--gui") a.gui = true;
		else if (s == "--quiet") a.quiet = true;
		else if (s == "--progress") a.progress = 1;
		else if (s == "--no-progress") a.progress = 0;
		else if (s.size() > 1 && s[0] == '-') usageError("unknown option '" + s + "'");
		else positional.push_back(s);
	}
	if (positional.size() > 1) usageError("expected one LOG, got " + std::to_string(positional.size()));
	if (initialPoseGiven && a.localize.empty()) usageError("--initial-pose needs --localize MAP");
	if (!a.live.empty() && !a.follow.empty()) usageError("--live and --follow exclude each other");
	if ((!a.live.empty() || !a.follow.empty()) && !positional.empty())
		usageError(std::string(a.live.empty() ? "--follow" : "--live") + " takes the place of LOG: give one or the other");
	if (!a.record.empty() && a.live.empty()) usageError("--record needs --live (a log is its own recording)");
	if (a.snapshotEvery < 0) a.snapshotEvery = (a.live.empty() && a.follow.empty()) ? 0 : 5;
	if (!a.follow.empty()) positional.push_back(a.follow);
	a.log = !a.live.empty() ? a.live : positional.empty() ? kDefaultLog : positional[0];
	a.logGiven = !positional.empty() || !a.live.empty();
	return a;
}

struct ScanTiming
{
	double timestamp, matchMs, updateMs, backendMs;
	bool matched, inserted;
	unsigned iterations;
	double goodness;
	int tracking;  // 0 matched, 1 not matched (below the insertion thresholds), 2 matched after a wide search moved it, 3 rejected, 4 new ground
	bool wideSearch;
};

void writeOutputs(const std::string& dir, const pmslam::PerfectMatchSlam& slam, const pmslam::Trajectory& traj,
				  const pmslam::Trajectory& online, const std::vector<ScanTiming>& timing, const std::string& header,
				  bool localizing)
{
	namespace fs = std::filesystem;
	const auto at = [&](const char* name) { return (fs::path(dir) / name).string(); };
	pmslam::saveTrajectory(at("trajectory.txt"), traj,
						   header + "\nposes of the robot base in the map frame (m, m, rad)" +
							   (slam.loopClosure() ? ", after loop closure (the final pose graph)" : ""));
	if (!localizing)
		pmslam::saveTrajectory(at("trajectory_online.txt"), online,
							   header + "\neach pose as known when its scan was processed (before later loop closures)");
	if (slam.loopClosure()) slam.loopClosure()->graph().writeGraphFile(at("graph.graph"));
	pmslam::writeFileAtomically(at("timing.txt"), [&](std::ostream& out) {
		out << "# " << header
			<< "\n# timestamp match_ms update_ms total_ms matched inserted iterations goodness tracking wide_search"
			   "\n# tracking: 0 matched, 1 odometry only (moved less than the insertion thresholds), 2 matched after"
			   " the wide search moved it (re-localised), 3 match rejected (odometry only), 4 lost on new ground:"
			   " inserted at the odometry pose; backend_wait_ms: waiting for the loop-closure back-end (not in total_ms)\n";
		char line[200];
		for (const auto& t : timing)
		{
			std::snprintf(line, sizeof line, "%.6f %.4f %.4f %.4f %d %d %u %.4f %d %d %.4f\n", t.timestamp, t.matchMs,
						  t.updateMs, t.matchMs + t.updateMs, int(t.matched), int(t.inserted), t.iterations, t.goodness,
						  t.tracking, int(t.wideSearch), t.backendMs);
			out << line;
		}
	});
	const auto& grid = slam.grid();
	pmslam::saveMapPng(grid, traj, at("map.png"),
					   slam.loopClosure() ? slam.loopClosure()->loopLinks()
										  : std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>());
	if (localizing) return;	 // the map is the fixed prior map: only the path over it is new
	pmslam::saveMapPgmYaml(grid, at("map.pgm"), at("map.yaml"));
	pmslam::saveGridMapGz(grid, at("map.gridmap.gz"));
	slam.saveSimpleMapGz(at("map.simplemap.gz"));
}

}  // namespace

int main(int argc, char** argv)
{
	// Installed first, so that a signal at any time ends with exit code 130 and outputs.
	std::signal(SIGINT, onSignal);
	std::signal(SIGTERM, onSignal);
	Args args = parseArgs(argc, argv);
	// A sensor driver writing to a connection the sensor has closed must get an error, not end the process.
	if (!args.live.empty()) std::signal(SIGPIPE, SIG_IGN);

	pmslam::SlamConfig cfg;
	try
	{
		cfg = pmslam::loadSlamConfig(args.config, args.sets);
	}
	catch (const std::exception& e)
	{
		std::cerr << "pm-slam-app: " << e.what() << "\n";
		return 2;
	}
	for (const auto& n : cfg.notes)
		if (!args.quiet) std::cerr << "pm-slam-app: note: " << n << "\n";
	// An icp-slam file names its log and output folder; the command line wins.
	if (!args.logGiven && !cfg.icpSlamLogFile.empty())
	{
		namespace fs = std::filesystem;
		fs::path p = cfg.icpSlamLogFile;
		// As icp-slam: relative to the working directory; MRPT's sample files name it relative to themselves.
		const fs::path besideIni = fs::path(args.config).parent_path() / p;
		if (p.is_relative() && !fs::exists(p) && fs::exists(besideIni)) p = besideIni;
		args.log = p.string();
	}
	if (!args.outGiven && !cfg.icpSlamOutputDir.empty()) args.out = cfg.icpSlamOutputDir;
	// The log first: a bad LOG must not leave an empty --out folder behind.
	std::unique_ptr<pmslam::LogReader> reader;
	const bool live = !args.live.empty();
	std::unique_ptr<pmslam::PendingObservations> pending;  // --live: between the sensor threads and the SLAM
	std::unique_ptr<pmslam::RawlogRecorder> recorder;	  // --record
	std::atomic<bool> recordFailed{false};
	std::unique_ptr<pmslam_app::LiveSensors> sensors;
	try
	{
		if (live)
		{
			pending = std::make_unique<pmslam::PendingObservations>(args.maxPending);
			if (!args.record.empty())
			{
				try
				{
					recorder = std::make_unique<pmslam::RawlogRecorder>(args.record);
				}
				catch (const std::exception& e)
				{
					throw std::runtime_error("--record " + args.record + ": " + e.what());
				}
				pending->onReceived = [&](const mrpt::serialization::CSerializable::Ptr& obj) {
					if (recordFailed) return;
					try
					{
						recorder->write(*obj);
					}
					catch (const std::exception& e)
					{  // the SLAM goes on; the recording stops, loudly
						recordFailed = true;
						pending->note("--record " + args.record + ": writing failed (" + e.what() +
									  "): the recording stops here");
					}
				};
			}
			try
			{
				sensors = std::make_unique<pmslam_app::LiveSensors>(args.live, *pending, args.connectTimeout, 2.0);
			}
			catch (const std::exception&)
			{
				if (recorder) recorder->abandon();
				throw;
			}
			reader = std::make_unique<pmslam::LiveReader>(
				args.live, *pending, [] { return g_stop.load(); }, [&] { sensors->stop(); }, cfg.log);
		}
		else if (!args.follow.empty())
		{
			pmslam::LogReaderOptions opts = cfg.log;
			opts.follow = true;
			opts.followTimeout = args.followTimeout;
			opts.stopRequested = [] { return g_stop.load(); };
			reader = pmslam::LogReader::open(args.follow, opts);
		}
		else
			reader = pmslam::LogReader::open(args.log, cfg.log);
	}
	catch (const std::exception& e)
	{
		std::cerr << "pm-slam-app: " << e.what() << "\n";
		// A sensor thread may be stuck inside its driver (one that never returns on garbage): end without
		// the static destructors it could still be using.
		std::fflush(nullptr);
		if (live) std::_Exit(2);
		return 2;
	}
	// The prior map too (--localize), before --out is created.
	mrpt::maps::COccupancyGridMap2D priorMap;
	if (!args.localize.empty())
	{
		try
		{
			pmslam::loadGridMapGz(args.localize, priorMap);
		}
		catch (const std::exception& e)
		{
			std::cerr << "pm-slam-app: --localize " << e.what() << "\n";
			return 2;
		}
	}
	try
	{
		// A floor, not a forecast: the map files grow with the mapped area, unknown yet, but a
		// trajectory and timing line per scan and the smallest map files need at least this.
		const std::uint64_t needed = (std::uint64_t(1) << 20) + 128 * std::uint64_t(reader->estimatedScanCount());
		pmslam::checkDirectoryWritable(args.out, needed);
	}
	catch (const std::exception& e)
	{
		std::cerr << "pm-slam-app: --out " << args.out << ": " << e.what() << "\n";
		return 2;
	}

	const bool showProgress = args.progress == 1 || (args.progress == -1 && isatty(STDERR_FILENO) && !args.quiet);
	pmslam::ProgressLine progress(showProgress, reader->estimatedScanCount());
	reader->onWarning = [&](const std::string& w) {
		progress.clear();
		std::cerr << "pm-slam-app: warning: " << w << "\n";
	};

	pmslam::PerfectMatchSlam slam;
	slam.PM_options = cfg.mapping;
	slam.PM_params = cfg.matcher;
	slam.LC_options = cfg.loopClosure;
	slam.initialize();
	if (!args.localize.empty())
	{
		try
		{
			slam.initializeWithFixedMap(priorMap, args.initialPose);
		}
		catch (const std::exception& e)
		{
			std::cerr << "pm-slam-app: --localize " << args.localize << ": " << e.what() << "\n";
			return 2;
		}
	}

	std::unique_ptr<pmslam_app::LiveViewer> window;
	if (args.gui)
	{
		if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
			std::cerr << "pm-slam-app: warning: --gui needs a display (DISPLAY is not set); running headless\n";
		else
		{
			window = std::make_unique<pmslam_app::LiveViewer>("pm-slam-app: " + args.log);
			if (!window->isOpen())
			{
				std::cerr << "pm-slam-app: warning: --gui: " << window->error() << "; running headless\n";
				window.reset();
			}
		}
	}

	pmslam::Trajectory traj;
	// The smoothed poses (odometrySmoothing) replace each scan's pose once final.
	auto applySmoothedPoses = [&](bool finish) {
		for (const auto& [i, p] : slam.takeSmoothedPoses(finish))
			if (i < traj.size()) traj[i].x = p.x, traj[i].y = p.y, traj[i].yaw = p.phi;
	};
	// Each pose moved with its keyframe to where the graph has it (the live view, and the final
	// trajectory once the graph is final); and the closures, for the live view.
	auto corrected = [&](const pmslam::Trajectory& t) {
		if (!slam.loopClosure()) return t;
		std::vector<mrpt::math::TPose2D> poses;
		poses.reserve(t.size());
		for (const auto& p : t) poses.emplace_back(p.x, p.y, p.yaw);
		poses = slam.correctedTrajectory(poses);
		pmslam::Trajectory out = t;
		for (std::size_t i = 0; i < out.size(); ++i) out[i].x = poses[i].x, out[i].y = poses[i].y, out[i].yaw = poses[i].phi;
		return out;
	};
	auto loopLinks = [&]() {
		return slam.loopClosure() ? slam.loopClosure()->loopLinks()
								  : std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>();
	};
	// Start-up is over: the library pages only the loader read go back (util/LibraryPages.h);
	// PMSLAM_KEEP_LIBRARY_PAGES=1 keeps them (to measure what that saves).
	// PMSLAM_SMAPS_DUMP=FILE: /proc/self/smaps before (FILE.before) and after (FILE.after), for
	// bench/memory.sh's table of what each library costs at start-up.
	const char* smapsDump = std::getenv("PMSLAM_SMAPS_DUMP");
	auto dumpSmaps = [&](const char* suffix) {
		if (!smapsDump || !*smapsDump) return;
		std::ifstream in("/proc/self/smaps");
		std::ofstream(std::string(smapsDump) + suffix) << in.rdbuf();
	};
	dumpSmaps(".before");
	const char* keepPages = std::getenv("PMSLAM_KEEP_LIBRARY_PAGES");
	const double releasedMB = keepPages && *keepPages && *keepPages != '0' ? 0.0 : pmslam::releaseStartupLibraryPages();
	dumpSmaps(".after");
	std::vector<ScanTiming> timing;
	const auto wallStart = std::chrono::steady_clock::now();
	auto lastGui = wallStart, lastSnapshot = wallStart;
	std::chrono::steady_clock::duration guiPeriod = std::chrono::milliseconds(500);
	// --live: from a scan's timestamp (the driver's clock) to its pose (ms), and drops already warned about.
	std::vector<double> latencyMs;
	// Test hook: PMSLAM_TEST_SCAN_DELAY_MS=N makes each live scan take N ms more, a SLAM slower than its sensors
	// (tests/apps/test_live.cpp: the oldest scans must be dropped, with the real driver in the loop).
	const char* delayEnv = std::getenv("PMSLAM_TEST_SCAN_DELAY_MS");
	const int testDelayMs = live && delayEnv ? std::atoi(delayEnv) : 0;
	std::size_t droppedWarned = 0;
	auto lastDropWarning = wallStart - std::chrono::hours(1);
	std::size_t snapshots = 0;
	auto snapshot = [&]() {
		namespace fs = std::filesystem;
		const auto at = [&](const char* name) { return (fs::path(args.out) / name).string(); };
		const pmslam::Trajectory now = corrected(traj);
		char line[160];
		std::snprintf(line, sizeof line, "%.6f %.4f %.4f %.5f\n", now.back().timestamp, now.back().x, now.back().y,
					  now.back().yaw);
		pmslam::writeFileAtomically(at("pose.txt"), [&](std::ostream& out) {
			out << "# timestamp x y yaw: the newest pose (m, m, rad), written every " << args.snapshotEvery
				<< " s while running\n"
				<< line;
		});
		pmslam::saveTrajectory(at("trajectory.txt"), now, "pm-slam-app " + args.log + ": snapshot while running");
		pmslam::saveMapPng(slam.grid(), now, at("map.png"), loopLinks());
		if (args.localize.empty()) pmslam::saveMapPgmYaml(slam.grid(), at("map.pgm"), at("map.yaml"));
		++snapshots;
	};
	bool failed = false;
	std::string failure;
	try
	{
		pmslam::LogEvent ev;
		// A live reader sees Ctrl-C itself: it stops the sensors, then hands over what they had delivered.
		while ((live || !g_stop) && reader->next(ev))
		{
			if (ev.kind == pmslam::LogEvent::Kind::Odometry)
			{
				if (cfg.odometrySource != pmslam::OdometrySource::Scan) slam.processOdometry(ev.odometry, ev.timestamp);
				continue;
			}
			std::optional<mrpt::math::TPose2D> odo;
			if (ev.scanHasOdometry && cfg.odometrySource != pmslam::OdometrySource::Events) odo = ev.scanOdometry;
			const auto& r = slam.processScan(*ev.scan, odo);
			traj.push_back({ev.timestamp, r.pose.x, r.pose.y, r.pose.phi});
			if (testDelayMs > 0) std::this_thread::sleep_for(std::chrono::milliseconds(testDelayMs));
			if (live && ev.scan->timestamp != INVALID_TIMESTAMP)
				latencyMs.push_back(
					1e3 * mrpt::system::timeDifference(ev.scan->timestamp, mrpt::Clock::now()));
			applySmoothedPoses(false);
			const int tracking = r.reanchored ? 4 : r.rejected ? 3 : r.relocalized ? 2 : r.matched ? 0 : 1;
			if (r.reanchored && (timing.empty() || timing.back().tracking != 4))
			{
				progress.clear();
				const auto& gaps = slam.trackingGaps();
				std::fprintf(stderr,
							 "pm-slam-app: warning: at t=%.3f, after %.1f s without an accepted match, the scans see new "
							 "ground only: inserted at the odometry pose from here, so the map grows on, but its alignment "
							 "with what was mapped before is not verified\n",
							 ev.timestamp, gaps.empty() ? 0.0 : ev.timestamp - gaps.back().from);
			}
			timing.push_back({ev.timestamp, r.matchMs, r.updateMs, r.backendWaitMs, r.matched, r.inserted, r.info.nIterations,
							  r.info.goodness, tracking, r.wideSearch});
			if (live)
			{
				const auto c = pending->counts();
				// Falling behind the sensors: said at once, then at most every 5 s while it goes on.
				if (c.droppedScans > droppedWarned &&
					std::chrono::steady_clock::now() - lastDropWarning > std::chrono::seconds(5))
				{
					progress.clear();
					std::fprintf(stderr,
								 "pm-slam-app: warning: at t=%.3f the SLAM fell behind the sensors: %zu scans dropped "
								 "unprocessed so far (the oldest pending; at most --max-pending %zu wait)\n",
								 ev.timestamp, c.droppedScans, args.maxPending);
					droppedWarned = c.droppedScans;
					lastDropWarning = std::chrono::steady_clock::now();
				}
				progress.updateText([&] {
					std::vector<double> recent(latencyMs.end() - std::min<std::size_t>(latencyMs.size(), 400),
											   latencyMs.end());
					double deg = std::round(mrpt::RAD2DEG(traj.back().yaw));
					if (deg == 0) deg = 0;	// not "-0"
					char b[256];
					std::snprintf(b, sizeof b,
								  "received %zu scans, processed %zu, dropped %zu; latency p50 %.1f ms, p99 %.1f ms; "
								  "pose %.2f %.2f %.0f deg",
								  c.scans, traj.size(), c.droppedScans, pmslam::percentile(recent, 0.5),
								  pmslam::percentile(recent, 0.99), traj.back().x, traj.back().y, deg);
					return std::string(b);
				});
			}
			else
				progress.update(traj.size());
			if (args.snapshotEvery > 0 &&
				std::chrono::steady_clock::now() - lastSnapshot > std::chrono::duration<double>(args.snapshotEvery))
			{
				try
				{
					snapshot();
				}
				catch (const std::exception& e)
				{
					progress.clear();
					std::cerr << "pm-slam-app: warning: snapshot to " << args.out << " failed: " << e.what() << "\n";
				}
				lastSnapshot = std::chrono::steady_clock::now();
			}
			if (window && std::chrono::steady_clock::now() - lastGui > guiPeriod)
			{
				const auto renderStart = std::chrono::steady_clock::now();
				// The current scan's returns, placed at the pose SLAM gave it.
				std::vector<mrpt::math::TPoint2D> scanInMap;
				const mrpt::poses::CPose2D pose(traj.back().x, traj.back().y, traj.back().yaw);
				for (const auto& p : pmslam::scanToPoints(*ev.scan, cfg.mapping.grid.scan).hits)
				{
					double wx, wy;
					pose.composePoint(p.x, p.y, wx, wy);
					scanInMap.emplace_back(wx, wy);
				}
				// With loop closure: the trajectory as the graph has it now, and the closures in blue.
				window->show(pmslam::renderMap(slam.grid(), corrected(traj), scanInMap, loopLinks(), kGuiMaxSide));
				lastGui = std::chrono::steady_clock::now();
				// The view takes at most a tenth of the time: a large map is redrawn less often, and a live
				// run never falls behind its sensors for the window's sake.
				guiPeriod = std::max<std::chrono::steady_clock::duration>(std::chrono::milliseconds(500),
																		   10 * (lastGui - renderStart));
			}
			if (args.maxScans && traj.size() >= args.maxScans) break;
		}
	}
	catch (const std::exception& e)
	{
		failed = true;
		failure = e.what();
	}
	progress.clear();
	// Nothing arrives any more: the counts below are final. A sensor thread stuck inside its driver is left
	// running, and the process ends without static destructors once everything is written.
	const std::size_t stuckSensors = sensors ? sensors->stop() : 0;
	if (stuckSensors)
		std::cerr << "pm-slam-app: warning: " << stuckSensors
				  << " sensor thread(s) did not return from their driver within 3 s of the stop\n";
	if (recorder)
	{
		try
		{
			recorder->close();
		}
		catch (const std::exception& e)
		{
			std::cerr << "pm-slam-app: --record " << args.record << ": " << e.what() << "\n";
			recordFailed = true;
		}
	}
	applySmoothedPoses(true);  // the last scans' poses wait for a look-ahead that will not come
	// The online poses as they were; the final ones follow the optimised pose graph.
	const pmslam::Trajectory online = traj;
	const auto finishStart = std::chrono::steady_clock::now();
	try
	{
		slam.finishLoopClosure();
		traj = corrected(traj);
	}
	catch (const std::exception& e)
	{
		failed = true;
		failure = std::string("loop closure: ") + e.what();
	}
	const double finishS = std::chrono::duration<double>(std::chrono::steady_clock::now() - finishStart).count();
	const double wallS = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();

	if (traj.empty() && !g_stop && !failed)
	{
		const auto& st = reader->stats();
		std::cerr << "pm-slam-app: no laser scan in '" << args.log << "' (" << st.linesOrObjects
				  << " lines/objects read, " << st.skipped
				  << " skipped): expected FLASER/RLASER/ROBOTLASER1 lines or CObservation2DRangeScan objects (or 3D "
					 "observations to slice: CObservation3DRangeScan, CObservationPointCloud, CObservationVelodyneScan)\n";
		return 2;
	}
	// --live and --follow end with Ctrl-C (or SIGTERM): their normal end, not an interruption.
	const bool openEnded = live || !args.follow.empty();
	if (g_stop && !openEnded)
		std::cerr << "pm-slam-app: interrupted after " << traj.size() << " scans: writing what was computed\n";
	if (failed)
		std::cerr << "pm-slam-app: error after " << traj.size() << " scans: " << failure
				  << ": writing what was computed\n";

	// Tracking: every stretch without an accepted match longer than a few seconds of log is said
	// loudly, with its time span; the longest decides the exit status (--max-untracked).
	double longestUntracked = 0;
	std::size_t untrackedSpans = 0;
	for (const auto& g : slam.trackingGaps())
	{
		const double span = std::isfinite(g.to - g.from) ? g.to - g.from : 0.0;
		longestUntracked = std::max(longestUntracked, span);
		if (span <= kWarnUntrackedSeconds) continue;
		++untrackedSpans;
		std::fprintf(stderr,
					 "pm-slam-app: warning: tracking lost from t=%.3f to t=%.3f (%.1f s of log, %zu rejected matches%s): "
					 "those poses follow odometry only and their scans are not in the map\n",
					 g.from, g.to, span, g.scans, g.open ? ", until the end of the log" : "");
	}
	const bool trackingLost = longestUntracked > args.maxUntracked;

	std::ostringstream header;
	header << "pm-slam-app " << args.log << " (" << traj.size() << " scans)";
	if (!args.localize.empty()) header << " localised on " << args.localize;
	try
	{
		writeOutputs(args.out, slam, traj, online, timing, header.str(), !args.localize.empty());
	}
	catch (const std::exception& e)
	{
		std::cerr << "pm-slam-app: cannot write outputs to " << args.out << ": " << e.what() << "\n";
		return 1;
	}
	if ((g_stop && !openEnded) || failed)
		std::cerr << "pm-slam-app: wrote the map and the trajectory of " << traj.size() << " scans to " << args.out
				  << "\n";

	if (!args.quiet)
	{
		const auto mb = [](std::size_t bytes) {
			char b[32];
			std::snprintf(b, sizeof b, "%.1f MB", double(bytes) / (1024.0 * 1024.0));
			return std::string(b);
		};
		std::vector<double> total;
		total.reserve(timing.size());
		for (const auto& t : timing) total.push_back(t.matchMs + t.updateMs);
		const double sumMs = std::accumulate(total.begin(), total.end(), 0.0);
		const double logSpan = traj.size() > 1 ? traj.back().timestamp - traj.front().timestamp : 0.0;
		const auto& st = reader->stats();
		std::printf("pm-slam-app: %s\n", args.log.c_str());
		std::printf("  scans %zu, matched %zu, inserted %zu, odometry readings %zu, skipped %zu, warnings %zu\n",
					traj.size(), slam.scansMatched(), slam.scansInserted(), st.odometry, st.skipped, st.warnings);
		std::printf("  tracking: %s; %zu matches rejected, %zu wide searches, %zu re-localisations, %zu scans inserted "
					"at the odometry pose on new ground, longest span without an accepted match %.1f s (%zu over %.0f s)\n",
					trackingLost ? "LOST (exit status 3)" : "ok", slam.scansRejected(), slam.wideSearches(),
					slam.relocalizations(), slam.reanchorings(), longestUntracked, untrackedSpans, kWarnUntrackedSeconds);
		if (const auto* lc = slam.loopClosure())
		{
			const auto& ls = lc->stats();
			std::printf("  loop closure: %zu loops closed; loop edges %zu accepted, %zu of them rejected by the chi-square "
						"test (%zu matches verified in %zu attempts, %zu dropped as look-alikes of another visit); %zu revisit edges (front-end matches onto an earlier "
						"visit), %zu of them rejected; %zu optimisations, %zu map updates (%zu keyframes re-inserted, %zu blocks "
						"rebuilt); back-end %.2f s on its thread "
						"(optimiser %.2f s), front-end waited %.2f s; graph: %s/graph.graph\n",
						ls.closures, ls.accepted, ls.rejected, ls.verified, ls.attempts, ls.ambiguous, ls.revisits, ls.revisitsRejected,
						ls.optimizations, ls.mapUpdates, ls.reinserted, ls.blocksReplaced, ls.backendSeconds, ls.optimizeSeconds, ls.waitSeconds,
						args.out.c_str());
		}
		if (live)
		{
			const auto c = pending->counts();
			std::printf("  live: %zu objects received (%zu scans) from %s; %zu scans processed, %zu dropped because the "
						"SLAM was behind (at most %zu pending); latency from a scan's timestamp to its pose: p50 %.1f ms, "
						"p99 %.1f ms, max %.1f ms\n",
						c.received, c.scans, args.live.c_str(), traj.size(), c.droppedScans, args.maxPending,
						pmslam::percentile(latencyMs, 0.5), pmslam::percentile(latencyMs, 0.99),
						latencyMs.empty() ? 0.0 : *std::max_element(latencyMs.begin(), latencyMs.end()));
			if (recorder)
				std::printf("  recorded %zu objects to %s%s\n", recorder->objects(), args.record.c_str(),
							recordFailed ? " (INCOMPLETE: writing failed)"
							: c.droppedScans ? " (it holds the dropped scans too: an offline run on it maps them)"
											 : " (pm-slam-app on it reproduces this trajectory)");
		}
		if (args.snapshotEvery > 0)
			std::printf("  %zu snapshots written to %s (every %.1f s)\n", snapshots, args.out.c_str(), args.snapshotEvery);
		std::printf("  time per scan (match + map update): mean %.3f ms, median %.3f ms, p99 %.3f ms\n",
					total.empty() ? 0.0 : sumMs / total.size(), pmslam::percentile(total, 0.5), pmslam::percentile(total, 0.99));
		// Whole-log processing: the front-end plus its waits for the back-end (and the final optimisation).
		double waitMs = 0;
		for (const auto& t : timing) waitMs += t.backendMs;
		const double slamS = (sumMs + waitMs) / 1000.0 + finishS;
		std::printf("  SLAM time %.2f s (front-end %.2f s, waiting for the back-end %.2f s), wall time %.2f s, "
					"realtime factor %.0fx\n",
					slamS, sumMs / 1000.0, slamS - sumMs / 1000.0, wallS, slamS > 0 && logSpan > 0 ? logSpan / slamS : 0.0);
		// The process's peak includes MRPT's shared libraries (~100 MB mapped and relocated at
		// start-up, before any data); the map's own memory is reported beside it.
		const auto now = pmslam::residentMemoryNow();
		const double res = slam.grid().updateOptions().resolution;
		std::printf(
			"  peak memory %.1f MB (at the end: %.1f MB own, %.1f MB mapped library files, %.1f MB of start-up "
			"library pages given back; map: %.0f m² observed, grid %.1f MB + distance layer %.1f MB%s)\n",
			pmslam::peakResidentMemoryMB(), now.anonymousMB, now.fileMB, releasedMB,
			slam.grid().cells().observedCells() * res * res, slam.grid().cells().memoryBytes() / (1024.0 * 1024.0),
			slam.grid().distanceMap().memoryBytes() / (1024.0 * 1024.0),
			slam.loopClosure() ? (", loop closure " + mb(slam.loopClosure()->memoryBytes())).c_str() : "");
		if (!args.localize.empty())
			std::printf("  localised on %s (unchanged): %s/map.png, trajectory: %s/trajectory.txt\n",
						args.localize.c_str(), args.out.c_str(), args.out.c_str());
		else
			std::printf("  map: %s/map.png (and map.pgm/.yaml, map.gridmap.gz, map.simplemap.gz), trajectory: %s/trajectory.txt\n",
						args.out.c_str(), args.out.c_str());
	}
	int status = 0;
	if (failed) status = 1;
	else if (g_stop && !openEnded) status = 130;
	else if (trackingLost)
	{
		std::fprintf(stderr, "pm-slam-app: tracking was lost for %.1f s of log (more than --max-untracked %.1f s): exit status 3\n",
					 longestUntracked, args.maxUntracked);
		status = 3;
	}
	// Everything said so far must survive whatever the GUI toolkit does at exit.
	std::fflush(stdout);
	std::fflush(stderr);
	if (stuckSensors) std::_Exit(status);
	if (window)
	{
		window->show(pmslam::renderMap(slam.grid(), traj, {}, loopLinks(), kGuiMaxSide));
		std::cout << "Close the window or press a key in it to exit." << std::endl;
		window->waitForKey();  // returns at once when the window is closed
		window.reset();
		// MRPT runs wxWidgets in a detached thread that may still be tearing GTK down when this
		// process's static destructors run (a SIGSEGV at exit now and then): every output is
		// written and flushed, so leave without them.
		std::fflush(nullptr);
		std::_Exit(status);
	}
	return status;
}
