// pm-slam-app --live with MRPT's real drivers (CHokuyoURG over Ethernet, CLMS100Eth) against sensor emulators
// on localhost that serve scans ray-cast along a known path in real time; --record and its exact replay;
// disconnects, garbage, sensors that never connect, a stalled SLAM dropping the oldest scans; --follow.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "RunProgram.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;

namespace
{
const std::string kBin = std::string(PMSLAM_BINARY_DIR) + "/bin/";

fs::path tempDir(const std::string& name)
{
	const fs::path d = fs::temp_directory_path() / ("pmslam_test_live_app_" + name + "_" + std::to_string(::getpid()));
	fs::remove_all(d);
	fs::create_directories(d);
	return d;
}

/** A child process with its stdout and stderr in a file. */
class Process
{
   public:
	Process(const std::vector<std::string>& argv, const fs::path& output)
	{
		m_pid = ::fork();
		if (m_pid == 0)
		{
			std::FILE* f = std::fopen(output.c_str(), "w");
			if (f)
			{
				::dup2(::fileno(f), 1);
				::dup2(::fileno(f), 2);
			}
			std::vector<char*> args;
			for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
			args.push_back(nullptr);
			::execv(args[0], args.data());
			std::_Exit(127);
		}
	}
	~Process()
	{
		if (m_pid > 0 && !m_waited)
		{
			::kill(m_pid, SIGKILL);
			wait();
		}
	}
	void signal(int sig) const { ::kill(m_pid, sig); }
	/** Exit status, or 128 + signal. */
	int wait()
	{
		int status = 0;
		::waitpid(m_pid, &status, 0);
		m_waited = true;
		return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
	}

   private:
	pid_t m_pid = -1;
	bool m_waited = false;
};

std::string readText(const fs::path& p)
{
	std::ifstream in(p);
	std::stringstream ss;
	ss << in.rdbuf();
	return ss.str();
}

/** A lidar emulator (tests/support/lidar_emulator) listening on a free port. */
struct Emulator
{
	fs::path dir;
	std::unique_ptr<Process> process;
	int port = 0;

