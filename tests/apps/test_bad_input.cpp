// pm-slam-app on bad input: missing, unreadable, empty or unknown logs, bad
// configuration, unusable --out, damaged Carmen lines and rawlogs, and an
// interruption mid-run. Every refusal is one line naming what is wrong, exit
// code 2; every damaged or interrupted run still writes complete outputs.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/io/Trajectory.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <thread>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kIntel = PMSLAM_SOURCE_DIR "/../shared/datasets/intel/intel.clf";
const char* const kOutputs[] = {"trajectory.txt", "timing.txt",		 "map.png",			 "map.pgm",
								"map.yaml",		  "map.gridmap.gz", "map.simplemap.gz"};

RunResult app(const std::string& args) { return run(quote(kApp) + " " + args); }

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

/** Exactly one line of output, containing every fragment; exit code 2. */
void expectRefusal(const RunResult& r, std::initializer_list<std::string> fragments)
{
	EXPECT_EQ(r.exitCode, 2) << r.output;
	ASSERT_FALSE(r.output.empty());
	EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "more than one line:\n" << r.output;
	EXPECT_EQ(r.output.rfind("pm-slam-app: ", 0), 0u) << r.output;
	for (const auto& f : fragments) EXPECT_TRUE(contains(r.output, f)) << "'" << f << "' not in: " << r.output;
}

/** Every output exists; trajectory and timing have one line per scan. */
void expectCompleteOutputs(const fs::path& out, std::size_t scans)
{
	for (const char* f : kOutputs)
	{
		ASSERT_TRUE(fs::exists(out / f)) << f;
		EXPECT_GT(fs::file_size(out / f), 0u) << f;
	}
	EXPECT_EQ(countDataLines(out / "trajectory.txt"), scans);
	EXPECT_EQ(countDataLines(out / "timing.txt"), scans);
	EXPECT_EQ(pmslam::loadTrajectory((out / "trajectory.txt").string()).size(), scans);
	mrpt::maps::COccupancyGridMap2D grid;
	pmslam::loadGridMapGz((out / "map.gridmap.gz").string(), grid);
	EXPECT_GT(grid.getSizeX(), 0u);
	for (const auto& e : fs::directory_iterator(out))  // no temporary file left behind
		EXPECT_FALSE(contains(e.path().filename().string(), ".tmp.")) << e.path();
}

/** The number N of "scans N," in the summary. */
std::size_t summaryScans(const std::string& output)
{
	const auto p = output.find("  scans ");
	if (p == std::string::npos) return static_cast<std::size_t>(-1);
	return std::stoul(output.substr(p + 8));
}

/** A small valid Carmen log of the furnished room (FLASER lines, odometry = truth). */
std::string roomCarmen(std::size_t n = 60)
{
	const auto truth = roomPath(n);
	return carmenLog(furnishedRoom(), truth, truth, CarmenLogSpec{});
}

std::vector<std::string> lines(const std::string& text)
{
	std::vector<std::string> v;
	std::istringstream in(text);
	for (std::string l; std::getline(in, l);) v.push_back(l);
	return v;
}

/** `line` with its whitespace-separated field `i` replaced by `value`. */
std::string withField(const std::string& line, std::size_t i, const std::string& value)
{
	std::istringstream in(line);
	std::vector<std::string> f;
	for (std::string w; in >> w;) f.push_back(w);
	f.at(i) = value;
	std::string out;
	for (const auto& w : f) out += (out.empty() ? "" : " ") + w;
	return out;
}

std::string join(const std::vector<std::string>& v)
{
	std::string s;
	for (const auto& l : v) s += l + "\n";
	return s;
}
}  // namespace

// ---------------------------------------------------------------- the LOG argument

TEST(BadInput, MissingLog)
{
	ScratchDir d("bad-missing");
	const auto out = d.path("out");
	const auto r = app("--out " + quote(out) + " " + quote(d.path("no-such-log.clf")));
	expectRefusal(r, {d.path("no-such-log.clf"), "does not exist", "expected a Carmen log"});
	EXPECT_FALSE(fs::exists(out)) << "a refused run must not create --out";
}

