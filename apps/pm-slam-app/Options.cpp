/* pm-slam-app — the command line (see Options.h). */
#include "Options.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "../common/CommandLine.h"
#include "../common/Message.h"

namespace pmslam_app
{
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

options (before or after LOG; an option's value may also follow it after '=': --out=DIR):
  --config FILE           INI configuration (sections [PerfectMatch], [MappingApplication], [LoopClosure],
                          [Log]; every key is documented in config/default.ini). An MRPT icp-slam INI file
                          works too: what means the same is read (its rawlog_file is the LOG and its
                          logOutput_dir the --out when none is given), the rest is named in a note
  --set SECTION.KEY=VALUE override one configuration key (repeatable)
  --out DIR               output folder (default ./pmslam-out); files of an earlier run that this run does
                          not write are removed (only pm-slam-app's own output names, said on stderr)
  --max-scans N           stop after N scans (0 = all)
  --localize MAP          track the robot on a fixed prior map without changing it: a ROS map.yaml, an MRPT
                          .gridmap[.gz] or .simplemap[.gz], or a pm-slam-app output folder; writes
                          trajectory.txt, timing.txt and map.png (the fixed map with the path). Without
                          --initial-pose the start is searched over the whole map from the first scans
  --continue DIR          continue the map of an earlier run's output folder DIR (never modified): the start
                          is searched on DIR's map, the map and loops grow on, and --out holds the map, the
                          pose graph and the trajectory of every session so far (trajectory.txt's header
                          says which poses are which session)
  --lifelong              with --continue: the earlier keyframes this run covers (within 0.5 m and 30 deg)
                          are retired and the map rebuilt without them, so it shows what changed (moved
                          furniture) and its keyframes follow the area, not the hours driven
  --initial-pose X,Y,YAW_DEG  start pose on the --localize or --continue map (m, m, degrees), if known
  --gui                   live view of map, scan and trajectory (needs a display); at the end the final map
                          stays shown until the window is closed or a key is pressed in it
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

[[noreturn]] void usageError(const std::string& msg)
{
	say(msg + " (see --help)");
	std::exit(2);
}

/** The words of the command line, one at a time, with the checks every option's value gets. */
class Words
{
   public:
	explicit Words(std::vector<std::string> words) : m_words(std::move(words)) {}
	bool next() { return ++m_at < m_words.size(); }
	const std::string& word() const { return m_words[m_at]; }
	std::string value(const std::string& name)
	{
		if (m_at + 1 >= m_words.size()) usageError(name + " needs a value");
		return m_words[++m_at];
	}
	std::size_t wholeNumber(const std::string& name, long least)
	{
		const std::string v = value(name);
		char* end = nullptr;
		const long n = std::strtol(v.c_str(), &end, 10);
		if (end == v.c_str() || *end || n < least)
			usageError(name + " '" + v + "': expected a whole number >= " + std::to_string(least));
		return static_cast<std::size_t>(n);
	}
	double seconds(const std::string& name)
	{
		const std::string v = value(name);
		char* end = nullptr;
		const double x = std::strtod(v.c_str(), &end);
		if (end == v.c_str() || *end || !(x >= 0) || !std::isfinite(x))
			usageError(name + " '" + v + "': expected seconds >= 0");
		return x;
	}
	mrpt::math::TPose2D pose(const std::string& name)
	{
		const std::string v = value(name);
		double x = 0, y = 0, yawDeg = 0;
		char tail = 0;
		if (std::sscanf(v.c_str(), "%lf,%lf,%lf%c", &x, &y, &yawDeg, &tail) != 3 || !std::isfinite(x + y + yawDeg))
			usageError(name + " '" + v + "': expected X,Y,YAW_DEG (m, m, degrees), e.g. 1.5,-2,90");
		return {x, y, mrpt::DEG2RAD(yawDeg)};
	}

   private:
	std::vector<std::string> m_words;
	std::size_t m_at = std::size_t(-1);
};

/** One option (and its value); false when `s` is none of them. */
bool takeOption(const std::string& s, Words& w, Options& a, bool& initialPoseGiven)
{
	if (s == "--config") a.config = w.value(s);
	else if (s == "--set") a.sets.push_back(w.value(s));
	else if (s == "--out") a.out = w.value(s), a.outGiven = true;
	else if (s == "--max-scans") a.maxScans = w.wholeNumber(s, 0);
	else if (s == "--localize") a.localize = w.value(s);
	else if (s == "--continue") a.continueFrom = w.value(s);
	else if (s == "--initial-pose") a.initialPose = w.pose(s), initialPoseGiven = true;
	else if (s == "--max-untracked") a.maxUntracked = w.seconds(s);
	else if (s == "--live") a.live = w.value(s);
	else if (s == "--follow") a.follow = w.value(s);
	else if (s == "--follow-timeout") a.followTimeout = w.seconds(s);
	else if (s == "--record") a.record = w.value(s);
	else if (s == "--snapshot-every") a.snapshotEvery = w.seconds(s);
	else if (s == "--connect-timeout") a.connectTimeout = w.seconds(s);
	else if (s == "--max-pending") a.maxPending = w.wholeNumber(s, 1);
	else if (s == "--lifelong") a.lifelong = true;
	else if (s == "--gui") a.gui = true;
	else if (s == "--quiet") a.quiet = true;
	else if (s == "--progress") a.progress = 1;
	else if (s == "--no-progress") a.progress = 0;
	else return false;
	return true;
}

/** The options that exclude or need each other, and what LOG is. */
void checkCombination(Options& a, std::vector<std::string> positional, bool initialPoseGiven)
{
	if (positional.size() > 1) usageError("expected one LOG, got " + std::to_string(positional.size()));
	if (initialPoseGiven && a.localize.empty() && a.continueFrom.empty())
		usageError("--initial-pose needs --localize MAP or --continue DIR");
	if (a.lifelong && a.continueFrom.empty()) usageError("--lifelong needs --continue DIR (the map whose keyframes give way)");
	if (!a.localize.empty() && !a.continueFrom.empty())
		usageError("--localize and --continue exclude each other: localise on a map, or continue it");
	if (!a.live.empty() && !a.follow.empty()) usageError("--live and --follow exclude each other");
	if ((!a.live.empty() || !a.follow.empty()) && !positional.empty())
		usageError(std::string(a.live.empty() ? "--follow" : "--live") + " takes the place of LOG: give one or the other");
	if (!a.record.empty() && a.live.empty()) usageError("--record needs --live (a log is its own recording)");
	if (a.snapshotEvery < 0) a.snapshotEvery = (a.live.empty() && a.follow.empty()) ? 0 : 5;
	if (!a.follow.empty()) positional.push_back(a.follow);
	a.log = !a.live.empty() ? a.live : positional.empty() ? kDefaultLog : positional[0];
	a.logGiven = !positional.empty() || !a.live.empty();
}
}  // namespace

void say(const std::string& message) { std::cerr << "pm-slam-app: " << withoutLibraryPrefix(message) << "\n"; }

Options parseOptions(int argc, char** argv)
{
	Options a;
	std::vector<std::string> positional;
	bool initialPoseGiven = false;
	Words w(splitOptionValues(argc, argv,
							  {"--config", "--set", "--out", "--max-scans", "--localize", "--continue", "--initial-pose",
							   "--max-untracked", "--live", "--follow", "--follow-timeout", "--record",
							   "--snapshot-every", "--connect-timeout", "--max-pending"}));
	while (w.next())
	{
		const std::string s = w.word();
		if (s == "-h" || s == "--help")
		{
			std::printf(kUsage, kDefaultLog);
			std::exit(0);
		}
		if (takeOption(s, w, a, initialPoseGiven)) continue;
		if (s.size() > 1 && s[0] == '-') usageError("unknown option '" + s + "'");
		positional.push_back(s);
	}
	checkCombination(a, positional, initialPoseGiven);
	a.initialPoseGiven = initialPoseGiven;
	return a;
}

void takeIcpSlamNames(Options& a, const pmslam::SlamConfig& cfg)
{
	if (!a.logGiven && !cfg.icpSlamLogFile.empty())
	{
		namespace fs = std::filesystem;
		fs::path p = cfg.icpSlamLogFile;
		// As icp-slam: relative to the working directory; MRPT's sample files name it relative to themselves.
		const fs::path besideIni = fs::path(a.config).parent_path() / p;
		if (p.is_relative() && !fs::exists(p) && fs::exists(besideIni)) p = besideIni;
		a.log = p.string();
	}
	if (!a.outGiven && !cfg.icpSlamOutputDir.empty()) a.out = cfg.icpSlamOutputDir;
}

}  // namespace pmslam_app
