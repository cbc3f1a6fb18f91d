/* pm-icp-slam — MRPT's ICP SLAM (mrpt::slam::CMetricMapBuilderICP) run on
 * exactly the scans pm-slam-app sees, as the peer of the side-by-side
 * benchmark (bench/run.sh).
 *
 *   pm-icp-slam --config FILE [--out DIR] [--max-scans N] LOG
 *
 * The log is read with pmslam::LogReader (so Carmen logs get the corrected
 * timestamps, fan geometry and "no return" handling). The builder receives an
 * observation-only stream, the way MRPT's icp-slam feeds it from an
 * observation-only rawlog: before every scan one CObservationOdometry with the
 * odometry pose belonging to that scan, then the CObservation2DRangeScan, both
 * through processObservation(). The odometry is the one pm-slam-app uses: the
 * pose written on the Carmen laser line when there is one, otherwise the
 * latest odometry reading of the log.
 */
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/slam/CMetricMapBuilderICP.h>
#include <mrpt/system/COutputLogger.h>
#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/slam/OdometrySelector.h>
#include <pmslam/util/RunStatistics.h>
#include <pmslam/io/Trajectory.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../common/CommandLine.h"
#include "../common/Message.h"

namespace
{
const char* kProg = "pm-icp-slam";

const char* kUsage =
	R"(usage: pm-icp-slam --config FILE [options] LOG

MRPT's ICP SLAM (CMetricMapBuilderICP) on a robot log, for comparison with
pm-slam-app on the same scans. LOG is an MRPT .rawlog or a Carmen log
(.clf/.log), read exactly as pm-slam-app reads it.

options (before or after LOG; a value may also follow after '=': --out=DIR):
  --config FILE    INI file in the format of MRPT's icp-slam: [MappingApplication]
                   (CMetricMapBuilderICP::TConfigParams and the map initializers,
                   alwaysInsertByClass) and [ICP] (CICP::TConfigParams); optional
                   [Log] noReturnRange, odometrySource = auto|scan|events as in
                   pm-slam-app. Required.
  --out DIR        output folder (default ./pm-icp-slam-out)
  --max-scans N    stop after N scans (0 = all)
  --quiet          no summary, only warnings and errors
  -h, --help       this text

outputs in DIR: trajectory.txt (timestamp x y yaw, one line per scan, the
builder's pose after the scan), timing.txt (timestamp and milliseconds spent
in the builder per scan). Exit status: 0 done, 2 bad input or configuration,
1 failure while running, 130 interrupted (outputs still written).
)";

std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

struct Args
{
	std::string log, config, out = "pm-icp-slam-out";
	std::size_t maxScans = 0;
	bool quiet = false;
};

[[noreturn]] void usageError(const std::string& msg)
{
	std::cerr << kProg << ": " << msg << " (see --help)\n";
	std::exit(2);
}

Args parseArgs(int argc, char** argv)
{
	Args a;
	std::vector<std::string> positional;
	const auto words = pmslam_app::splitOptionValues(argc, argv, {"--config", "--out", "--max-scans"});
	for (std::size_t i = 0; i < words.size(); ++i)
	{
		const std::string& s = words[i];
		auto value = [&](const char* name) -> std::string {
			if (i + 1 >= words.size()) usageError(std::string(name) + " needs a value");
			return words[++i];
		};
		if (s == "-h" || s == "--help")
		{
			std::fputs(kUsage, stdout);
			std::exit(0);
		}
		else if (s == "--config") a.config = value("--config");
		else if (s == "--out") a.out = value("--out");
		else if (s == "--max-scans")
		{
			const std::string v = value("--max-scans");
			char* end = nullptr;
			const long n = std::strtol(v.c_str(), &end, 10);
			if (v.empty() || end == v.c_str() || *end || n < 0)
				usageError("--max-scans '" + v + "': expected a whole number >= 0");
			a.maxScans = static_cast<std::size_t>(n);
		}
		else if (s == "--quiet") a.quiet = true;
		else if (s.size() > 1 && s[0] == '-') usageError("unknown option '" + s + "'");
		else positional.push_back(s);
	}
	if (a.config.empty()) usageError("--config FILE is required");
	if (positional.size() != 1) usageError("expected one LOG, got " + std::to_string(positional.size()));
	a.log = positional[0];
	return a;
}

/** One line out of an exception text: MRPT's span several lines (banner,
 * message, location, call stack); keep the message only. */