TEST(BadInput, LogIsADirectoryADeviceOrAFifo)
{
	ScratchDir d("bad-kind");
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(d.dir.string())),
				  {d.dir.string(), "is a directory", "expected a Carmen log"});
	expectRefusal(app("--out " + quote(d.path("out")) + " /dev/null"), {"/dev/null", "is not a regular file"});
	ASSERT_EQ(::mkfifo(d.path("fifo").c_str(), 0600), 0);
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(d.path("fifo"))),
				  {d.path("fifo"), "is not a regular file"});
}

TEST(BadInput, EmptyLog)
{
	ScratchDir d("bad-empty");
	const auto log = d.write("empty.clf", "");
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(log)), {log, "is empty", "expected a Carmen log"});
	const auto raw = d.write("empty.rawlog", "");
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(raw)), {raw, "is empty"});
}

TEST(BadInput, UnknownFormat)
{
	ScratchDir d("bad-format");
	const auto text = d.write("notes.dat", "hello world\nthis is not a robot log\n");
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(text)),
				  {text, "unknown log format", "expected a Carmen log (.clf/.log/.txt) or an MRPT .rawlog"});
	std::string bytes(3000, '\0');
	for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 7919u) % 251u);
	const auto bin = d.write("noise.bin", bytes);
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(bin)), {bin, "unknown log format"});
	const auto raw = d.write("noise.rawlog", bytes);
	expectRefusal(app("--out " + quote(d.path("out")) + " " + quote(raw)), {raw, "is not a readable MRPT rawlog"});
}

TEST(BadInput, CarmenNamedTextWithoutAnyScan)
{
	ScratchDir d("bad-noscan");
	const auto log = d.write("notes.clf", "hello\nPARAM only\n");
	const auto r = app("--out " + quote(d.path("out")) + " " + quote(log));
	expectRefusal(r, {log, "no laser scan", "expected FLASER/RLASER/ROBOTLASER1"});
	EXPECT_FALSE(fs::exists(d.dir / "out" / "trajectory.txt"));
}

TEST(BadInput, UnreadableLog)
{
	// Tests run as root, which reads any file: drop to "nobody" for the child.
	if (::geteuid() != 0) GTEST_SKIP() << "needs root to run the app as another user";
	if (run("command -v setpriv").exitCode != 0) GTEST_SKIP() << "setpriv (util-linux) not installed";
	ScratchDir d("bad-unreadable");
	fs::permissions(d.dir, fs::perms::all);
	const auto log = d.write("secret.clf", roomCarmen(5));
	fs::permissions(log, fs::perms::none);
	const std::string asNobody = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
	const auto r = run(asNobody + quote(kApp) + " --out " + quote(d.path("out")) + " " + quote(log));
	expectRefusal(r, {log, "cannot read log file", "Permission denied"});
	// A folder on the way that cannot be searched.
	const auto hidden = d.path("private");
	fs::create_directories(hidden);
	fs::permissions(hidden, fs::perms::owner_all);
	d.write("private/log.clf", roomCarmen(5));
	const auto r2 = run(asNobody + quote(kApp) + " --out " + quote(d.path("out")) + " " + quote(hidden + "/log.clf"));
	expectRefusal(r2, {hidden + "/log.clf", "cannot access log file", "Permission denied"});
}

// ---------------------------------------------------------------- configuration

TEST(BadInput, ConfigUnknownSectionAndKeyWithSuggestion)
{
	ScratchDir d("bad-config");
	const auto log = d.write("room.clf", roomCarmen(5));
	const auto ini = d.write("typo-section.ini", "[Mapping]\nresolution = 0.05\n");
	expectRefusal(app("--config " + quote(ini) + " --out " + quote(d.path("out")) + " " + quote(log)),
				  {ini, "unknown section [Mapping]", "did you mean [MappingApplication]?"});
	const auto ini2 = d.write("typo-key.ini", "[PerfectMatch]\nsigam = 0.05\n");
	expectRefusal(app("--config " + quote(ini2) + " --out " + quote(d.path("out")) + " " + quote(log)),
				  {ini2, "unknown key 'sigam' in [PerfectMatch]", "did you mean 'sigma'?"});
	expectRefusal(app("--set Log.odometrysource=scan --out " + quote(d.path("out")) + " " + quote(log)),
				  {"unknown key 'odometrysource' in [Log]", "did you mean 'odometrySource'?"});
	EXPECT_FALSE(fs::exists(d.dir / "out"));
}