	Emulator(const fs::path& d, const std::string& protocol, const std::vector<std::string>& extra = {}) : dir(d)
	{
		std::vector<std::string> argv = {kBin + "pm-lidar-emulator", "--protocol", protocol, "--port", "0",
										 "--truth", (dir / "truth.txt").string()};
		argv.insert(argv.end(), extra.begin(), extra.end());
		process = std::make_unique<Process>(argv, dir / "emulator.out");
		for (int i = 0; i < 200 && !port; ++i)
		{
			std::this_thread::sleep_for(std::chrono::milliseconds(25));
			std::istringstream in(readText(dir / "emulator.out"));
			std::string word;
			while (in >> word)
				if (word == "PORT" && in >> port) break;
		}
	}
	~Emulator()
	{
		if (process) process->signal(SIGTERM);
	}
};

std::string hokuyoIni(int port, const std::string& section = "LIDAR")
{
	return "[global]\nrawlog_prefix = ignored\n\n[" + section +
		   "]\ndriver = CHokuyoURG\nprocess_rate = 90\nsensorLabel = HOKUYO\nIP_DIR = 127.0.0.1\nPORT_DIR = " +
		   std::to_string(port) + "\npose_x = 0\npose_y = 0\npose_z = 0.3\npose_yaw = 0\n";
}

std::string sickIni(int port)
{
	return "[SICK]\ndriver = CLMS100Eth\nprocess_rate = 50\nsensorLabel = LMS111\nip_address = 127.0.0.1\nTCP_port = " +
		   std::to_string(port) + "\npose_x = 0\npose_y = 0\npose_z = 0.3\npose_yaw = 0\n";
}

fs::path writeIni(const fs::path& dir, const std::string& text)
{
	const fs::path p = dir / "sensors.ini";
	std::ofstream(p) << text;
	return p;
}

struct Pose
{
	double t, x, y, yaw;
};

std::vector<Pose> loadPoses(const fs::path& p)
{
	std::vector<Pose> out;
	std::ifstream in(p);
	std::string line;
	while (std::getline(in, line))
	{
		if (line.empty() || line[0] == '#') continue;
		Pose q{};
		if (std::sscanf(line.c_str(), "%lf %lf %lf %lf", &q.t, &q.x, &q.y, &q.yaw) == 4) out.push_back(q);
	}
	return out;
}

/** Pose b in the frame of pose a. */
Pose relative(const Pose& a, const Pose& b)
{
	const double c = std::cos(a.yaw), s = std::sin(a.yaw), dx = b.x - a.x, dy = b.y - a.y;
	return {b.t - a.t, c * dx + s * dy, -s * dx + c * dy, std::remainder(b.yaw - a.yaw, 2 * M_PI)};
}

struct TruthError
{
	std::size_t poses = 0;
	double meanTrans = 0, maxTrans = 0, meanRotDeg = 0;	 // relations 1 s apart
	double maxDrift = 0;  // from the first pose
	double span = 0;  // s of trajectory
};

/** Kümmerle-style relations 1 s apart against the emulator's truth at each scan's timestamp (the truth served
 * nearest in time: the driver stamps a scan within a period of when the emulator cast it). */
TruthError errorAgainstTruth(const std::vector<Pose>& est, const std::vector<Pose>& truth)
{
	TruthError e;
	if (est.size() < 2 || truth.empty()) return e;
	std::vector<Pose> gt;
	for (const auto& p : est)
	{
		const auto it = std::lower_bound(truth.begin(), truth.end(), p.t, [](const Pose& q, double t) { return q.t < t; });
		const Pose* best = it == truth.end() ? &truth.back() : &*it;
		if (it != truth.begin() && (it == truth.end() || std::abs((it - 1)->t - p.t) < std::abs(it->t - p.t)))
			best = &*(it - 1);
		gt.push_back(*best);
	}
	std::size_t n = 0;
	for (std::size_t i = 0, j = 0; i < est.size(); ++i)
	{
		while (j < est.size() && est[j].t < est[i].t + 1.0) ++j;
		if (j >= est.size()) break;
		const Pose re = relative(est[i], est[j]), rg = relative(gt[i], gt[j]);
		const double d = std::hypot(re.x - rg.x, re.y - rg.y);
		e.meanTrans += d;
		e.maxTrans = std::max(e.maxTrans, d);
		e.meanRotDeg += std::abs(std::remainder(re.yaw - rg.yaw, 2 * M_PI)) * 180 / M_PI;
		++n;
	}
	if (n) e.meanTrans /= n, e.meanRotDeg /= n;
	for (std::size_t i = 0; i < est.size(); ++i)
	{
		const Pose re = relative(est[0], est[i]), rg = relative(gt[0], gt[i]);
		e.maxDrift = std::max(e.maxDrift, std::hypot(re.x - rg.x, re.y - rg.y));
	}
	e.poses = est.size();
	e.span = est.back().t - est.front().t;
	return e;
}

/** pm-slam-app --live for `seconds`, then Ctrl-C; its exit status and output. */
RunResult runLive(const fs::path& ini, const fs::path& out, double seconds, const std::string& extra = "")
{
	char t[32];
	std::snprintf(t, sizeof t, "%.1f", seconds);
	return run("timeout -s INT -k 30 --preserve-status " + std::string(t) + " " + quote(kBin + "pm-slam-app") +
			   " --live " + quote(ini.string()) + " --out " + quote(out.string()) + " " + extra);
}

std::string dataLines(const fs::path& p)
{
	std::ifstream in(p);
	std::string line, out;
	while (std::getline(in, line))
		if (!line.empty() && line[0] != '#') out += line + "\n";
	return out;
}

void expectLiveRunMatchesTruthAndReplays(const std::string& protocol, const std::string& ini, double seconds)
{
	const fs::path dir = tempDir(protocol);
	Emulator emu(dir, protocol);
	ASSERT_GT(emu.port, 0) << readText(dir / "emulator.out");
	const fs::path cfg = writeIni(dir, ini == "hokuyo" ? hokuyoIni(emu.port) : sickIni(emu.port));
	const fs::path out = dir / "out", rec = dir / "live.rawlog";
	// Nothing may be dropped here (that is tested below): the replay must see what the live run saw.
	const auto r = runLive(cfg, out, seconds, "--record " + quote(rec.string()) + " --snapshot-every 2 --max-pending 100000");
	ASSERT_EQ(r.exitCode, 0) << r.output;  // Ctrl-C is a live run's normal end
	for (const char* f : {"trajectory.txt", "trajectory_online.txt", "map.png", "map.pgm", "map.yaml",
						  "map.gridmap.gz", "timing.txt", "pose.txt"})
		EXPECT_TRUE(fs::exists(out / f)) << f;
	EXPECT_NE(r.output.find("0 dropped"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("latency from a scan's timestamp to its pose: p50"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("snapshots written"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("tracking: ok"), std::string::npos) << r.output;

	const auto truth = loadPoses(dir / "truth.txt");
	const auto live = loadPoses(out / "trajectory.txt");
	const TruthError e = errorAgainstTruth(live, truth);
	// 12 s of scans at 40 / 25 Hz after the driver's start-up: several hundred scans, through two turns.
	EXPECT_GT(e.poses, 200u);
	EXPECT_GT(e.span, 8.0);
	EXPECT_LT(e.meanTrans, 0.02) << protocol;
	EXPECT_LT(e.maxTrans, 0.08) << protocol;
	EXPECT_LT(e.meanRotDeg, 0.5) << protocol;
	EXPECT_LT(e.maxDrift, 0.15) << protocol;

	// MRPT's own tools read the recording as a rawlog-grabber file: observations only, every one received.
	std::size_t recorded = 0;
	const auto rat = r.output.find("recorded ");
	ASSERT_NE(rat, std::string::npos) << r.output;
	ASSERT_EQ(std::sscanf(r.output.c_str() + rat, "recorded %zu", &recorded), 1);
	if (fs::exists("/usr/bin/rawlog-edit"))
	{
		const auto info = run("rawlog-edit --info -i " + quote(rec.string()));
		EXPECT_NE(info.output.find("Observations format               : Yes"), std::string::npos) << info.output;
		EXPECT_NE(info.output.find("Overall number of objects         : " + std::to_string(recorded) + "\n"),
				  std::string::npos)
			<< info.output;
	}
	// The recording, mapped offline, gives exactly the live trajectory (so, as well as an offline run of the
	// same scans does).
	ASSERT_TRUE(fs::exists(rec));
	const fs::path off = dir / "offline";
	const auto o = run(quote(kBin + "pm-slam-app") + " " + quote(rec.string()) + " --out " + quote(off.string()) + " --quiet");
	ASSERT_EQ(o.exitCode, 0) << o.output;
	EXPECT_EQ(dataLines(off / "trajectory_online.txt"), dataLines(out / "trajectory_online.txt"));
	EXPECT_EQ(dataLines(off / "trajectory.txt"), dataLines(out / "trajectory.txt"));
	const auto pose = loadPoses(out / "pose.txt");
	ASSERT_EQ(pose.size(), 1u);	 // the newest pose of the last snapshot
	EXPECT_LE(pose[0].t, live.back().t);
	fs::remove_all(dir);
}
}  // namespace

TEST(LiveSensors, HokuyoOverEthernetMapsAsTheTruthAndTheRecordingReplaysExactly)
{
	expectLiveRunMatchesTruthAndReplays("scip", "hokuyo", 14.0);
}

TEST(LiveSensors, SickLms1xxMapsAsTheTruthAndTheRecordingReplaysExactly)
{
	// MRPT's CLMS100Eth takes 15 s to start (it waits after each configuration telegram).
	expectLiveRunMatchesTruthAndReplays("lms1xx", "sick", 30.0);
}

TEST(LiveSensors, TracksTheRobotOnTheMapOfAnEarlierRun)
{
	// Map today, localise tomorrow: a live run's map.gridmap.gz as the fixed map of a second live run.
	const fs::path dir = tempDir("localize");
	const fs::path mapped = dir / "mapped", tracked = dir / "tracked";
	{
		Emulator emu(dir, "scip");
		ASSERT_GT(emu.port, 0);
		const auto r = runLive(writeIni(dir, hokuyoIni(emu.port)), mapped, 9.0);
		ASSERT_EQ(r.exitCode, 0) << r.output;
	}
	fs::rename(dir / "truth.txt", dir / "truth-mapped.txt");
	Emulator emu(dir, "scip");	// the robot starts again where the map's first pose was
	ASSERT_GT(emu.port, 0);
	const auto r = runLive(writeIni(dir, hokuyoIni(emu.port)), tracked, 9.0,
						   "--localize " + quote((mapped / "map.gridmap.gz").string()));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("localised on"), std::string::npos) << r.output;
	const auto poses = loadPoses(tracked / "trajectory.txt");
	ASSERT_GT(poses.size(), 150u);
	const TruthError e = errorAgainstTruth(poses, loadPoses(dir / "truth.txt"));
	EXPECT_LT(e.meanTrans, 0.02);
	EXPECT_LT(e.maxDrift, 0.1);
	// On the fixed map the pose is absolute: the robot's start, the map's origin.
	EXPECT_LT(std::hypot(poses.front().x, poses.front().y), 0.05);

	// Again with a start pose 3 m and 150 degrees off: the robot is lost, searched for on the whole map,
	// found, and every pose from then on is where the truth has it (D47).
	fs::rename(dir / "truth.txt", dir / "truth-tracked.txt");
	const fs::path hinted = dir / "hinted";
	Emulator again(dir, "scip");
	ASSERT_GT(again.port, 0);
	const auto h = runLive(writeIni(dir, hokuyoIni(again.port)), hinted, 9.0,
						   "--localize " + quote((mapped / "map.gridmap.gz").string()) + " --initial-pose=3,1,150");
	ASSERT_EQ(h.exitCode, 0) << h.output;
	EXPECT_NE(h.output.find("the robot found again 1 times"), std::string::npos) << h.output;
	EXPECT_NE(h.output.find("tracking: recovered"), std::string::npos) << h.output;
	const auto found = loadPoses(hinted / "trajectory.txt");
	ASSERT_GT(found.size(), 150u);
	// The map's frame is the truth's first pose's: each pose of the second half against the truth nearest in time.
	const auto truth = loadPoses(dir / "truth.txt");
	ASSERT_FALSE(truth.empty());
	double worst = 0;
	for (std::size_t i = found.size() / 2; i < found.size(); ++i)
	{
		const auto it = std::min_element(truth.begin(), truth.end(), [&](const Pose& a, const Pose& b) {
			return std::abs(a.t - found[i].t) < std::abs(b.t - found[i].t);
		});
		const Pose g = relative(truth.front(), *it);
		worst = std::max(worst, std::hypot(found[i].x - g.x, found[i].y - g.y));
	}
	EXPECT_LT(worst, 0.15) << h.output;
	fs::remove_all(dir);
}

TEST(LiveSensors, ADisconnectMidRunIsReportedAndSurvived)
{
	const fs::path dir = tempDir("disconnect");
	// Unplugged for 3 s: MRPT's driver cannot reconnect by itself, so pm-slam-app creates it anew.
	Emulator emu(dir, "scip", {"--disconnect-at", "4", "--outage", "3"});
	ASSERT_GT(emu.port, 0);
	const fs::path out = dir / "out";
	const auto r = runLive(writeIni(dir, hokuyoIni(emu.port)), out, 18.0);
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("sensor [LIDAR] (CHokuyoURG): no data for"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("sensor [LIDAR] (CHokuyoURG): reconnected after"), std::string::npos) << r.output;
	const auto truth = loadPoses(dir / "truth.txt");
	const auto live = loadPoses(out / "trajectory.txt");
	ASSERT_GT(live.size(), 100u);
	// Scans from well after the disconnect were mapped, and the robot was tracked through the gap.
	const double disconnectAt = truth.front().t + 4.0;
	EXPECT_GT(live.back().t, disconnectAt + 8.0) << r.output;
	std::size_t during = 0;	 // no scan while unplugged (so the gap was real)
	for (const auto& p : live) during += p.t > disconnectAt + 0.5 && p.t < disconnectAt + 2.5;
	EXPECT_EQ(during, 0u);
	const TruthError e = errorAgainstTruth(live, truth);
	EXPECT_LT(e.maxDrift, 0.3) << r.output;
	EXPECT_LT(e.meanTrans, 0.05);
	fs::remove_all(dir);
}

TEST(LiveSensors, ASlamSlowerThanItsSensorDropsTheOldestScansAndSaysSo)
{
	const fs::path dir = tempDir("slow");
	Emulator emu(dir, "scip");
	ASSERT_GT(emu.port, 0);
	const fs::path out = dir / "out", rec = dir / "live.rawlog";
	// 40 ms per scan (the test hook of pm-slam-app-instrumented) against a 40 Hz sensor: the SLAM runs at most
	// 25 scans a second, so the queue must stay at 3 scans and the oldest go.
	const auto r = run("PMSLAM_TEST_SCAN_DELAY_MS=40 timeout -s INT -k 30 --preserve-status 10 " +
					   quote(kBin + "pm-slam-app-instrumented") + " --live " + quote(writeIni(dir, hokuyoIni(emu.port)).string()) +
					   " --out " + quote(out.string()) + " --max-pending 3 --record " + quote(rec.string()));
	const int status = r.exitCode;
	const std::string& output = r.output;
	ASSERT_EQ(status, 0) << output;
	EXPECT_NE(output.find("the SLAM fell behind the sensors"), std::string::npos) << output;
	// The summary's counts add up: every scan received was processed or dropped, and all were recorded.
	std::size_t received = 0, processed = 0, dropped = 0, recorded = 0;
	const auto at = output.find("live: ");
	ASSERT_NE(at, std::string::npos) << output;
	ASSERT_EQ(std::sscanf(output.c_str() + at, "live: %*s objects received (%zu scans) from %*s %zu scans processed, %zu dropped",
						  &received, &processed, &dropped),
			  3)
		<< output.substr(at, 200);
	EXPECT_GT(dropped * 4, received);  // at least a third of 40 Hz is more than 25 Hz can take
	EXPECT_EQ(processed + dropped, received);
	EXPECT_EQ(loadPoses(out / "trajectory.txt").size(), processed);
	const auto rat = output.find("recorded ");
	ASSERT_NE(rat, std::string::npos);
	ASSERT_EQ(std::sscanf(output.c_str() + rat, "recorded %zu", &recorded), 1);
	EXPECT_EQ(recorded, received);
	EXPECT_NE(output.find("it holds the dropped scans too"), std::string::npos);
	// Dropping kept the robot tracked.
	const TruthError e = errorAgainstTruth(loadPoses(out / "trajectory.txt"), loadPoses(dir / "truth.txt"));
	EXPECT_LT(e.maxDrift, 0.3) << output;
	fs::remove_all(dir);
}

TEST(LiveSensors, OneStopSignalDeliveredTwiceIsStillACleanStopButALaterSecondOneEndsAtOnce)
{
	// coreutils' timeout signals the process and its group: the same stop can arrive twice within microseconds.
	const fs::path dir = tempDir("twice");
	Emulator emu(dir, "scip");
	ASSERT_GT(emu.port, 0);
	const fs::path ini = writeIni(dir, hokuyoIni(emu.port));
	{
		Process app({kBin + "pm-slam-app", "--live", ini.string(), "--out", (dir / "a").string()}, dir / "a.out");
		std::this_thread::sleep_for(std::chrono::seconds(3));
		app.signal(SIGINT);
		app.signal(SIGINT);
		EXPECT_EQ(app.wait(), 0) << readText(dir / "a.out");
		EXPECT_TRUE(fs::exists(dir / "a" / "trajectory.txt"));
	}
	{
		// A user's second Ctrl-C, 0.6 s later while the run is still finishing (200 ms per scan, 20 scans pending
		// when the first came: 4 s of draining), ends it at once: killed by the signal, as documented.
		::setenv("PMSLAM_TEST_SCAN_DELAY_MS", "200", 1);
		Process app({kBin + "pm-slam-app-instrumented", "--live", ini.string(), "--out", (dir / "b").string()}, dir / "b.out");
		::unsetenv("PMSLAM_TEST_SCAN_DELAY_MS");
		std::this_thread::sleep_for(std::chrono::seconds(4));
		app.signal(SIGINT);
		std::this_thread::sleep_for(std::chrono::milliseconds(600));
		app.signal(SIGINT);
		EXPECT_EQ(app.wait(), 128 + SIGINT) << readText(dir / "b.out");
	}
	fs::remove_all(dir);
}

TEST(LiveSensors, GarbageFromTheSensorIsAClearErrorNotACrash)
{
	// CHokuyoURG gives up on garbage and delivers nothing; CLMS100Eth's initialize() never returns on it (its
	// thread is left behind): both end as the same one-line error, exit status 2, nothing written.
	for (const std::string protocol : {"scip", "lms1xx"})
	{
		const fs::path dir = tempDir("garbage_" + protocol);
		Emulator emu(dir, protocol, {"--garbage"});
		ASSERT_GT(emu.port, 0);
		const fs::path out = dir / "out";
		const bool hokuyo = protocol == "scip";
		const auto r = run("timeout -k 10 60 " + quote(kBin + "pm-slam-app") + " --live " +
						   quote(writeIni(dir, hokuyo ? hokuyoIni(emu.port) : sickIni(emu.port)).string()) + " --out " +
						   quote(out.string()) + " --connect-timeout 3");
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_NE(r.output.find(hokuyo ? "sensors.ini: [LIDAR] (CHokuyoURG): no data within 3 s"
									   : "sensors.ini: [SICK] (CLMS100Eth): no data within 3 s"),
				  std::string::npos)
			<< r.output;
		EXPECT_FALSE(fs::exists(out));	// nothing half-written
		fs::remove_all(dir);
	}
}

TEST(LiveSensors, SensorsThatCannotStartAreClearErrorsNamingTheirSection)
{
	const fs::path dir = tempDir("errors");
	const fs::path out = dir / "out";
	auto live = [&](const std::string& ini, const std::string& extra = "") {
		return run("timeout -k 10 60 " + quote(kBin + "pm-slam-app") + " --live " + quote(writeIni(dir, ini).string()) +
				   " --out " + quote(out.string()) + " " + extra);
	};
	// Nothing listens on the port: no data, named by section.
	int freePort = 0;
	{
		Emulator probe(dir, "scip");
		freePort = probe.port;
	}
	std::this_thread::sleep_for(std::chrono::milliseconds(300));
	auto r = live(hokuyoIni(freePort, "FRONT_LIDAR"), "--connect-timeout 2");
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("[FRONT_LIDAR] (CHokuyoURG): no data within"), std::string::npos) << r.output;
	r = live("[LIDAR]\ndriver = CNoSuchLaser\nprocess_rate = 10\n");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("[LIDAR]: driver = CNoSuchLaser: not a sensor class of MRPT's hwdrivers"), std::string::npos)
		<< r.output;
	r = live("[LIDAR]\nprocess_rate = 10\n");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("[LIDAR]: no 'driver' key"), std::string::npos) << r.output;
	// A key the driver refuses: its own message, out of MRPT's exception text (not its call stack).
	r = live("[LIDAR]\ndriver = CHokuyoURG\nprocess_rate = 10\n");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("[LIDAR] (CHokuyoURG): Either COM_port or IP_DIR must be defined in the configuration file!\n"),
			  std::string::npos)
		<< r.output;
	r = live("[LIDAR]\ndriver = CHokuyoURG\nIP_DIR = 127.0.0.1\nPORT_DIR = 1\n");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("[LIDAR]: process_rate must be set"), std::string::npos) << r.output;
	r = run(quote(kBin + "pm-slam-app") + " --live " + quote((dir / "missing.ini").string()) + " --out " + quote(out.string()));
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("missing.ini: no such file"), std::string::npos) << r.output;
	r = run(quote(kBin + "pm-slam-app") + " --follow robot.clf");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("--follow reads MRPT rawlogs"), std::string::npos) << r.output;
	r = run(quote(kBin + "pm-slam-app") + " --record x.rawlog some.rawlog");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("--record needs --live"), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(out));
	fs::remove_all(dir);
}