std::string oneLine(const std::string& what)
{
	std::string s;
	for (const char c : what)
	{
		const char d = (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
		if (d == ' ' && (s.empty() || s.back() == ' ')) continue;
		s += d;
	}
	if (const auto m = s.find("Message:"); m != std::string::npos) s = s.substr(m + 8);
	for (const char* cut : {" Location:", " Call stack", " ===="})
		if (const auto k = s.find(cut); k != std::string::npos) s.resize(k);
	while (!s.empty() && s.front() == ' ') s.erase(s.begin());
	while (!s.empty() && s.back() == ' ') s.pop_back();
	return pmslam_app::withoutLibraryPrefix(s);
}

/** Everything read from --config. */
struct IcpSlamConfig
{
	mrpt::config::CConfigFileMemory ini;
	pmslam::LogReaderOptions log;
	pmslam::OdometrySource odometry = pmslam::OdometrySource::Auto;
	bool verbositySet = false;
};

/** Reads and checks the INI file; throws std::runtime_error with one line. */
void loadConfig(const std::string& path, IcpSlamConfig& cfg)
{
	namespace fs = std::filesystem;
	std::error_code ec;
	if (!fs::exists(path, ec)) throw std::runtime_error("--config " + path + ": no such file");
	if (fs::is_directory(path, ec)) throw std::runtime_error("--config " + path + ": is a directory, expected an INI file");
	std::ifstream in(path, std::ios::binary);
	if (!in) throw std::runtime_error("--config " + path + ": cannot open");
	const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
	cfg.ini.setContent(text);
	if (!cfg.ini.sectionExists("MappingApplication"))
		throw std::runtime_error("--config " + path + ": no [MappingApplication] section (MRPT icp-slam format expected)");

	cfg.log.noReturnRange = cfg.ini.read_double("Log", "noReturnRange", cfg.log.noReturnRange);
	if (!(cfg.log.noReturnRange > 0)) throw std::runtime_error("--config " + path + ": [Log] noReturnRange: expected > 0 m");
	try
	{
		cfg.odometry = pmslam::odometrySourceFromName(cfg.ini.read_string("Log", "odometrySource", "auto"));
	}
	catch (const std::invalid_argument& e)
	{
		throw std::runtime_error("--config " + path + ": [Log] odometrySource = " + e.what());
	}
	cfg.verbositySet = cfg.ini.keyExists("MappingApplication", "verbosity_level");
}

/** Counts the builder's warnings (low-quality ICP rejected, ...) without printing them. */
struct WarningCounter
{
	std::size_t icpRejected = 0, other = 0;
};
WarningCounter* g_warnings = nullptr;

void countWarning(std::string_view msg, mrpt::system::VerbosityLevel level, std::string_view, mrpt::Clock::time_point)
{
	if (!g_warnings || level < mrpt::system::LVL_WARN) return;
	if (msg.find("low quality") != std::string_view::npos) ++g_warnings->icpRejected;
	else ++g_warnings->other;
}

/** The builder configured from --config: quiet by default, counting its warnings (per-scan INFO output
 * would dominate the timing); a verbosity_level in the INI wins. Exits 2 with one line on a bad file. */
void configureOrExit(const Args& args, IcpSlamConfig& cfg, mrpt::slam::CMetricMapBuilderICP& builder,
					 WarningCounter& warnings)
{
	try
	{
		loadConfig(args.config, cfg);
		builder.setMinLoggingLevel(mrpt::system::LVL_WARN);
		builder.ICP_options.loadFromConfigFile(cfg.ini, "MappingApplication");
		builder.ICP_params.loadFromConfigFile(cfg.ini, "ICP");
		builder.options.alwaysInsertByClass.fromString(cfg.ini.read_string("MappingApplication", "alwaysInsertByClass", ""));
		if (builder.ICP_options.mapInitializers.size() == 0)
			throw std::runtime_error("--config " + args.config +
									 ": [MappingApplication] creates no map (set pointsMap_count=1 and/or occupancyGrid_count=1)");
		builder.initialize();
		const auto* maps = builder.getCurrentlyBuiltMetricMap();
		if (!maps || !maps->mapByClass<mrpt::maps::CPointsMap>())
			if (!(builder.ICP_options.matchAgainstTheGrid && maps && maps->mapByClass<mrpt::maps::COccupancyGridMap2D>()))
				throw std::runtime_error("--config " + args.config +
										 ": ICP needs a points map (pointsMap_count >= 1) or matchAgainstTheGrid with a grid map");
	}
	catch (const std::exception& e)
	{
		const std::string msg = oneLine(e.what());
		if (msg.rfind("--config", 0) == 0) std::cerr << kProg << ": " << msg << "\n";
		else std::cerr << kProg << ": --config " << args.config << ": " << msg << "\n";
		std::exit(2);
	}
	if (!cfg.verbositySet)
	{
		builder.logging_enable_console_output = false;
		g_warnings = &warnings;
		builder.setVerbosityLevelForCallbacks(mrpt::system::LVL_WARN);
		builder.logRegisterCallback(&countWarning);
	}
}

/** What the run computed. */
struct Run
{
	pmslam::Trajectory traj;
	std::vector<double> timingMs;
	std::size_t odometryFed = 0;
	bool failed = false;
	std::string failure;
};

/** Feeds one scan to the builder as MRPT's icp-slam does from an observation-only rawlog: the odometry
 * belonging to it first (if any), then the scan. Returns the ms spent in the builder. */
double feedScan(mrpt::slam::CMetricMapBuilderICP& builder, pmslam::LogEvent& ev,
				const std::optional<mrpt::math::TPose2D>& odo, double& lastOdoStamp)
{
	// Carmen ipc_timestamps may repeat or step back (intel: up to 0.9 s):
	// keep the builder's clock strictly increasing, by 10 us (MRPT's
	// timeDifference() resolves whole microseconds only).
	double stamp = ev.timestamp;
	if (odo && stamp < lastOdoStamp + 1e-5) stamp = lastOdoStamp + 1e-5;
	const auto when = mrpt::Clock::fromDouble(stamp);
	mrpt::obs::CObservationOdometry::Ptr odoObs;
	if (odo)
	{
		odoObs = mrpt::obs::CObservationOdometry::Create();
		odoObs->timestamp = when;
		odoObs->sensorLabel = "ODOMETRY";
		odoObs->odometry = mrpt::poses::CPose2D(*odo);
		odoObs->hasVelocities = false;
		lastOdoStamp = stamp;
	}
	ev.scan->timestamp = when;
	if (ev.scan->sensorLabel.empty()) ev.scan->sensorLabel = "LASER";
	const auto t0 = std::chrono::steady_clock::now();
	if (odoObs) builder.processObservation(odoObs);
	builder.processObservation(ev.scan);
	return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/** Every scan of the log through the builder, until the end, --max-scans or a stop. */
Run runLog(pmslam::LogReader& reader, mrpt::slam::CMetricMapBuilderICP& builder, pmslam::OdometrySource source,
		   const Args& args)
{
	Run run;
	const bool progress = !args.quiet && isatty(STDERR_FILENO);
	const std::size_t estimated = reader.estimatedScanCount();
	pmslam::OdometrySelector odometry(source);
	double lastOdoStamp = -1e300;  // CRobot2DPoseEstimator wants strictly increasing odometry stamps
	try
	{
		pmslam::LogEvent ev;
		while (!g_stop && reader.next(ev))
		{
			if (ev.kind == pmslam::LogEvent::Kind::Odometry)
			{
				odometry.takeReading(ev);
				continue;
			}
			const auto odo = odometry.forScan(ev);
			run.timingMs.push_back(feedScan(builder, ev, odo, lastOdoStamp));
			if (odo) ++run.odometryFed;
			const auto pose = builder.getCurrentPoseEstimation()->getMeanVal();
			run.traj.push_back({ev.timestamp, pose.x(), pose.y(), pose.yaw()});
			if (progress && run.traj.size() % 100 == 0)
			{
				std::fprintf(stderr, "\r%s: %zu", kProg, run.traj.size());
				if (estimated) std::fprintf(stderr, "/%zu", estimated);
				std::fprintf(stderr, " scans ");
			}
			if (args.maxScans && run.traj.size() >= args.maxScans) break;
		}
	}
	catch (const std::exception& e)
	{
		run.failed = true;
		run.failure = oneLine(e.what());
	}
	if (progress) std::fprintf(stderr, "\r%*s\r", 40, "");
	return run;
}

/** trajectory.txt and timing.txt; false when writing failed (said). */
bool writeOutputs(const Args& args, const Run& run)
{
	namespace fs = std::filesystem;
	std::ostringstream header;
	header << kProg << " --config " << args.config << " " << args.log << " (" << run.traj.size() << " scans)";
	try
	{
		pmslam::saveTrajectory((fs::path(args.out) / "trajectory.txt").string(), run.traj,
							   header.str() + "\nposes of the robot base in the map frame (m, m, rad)");
		pmslam::writeFileAtomically((fs::path(args.out) / "timing.txt").string(), [&](std::ostream& out) {
			out << "# " << header.str() << "\n# timestamp ms\n";
			char line[96];
			for (std::size_t i = 0; i < run.traj.size(); ++i)
			{
				std::snprintf(line, sizeof line, "%.6f %.4f\n", run.traj[i].timestamp, run.timingMs[i]);
				out << line;
			}
		});
	}
	catch (const std::exception& e)
	{
		std::cerr << kProg << ": cannot write outputs to " << args.out << ": " << oneLine(e.what()) << "\n";
		return false;
	}
	return true;
}

void printSummary(const Args& args, const Run& run, const pmslam::LogReadStats& st,
				  mrpt::slam::CMetricMapBuilderICP& builder, const WarningCounter& warnings, double wallS)
{
	const auto& traj = run.traj;
	const double sumMs = std::accumulate(run.timingMs.begin(), run.timingMs.end(), 0.0);
	const double logSpan = traj.size() > 1 ? traj.back().timestamp - traj.front().timestamp : 0.0;
	std::printf("%s: %s\n", kProg, args.log.c_str());
	std::printf("  scans %zu, keyframes %u, ICP rejected (low goodness) %zu, odometry readings %zu (fed %zu), skipped %zu, warnings %zu\n",
				traj.size(), builder.getCurrentlyBuiltMapSize(), warnings.icpRejected, st.odometry, run.odometryFed,
				st.skipped, st.warnings);
	std::printf("  time per scan (ICP + map update): mean %.3f ms, median %.3f ms, p99 %.3f ms\n",
				run.timingMs.empty() ? 0.0 : sumMs / run.timingMs.size(), pmslam::percentile(run.timingMs, 0.5),
				pmslam::percentile(run.timingMs, 0.99));
	std::printf("  SLAM time %.2f s, wall time %.2f s, realtime factor %.0fx, peak memory %.1f MB\n", sumMs / 1000.0,
				wallS, sumMs > 0 && logSpan > 0 ? logSpan / (sumMs / 1000.0) : 0.0, pmslam::peakResidentMemoryMB());
	std::printf("  trajectory: %s/trajectory.txt, timing: %s/timing.txt\n", args.out.c_str(), args.out.c_str());
}

}  // namespace

int main(int argc, char** argv)
{
	const Args args = parseArgs(argc, argv);
	IcpSlamConfig cfg;
	mrpt::slam::CMetricMapBuilderICP builder;
	WarningCounter warnings;
	configureOrExit(args, cfg, builder, warnings);
	// The log before --out: a bad log must not leave an empty folder behind.
	std::unique_ptr<pmslam::LogReader> reader;
	try
	{
		reader = pmslam::LogReader::open(args.log, cfg.log);
	}
	catch (const std::exception& e)
	{
		std::cerr << kProg << ": " << oneLine(e.what()) << "\n";
		return 2;
	}
	try
	{
		pmslam::checkDirectoryWritable(args.out);
	}
	catch (const std::exception& e)
	{
		std::cerr << kProg << ": --out " << args.out << ": " << oneLine(e.what()) << "\n";
		return 2;
	}
	reader->onWarning = [](const std::string& w) { std::cerr << kProg << ": warning: " << w << "\n"; };
	std::signal(SIGINT, onSignal);
	std::signal(SIGTERM, onSignal);

	const auto wallStart = std::chrono::steady_clock::now();
	const Run run = runLog(*reader, builder, cfg.odometry, args);
	const double wallS = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
	if (g_stop) std::cerr << kProg << ": interrupted after " << run.traj.size() << " scans: writing what was computed\n";
	if (run.failed)
		std::cerr << kProg << ": error after " << run.traj.size() << " scans: " << run.failure
				  << ": writing what was computed\n";
	if (!writeOutputs(args, run)) return 1;
	if (!args.quiet) printSummary(args, run, reader->stats(), builder, warnings, wallS);
	if (run.failed) return 1;
	if (g_stop) return 130;
	return 0;
}