TEST(BadInput, ConfigWrongTypeAndOutOfRange)
{
	ScratchDir d("bad-values");
	const auto log = d.write("room.clf", roomCarmen(5));
	const std::string tail = " --out " + quote(d.path("out")) + " " + quote(log);
	expectRefusal(app("--set PerfectMatch.sigma=abc" + tail), {"[PerfectMatch] sigma = 'abc'", "expected a number"});
	expectRefusal(app("--set PerfectMatch.sigma=-1" + tail), {"[PerfectMatch] sigma", "expected a value in"});
	expectRefusal(app("--set MappingApplication.resolution=5" + tail), {"resolution = '5'", "expected a value in 0.005..2 m"});
	expectRefusal(app("--set MappingApplication.keepSimpleMap=maybe" + tail), {"keepSimpleMap", "true or false"});
	expectRefusal(app("--set Log.odometrySource=gps" + tail), {"odometrySource = 'gps'", "auto, scan, events"});
	expectRefusal(app("--set Log.noReturnRange=0" + tail), {"noReturnRange", "> 0"});
	// Counts are plain whole numbers: MRPT would read "1e3" as 1 and "-5" as a huge unsigned value.
	expectRefusal(app("--set PerfectMatch.maxIterations=1e3" + tail), {"maxIterations = '1e3'", "whole number >= 0"});
	expectRefusal(app("--set MappingApplication.minPoints=-5" + tail), {"minPoints = '-5'", "whole number >= 0"});
	expectRefusal(app("--set PerfectMatch.maxIterations=99999999999" + tail), {"maxIterations", "whole number"});
	expectRefusal(app("--set sigma" + tail), {"--set 'sigma'", "expected SECTION.KEY=VALUE"});
	const auto ini = d.write("bad.ini", "[MappingApplication]\nminGoodness = 2\n");
	expectRefusal(app("--config " + quote(ini) + tail), {ini, "minGoodness = '2'", "expected a value in 0..1"});
	// MRPT's own INI syntax errors (its $eval{...} expansion) are configuration errors too.
	const auto ini2 = d.write("eval.ini", "[PerfectMatch]\nsigma = $eval{0.05\n");
	expectRefusal(app("--config " + quote(ini2) + tail), {ini2 + ": "});
}

TEST(BadInput, ConfigFileMissingOrADirectory)
{
	ScratchDir d("bad-config-file");
	const auto log = d.write("room.clf", roomCarmen(5));
	const std::string tail = " --out " + quote(d.path("out")) + " " + quote(log);
	expectRefusal(app("--config " + quote(d.path("none.ini")) + tail),
				  {d.path("none.ini"), "cannot open configuration file", "expected an INI file"});
	expectRefusal(app("--config " + quote(d.dir.string()) + tail), {d.dir.string(), "is a directory"});
	expectRefusal(app("--config"), {"--config needs a value"});
}

// ---------------------------------------------------------------- --out

TEST(BadInput, OutputFolderUnusableIsDetectedBeforeProcessing)
{
	ScratchDir d("bad-out");
	const auto log = d.write("room.clf", roomCarmen(30));
	const auto file = d.write("a-file", "x");
	auto r = app("--out " + quote(file) + " " + quote(log));
	expectRefusal(r, {"--out " + file, "exists but is not a directory"});
	EXPECT_EQ(readText(file), "x");
	r = app("--out " + quote(file + "/sub") + " " + quote(log));
	expectRefusal(r, {"--out " + file + "/sub", "cannot create directory", "Not a directory"});
	// Before processing: no summary, and no output anywhere.
	EXPECT_FALSE(contains(r.output, "scans"));
	std::size_t entries = 0;
	for ([[maybe_unused]] const auto& e : fs::directory_iterator(d.dir)) ++entries;
	EXPECT_EQ(entries, 2u);
}

