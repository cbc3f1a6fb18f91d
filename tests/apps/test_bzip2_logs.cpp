// Carmen logs as Radish distributes them, bzip2-compressed (.clf.bz2), end to end: pm-slam-app maps one as it
// maps the plain log, maps a truncated one up to the damage with one warning, and refuses a bzip2 rawlog saying
// what it reads instead; pm-fault-inject takes one as input. (The reader itself: tests/io/test_compressed_logs.)
#include <gtest/gtest.h>
#include <pmslam/io/CarmenLogReader.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/Trajectory.h>

#include "Bzip2.h"
#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kInject = PMSLAM_BINARY_DIR "/bin/pm-fault-inject";

/** 200 scans through the room (240 kB) with ODOM lines and drifting odometry: matching has work to do. */
std::string roomLog()
{
	const auto truth = roomPath(200);
	CarmenLogSpec spec;
	spec.odomLines = true;
	return carmenLog(furnishedRoom(), truth, driftingOdometry(truth, 1.03, 0.03), spec);
}

RunResult mapLog(const ScratchDir& d, const std::string& log, const std::string& out)
{
	return run(quote(kApp) + " --no-progress --out " + quote(d.path(out)) + " " + quote(log));
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

/** The lines of a file that are not '#' comments (the header names the log). */
std::string withoutComments(const fs::path& p)
{
	std::istringstream in(readText(p));
	std::string out;
	for (std::string line; std::getline(in, line);)
		if (line.empty() || line[0] != '#') out += line + "\n";
	return out;
}

/** Scans the reader delivers from `log` (what pm-slam-app gets). */
std::size_t scansRead(const std::string& log)
{
	auto reader = pmslam::LogReader::open(log);
	reader->onWarning = nullptr;
	pmslam::LogEvent ev;
	while (reader->next(ev))
	{
	}
	return reader->stats().scans;
}
}  // namespace

TEST(Bzip2Logs, PmSlamAppMapsAClfBz2AsThePlainClf)
{
	ScratchDir d("bz2-app");
	const std::string text = roomLog();
	const auto plain = mapLog(d, d.write("room.clf", text), "plain");
	ASSERT_EQ(plain.exitCode, 0) << plain.output;
	const std::string bz = d.write("room.clf.bz2", bzip2(text));
	const auto zipped = mapLog(d, bz, "bz2");
	ASSERT_EQ(zipped.exitCode, 0) << zipped.output;
	EXPECT_FALSE(contains(zipped.output, "warning:")) << zipped.output;
	EXPECT_TRUE(contains(zipped.output, "skipped 0, warnings 0")) << zipped.output;
	EXPECT_EQ(countDataLines(d.dir / "bz2" / "trajectory.txt"), 200u);
	EXPECT_EQ(withoutComments(d.dir / "bz2" / "trajectory.txt"), withoutComments(d.dir / "plain" / "trajectory.txt"));
}

TEST(Bzip2Logs, PmSlamAppMapsATruncatedClfBz2UpToTheDamage)
{
	ScratchDir d("bz2-app-cut");
	const std::string text = roomLog();
	const std::string bz = bzip2(text, 1);	// 100 kB blocks: the cut leaves whole blocks before it
	ASSERT_GT(text.size(), 200000u);
	const std::string cut = d.write("room.clf.bz2", bz.substr(0, bz.size() * 7 / 10));
	const std::size_t scans = scansRead(cut);
	ASSERT_GT(scans, 30u);
	ASSERT_LT(scans, 200u);
	const auto r = mapLog(d, cut, "out");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_TRUE(contains(r.output, "warning: " + cut + ":")) << r.output;
	EXPECT_TRUE(contains(r.output, ": read error (bzip2: data ends early (truncated file)), stopping")) << r.output;
	EXPECT_EQ(pmslam::loadTrajectory((d.dir / "out" / "trajectory.txt").string()).size(), scans);
}

TEST(Bzip2Logs, PmSlamAppRefusesABzip2RawlogSayingWhatItReads)
{
	ScratchDir d("bz2-app-rawlog");
	const auto truth = roomPath(20);
	writeRawlog(d.path("room.rawlog"), furnishedRoom(), truth, truth, RawlogSpec{});
	const std::string bz = d.write("room.rawlog.bz2", bzip2(readText(d.dir / "room.rawlog")));
	const auto r = mapLog(d, bz, "out");
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_TRUE(contains(r.output, "'" + bz + "' is bzip2-compressed but not a Carmen log")) << r.output;
	EXPECT_TRUE(contains(r.output, "gz-compressed")) << r.output;
	EXPECT_FALSE(contains(r.output, "unknown log format")) << r.output;
}

TEST(Bzip2Logs, PmFaultInjectReadsAClfBz2AsThePlainClf)
{
	ScratchDir d("bz2-inject");
	const std::string text = roomLog();
	const std::string args = " --fault dropout --count 2 --scans 10 --seed 3 ";
	const auto plain = run(quote(kInject) + args + quote(d.write("room.clf", text)) + " " + quote(d.path("a.clf")));
	ASSERT_EQ(plain.exitCode, 0) << plain.output;
	const auto zipped =
		run(quote(kInject) + args + quote(d.write("room.clf.bz2", bzip2(text))) + " " + quote(d.path("b.clf")));
	ASSERT_EQ(zipped.exitCode, 0) << zipped.output;
	EXPECT_EQ(zipped.output, plain.output);
	EXPECT_EQ(readText(d.dir / "b.clf"), readText(d.dir / "a.clf"));
	EXPECT_LT(countDataLines(d.dir / "b.clf"), countDataLines(d.dir / "room.clf"));	 // the dropouts

	// Cut short in its third block: the lines of the first two are used (> 100 scans), with one warning.
	const std::string bz = bzip2(text, 1);
	const auto cut = run(quote(kInject) + args + quote(d.write("cut.clf.bz2", bz.substr(0, bz.size() * 9 / 10))) +
						 " " + quote(d.path("c.clf")));
	ASSERT_EQ(cut.exitCode, 0) << cut.output;
	EXPECT_TRUE(contains(cut.output, "pm-fault-inject: warning: " + d.path("cut.clf.bz2") + ":")) << cut.output;
	EXPECT_TRUE(contains(cut.output, "read error (bzip2: data ends early (truncated file)), the ")) << cut.output;
	EXPECT_LT(countDataLines(d.dir / "c.clf"), countDataLines(d.dir / "b.clf"));
}