TEST(FollowRawlog, MapsALogWhileItIsWrittenAsTheFinishedLogAndEndsAfterTheTimeout)
{
	const std::string sample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
	if (!fs::exists(sample)) GTEST_SKIP() << "MRPT's sample rawlog is not installed (" << sample << ")";
	const fs::path dir = tempDir("follow");
	const fs::path grow = dir / "grabbing.rawlog";
	std::ofstream(grow).close();  // rawlog-grabber creates the file first
	Process app({kBin + "pm-slam-app", "--follow", grow.string(), "--follow-timeout", "2", "--out", (dir / "followed").string()},
				dir / "app.out");
	// The bytes arrive in pieces, cut anywhere (mid-object too), as a writer's buffer reaches the disk.
	std::ifstream in(sample, std::ios::binary);
	std::vector<char> buf(20000);
	while (in.read(buf.data(), buf.size()) || in.gcount() > 0)
	{
		std::ofstream o(grow, std::ios::binary | std::ios::app);
		o.write(buf.data(), in.gcount());
		o.close();
		std::this_thread::sleep_for(std::chrono::milliseconds(150));
	}
	const int status = app.wait();
	const std::string output = readText(dir / "app.out");
	ASSERT_EQ(status, 0) << output;
	const auto r = run(quote(kBin + "pm-slam-app") + " " + quote(sample) + " --out " + quote((dir / "whole").string()) + " --quiet");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(dataLines(dir / "followed" / "trajectory_online.txt"), dataLines(dir / "whole" / "trajectory_online.txt"));
	EXPECT_GT(loadPoses(dir / "followed" / "trajectory.txt").size(), 200u);
	fs::remove_all(dir);
}

TEST(FollowRawlog, CtrlCEndsAFollowWithEveryOutput)
{
	const fs::path dir = tempDir("follow_int");
	const fs::path grow = dir / "grabbing.rawlog";
	const std::string sample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
	if (!fs::exists(sample)) GTEST_SKIP() << "MRPT's sample rawlog is not installed (" << sample << ")";
	fs::copy_file(sample, grow);
	// No timeout: it waits for more until Ctrl-C.
	const auto r = run("timeout -s INT -k 20 --preserve-status 6 " + quote(kBin + "pm-slam-app") + " --follow " +
					   quote(grow.string()) + " --out " + quote((dir / "out").string()));
	EXPECT_EQ(r.exitCode, 0) << r.output;
	EXPECT_GT(loadPoses(dir / "out" / "trajectory.txt").size(), 200u);
	EXPECT_TRUE(fs::exists(dir / "out" / "map.gridmap.gz"));
	fs::remove_all(dir);
}