/** A 64 KiB tmpfs mounted on `dir` for the test's lifetime (needs root in a mount namespace that allows it). */
struct TinyFileSystem
{
	std::string dir;
	bool mounted = false;
	explicit TinyFileSystem(const std::string& d) : dir(d)
	{
		fs::create_directories(dir);
		mounted = ::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") == 0;
	}
	~TinyFileSystem()
	{
		if (mounted) ::umount2(dir.c_str(), MNT_DETACH);
	}
};

TEST(BadInput, OutputFolderWithoutFreeSpaceIsDetectedBeforeProcessing)
{
	ScratchDir d("bad-out-full");
	const auto log = d.write("room.clf", roomCarmen(30));
	TinyFileSystem tiny(d.path("tiny"));
	if (!tiny.mounted) GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): " << std::strerror(errno);
	// Room for a probe file, not for the outputs.
	auto r = app("--out " + quote(tiny.dir + "/out") + " " + quote(log));
	expectRefusal(r, {"--out " + tiny.dir + "/out", "not enough free space", "64 KB free, at least", "KB needed"});
	EXPECT_FALSE(fs::exists(tiny.dir + "/out")) << "the refused --out folder is left behind";
	// Completely full: not even the probe can be written.
	{
		std::ofstream fill(tiny.dir + "/fill", std::ios::binary);
		const std::string block(4096, 'x');
		for (int i = 0; i < 64 && fill.write(block.data(), block.size()); ++i)
		{
		}
	}
	r = app("--out " + quote(tiny.dir) + " " + quote(log));
	expectRefusal(r, {"--out " + tiny.dir, "is not writable", "No space left on device"});
}

// ---------------------------------------------------------------- damage inside a log

TEST(BadInput, MalformedCarmenLinesAreSkippedCountedAndNamed)
{
	ScratchDir d("bad-carmen-lines");
	auto v = lines(roomCarmen(60));
	// Line numbers are 1-based; the log starts with a comment and a PARAM line.
	ASSERT_EQ(v[10].rfind("FLASER 181 ", 0), 0u);
	v[10].replace(0, 10, "FLASER 180");	 // beam count disagrees with the line
	v[20] = v[20].substr(0, v[20].size() / 2);	// truncated line
	v[30].replace(v[30].find(' ', 12), 1, " x");	// a non-numeric range
	v[40] = "FLASER 4 81.9 81.9 0 81.9 0 0 0 0 0 0 1004.000000 nohost 1004.000000";  // no valid beam
	// FLASER 181: fields 183..185 laser pose, 186..188 odometry pose.
	v[44] = withField(v[44], 186, "1e300");	 // finite, but no robot is there
	v[46] = withField(v[46], 183, "500.0");	 // a laser 500 m from the robot base
	v.insert(v.begin() + 50, "\x01\x02 binary junk \xff");	// unknown keyword: ignored silently
	const auto log = d.write("damaged.clf", join(v));
	const auto out = d.path("out");
	const auto r = app("--no-progress --out " + quote(out) + " " + quote(log));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	for (const char* n : {":11: beam count 180 disagrees", ":21: ", ":31: non-numeric range", ":41: scan has no valid beam",
						  ":45: implausible odometry pose (1e+300, ", ":47: laser pose 498.99"})
		EXPECT_TRUE(contains(r.output, "warning: " + log + n)) << n << "\n" << r.output;
	EXPECT_TRUE(contains(r.output, ", skipped 6, warnings 6")) << r.output;
	EXPECT_EQ(summaryScans(r.output), 54u) << r.output;
	expectCompleteOutputs(out, 54);
}

namespace
{
/** A plain observation-only rawlog of the room: n × (odometry + scan). */
std::string roomRawlog(const ScratchDir& d, const std::string& name, std::size_t n)
{
	const auto truth = roomPath(n);
	writeRawlog(d.path(name), furnishedRoom(), truth, truth, RawlogSpec{});
	return d.path(name);
}
}  // namespace

TEST(BadInput, TruncatedRawlogIsMappedUpToTheDamage)
{
	ScratchDir d("bad-truncated");
	const auto full = roomRawlog(d, "full.rawlog", 60);
	const std::string bytes = readText(full);
	const std::size_t perPair = bytes.size() / 60;
	const auto cut = d.write("cut.rawlog", bytes.substr(0, 40 * perPair + perPair / 2));  // inside pair 41
	const auto out = d.path("out");
	const auto r = app("--no-progress --out " + quote(out) + " " + quote(cut));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_TRUE(contains(r.output, "warning: " + cut + ": damaged after object ")) << r.output;
	EXPECT_TRUE(contains(r.output, "), stopping")) << r.output;
	const std::size_t scans = summaryScans(r.output);
	EXPECT_GE(scans, 40u) << r.output;
	EXPECT_LE(scans, 41u) << r.output;
	expectCompleteOutputs(out, scans);
}

TEST(BadInput, GarbageAfterARawlogIsReportedAndEverythingBeforeIsMapped)
{
	ScratchDir d("bad-garbage");
	const auto full = roomRawlog(d, "full.rawlog", 50);
	std::string bytes = readText(full);
	for (int i = 0; i < 500; ++i) bytes += static_cast<char>((i * 131) % 256);
	const auto log = d.write("garbage.rawlog", bytes);
	const auto out = d.path("out");
	const auto r = app("--no-progress --out " + quote(out) + " " + quote(log));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_TRUE(contains(r.output, "warning: " + log + ": damaged after object 100 (")) << r.output;
	EXPECT_EQ(summaryScans(r.output), 50u) << r.output;
	expectCompleteOutputs(out, 50);
}

TEST(BadInput, RawlogObjectThatCrashesMrptIsWhereTheLogEnds)
{
	// An action found by fuzzing on which CActionRobotMovement2D::serializeFrom (MRPT 2.5.8)
	// dereferences a null pointer; read in-process it kills the program.
	const std::string crash = readText(PMSLAM_SOURCE_DIR "/fuzz/corpus/fuzz_rawlog/mrpt-segv-in-CActionRobotMovement2D");
	ASSERT_GT(crash.size(), 100u);
	ScratchDir d("bad-mrpt-crash");
	const auto full = roomRawlog(d, "full.rawlog", 40);
	const auto log = d.write("crash.rawlog", readText(full) + crash);
	const auto out = d.path("out");
	const auto r = app("--no-progress --out " + quote(out) + " " + quote(log));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_TRUE(contains(r.output, "warning: " + log + ": damaged after object 80 (MRPT crashed reading it (signal 11"))
		<< r.output;
	EXPECT_EQ(summaryScans(r.output), 40u) << r.output;
	expectCompleteOutputs(out, 40);

	// The same object first in the file: refused like any unreadable rawlog.
	const auto alone = d.write("alone.rawlog", crash);
	expectRefusal(app("--no-progress --out " + quote(out) + " " + quote(alone)),
				  {alone, "is not a readable MRPT rawlog", "MRPT crashed reading it"});
}

TEST(BadInput, RawlogScanWithoutAValidBeamIsSkipped)
{
	ScratchDir d("bad-rawlog-empty-scan");
	const auto truth = roomPath(20);
	auto world = furnishedRoom();
	{
		mrpt::io::CFileOutputStream f(d.path("log.rawlog"));
		auto a = mrpt::serialization::archiveFrom(f);
		for (std::size_t k = 0; k < truth.size(); ++k)
		{
			auto s = world.scan(truth[k]);
			if (k == 7)
				for (std::size_t i = 0; i < s.getScanSize(); ++i) s.setScanRangeValidity(i, false);
			s.timestamp = mrpt::Clock::fromDouble(10.0 + double(k));
			a << s;
		}
	}
	const auto out = d.path("out");
	const auto r = app("--no-progress --out " + quote(out) + " " + quote(d.path("log.rawlog")));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_TRUE(contains(r.output, "object 8: scan has no valid beam, skipped")) << r.output;
	EXPECT_TRUE(contains(r.output, ", skipped 1, warnings 1")) << r.output;
	expectCompleteOutputs(out, 19);
}

// ---------------------------------------------------------------- interruption

namespace
{
/** Starts the app with stdout+stderr to `logFile`; returns its pid. */
pid_t spawnApp(const std::vector<std::string>& args, const std::string& logFile)
{
	const pid_t pid = ::fork();
	if (pid == 0)
	{
		FILE* f = std::freopen(logFile.c_str(), "w", stdout);
		if (!f || ::dup2(STDOUT_FILENO, STDERR_FILENO) < 0) ::_exit(127);
		std::vector<char*> argv{const_cast<char*>(kApp.c_str())};
		for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
		argv.push_back(nullptr);
		::execv(kApp.c_str(), argv.data());
		::_exit(127);
	}
	return pid;
}

/** Exit code (128 + signal if killed); -1 if still running after `timeout`. */
int waitFor(pid_t pid, std::chrono::seconds timeout)
{
	const auto end = std::chrono::steady_clock::now() + timeout;
	while (std::chrono::steady_clock::now() < end)
	{
		int status = 0;
		if (::waitpid(pid, &status, WNOHANG) == pid)
			return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
		std::this_thread::sleep_for(std::chrono::milliseconds(20));
	}
	::kill(pid, SIGKILL);
	::waitpid(pid, nullptr, 0);
	return -1;
}

/** A long Carmen log of the room (back and forth), for when intel.clf is absent. */
std::string longSyntheticLog(const ScratchDir& d)
{
	std::vector<mrpt::math::TPose2D> truth;
	const auto loop = roomPath(200);
	for (int rep = 0; rep < 150; ++rep) truth.insert(truth.end(), loop.begin(), loop.end());
	CarmenLogSpec spec;
	spec.beams = 90;
	return d.write("long.clf", carmenLog(furnishedRoom(), truth, truth, spec));
}
}  // namespace

void interruptMidRun(int sig)
{
	ScratchDir d("interrupt");
	const std::string log = fs::exists(kIntel) ? kIntel : longSyntheticLog(d);
	const auto out = d.path("out");
	const auto console = d.path("console.txt");
	const pid_t pid = spawnApp({"--progress", "--out", out, log}, console);
	ASSERT_GT(pid, 0);
	// About a second in, and only once scans are being processed (the progress line shows).
	const auto start = std::chrono::steady_clock::now();
	while (std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
	{
		std::this_thread::sleep_for(std::chrono::milliseconds(50));
		if (std::chrono::steady_clock::now() - start >= std::chrono::seconds(1) && contains(readText(console), " scans"))
			break;
	}
	ASSERT_EQ(::kill(pid, sig), 0);
	const int code = waitFor(pid, std::chrono::seconds(300));
	const std::string output = readText(console);
	ASSERT_EQ(code, 130) << output;
	EXPECT_TRUE(contains(output, "pm-slam-app: interrupted after ")) << output;
	EXPECT_TRUE(contains(output, "wrote the map and the trajectory of ")) << output;
	const std::size_t scans = countDataLines(fs::path(out) / "trajectory.txt");
	EXPECT_GT(scans, 0u) << output;
	EXPECT_TRUE(contains(output, "interrupted after " + std::to_string(scans) + " scans")) << output;
	expectCompleteOutputs(out, scans);
	// Interrupted, not finished: fewer poses than laser lines.
	std::ifstream in(log);
	std::size_t lasers = 0;
	for (std::string l; std::getline(in, l);) lasers += l.rfind("FLASER ", 0) == 0;
	EXPECT_LT(scans, lasers);
}

TEST(Interrupt, SigtermMidRunWritesCompleteOutputsAndExits130) { interruptMidRun(SIGTERM); }

TEST(Interrupt, SigintMidRunWritesCompleteOutputsAndExits130) { interruptMidRun(SIGINT); }
