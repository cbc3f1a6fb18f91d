// Sessions (pm-slam-app --continue DIR): a map made in one run, continued by another from a start the
// second run does not know, comes out as one map and one trajectory in one frame, as good as one run
// of the whole log; DIR is never modified; a damaged, foreign or newer session is a one-line error.
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/Session.h>
#include <pmslam/io/Trajectory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using pmslam::testing::quote;
using pmslam::testing::run;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";

/** A drive through the furnished room, its odometry drifting; cut at `cut` into two logs (with a 30 s
 * gap between them), the second with its odometry restarted elsewhere (a robot switched on again). */
struct CutLog
{
	std::vector<TPose2D> truth = pmslam::testing::roomPath(160);
	std::size_t cut = 80;
	std::string whole, first, second;
	explicit CutLog(const pmslam::testing::ScratchDir& dir)
	{
		const auto world = pmslam::testing::furnishedRoom();
		const auto odo = pmslam::testing::driftingOdometry(truth, 1.02, 0.02);
		pmslam::testing::CarmenLogSpec spec;
		whole = dir.write("whole.clf", pmslam::testing::carmenLog(world, truth, odo, spec));
		const std::vector<TPose2D> t1(truth.begin(), truth.begin() + long(cut)), o1(odo.begin(), odo.begin() + long(cut));
		first = dir.write("first.clf", pmslam::testing::carmenLog(world, t1, o1, spec));
		const std::vector<TPose2D> t2(truth.begin() + long(cut), truth.end());
		const auto o2 = pmslam::testing::driftingOdometry(t2, 1.02, 0.02, CPose2D(7, -3, 1.2));
		spec.t0 += spec.dt * double(cut) + 30;
		second = dir.write("second.clf", pmslam::testing::carmenLog(world, t2, o2, spec));
	}
	/** Mean and max distance of each pose from the truth, in the frame of the first pose. */
	std::pair<double, double> error(const pmslam::Trajectory& t) const
	{
		double sum = 0, worst = 0;
		for (std::size_t k = 0; k < truth.size(); ++k)
		{
			const TPose2D r = pmslam::testing::relativeToFirst(truth, k);
			const double d = std::hypot(t[k].x - r.x, t[k].y - r.y);
			sum += d;
			worst = std::max(worst, d);
		}
		return {sum / double(truth.size()), worst};
	}
};

std::map<std::string, std::string> contents(const std::string& dir)
{
	std::map<std::string, std::string> out;
	for (const auto& e : fs::directory_iterator(dir)) out[e.path().filename().string()] = pmslam::testing::readText(e.path());
	return out;
}
}  // namespace

// The log cut in two and mapped as two sessions: every scan of both in one trajectory, as close to the
// truth as one run of the whole log; the second session's start found on the first one's map.
TEST(Sessions, ALogCutInTwoMapsAsWellAsOneRun)
{
	pmslam::testing::ScratchDir dir("sessions");
	const CutLog log(dir);
	auto r = run(quote(kApp) + " --quiet --out " + quote(dir.path("one")) + " " + quote(log.whole));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	r = run(quote(kApp) + " --quiet --out " + quote(dir.path("a")) + " " + quote(log.first));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto before = contents(dir.path("a"));
	r = run(quote(kApp) + " --continue " + quote(dir.path("a")) + " --out " + quote(dir.path("ab")) + " " +
			quote(log.second));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("global localisation: start found at"), std::string::npos) << r.output;
	EXPECT_EQ(contents(dir.path("a")), before) << "--continue changed its folder";

	const auto one = pmslam::loadTrajectory(dir.path("one") + "/trajectory.txt");
	const auto two = pmslam::loadTrajectory(dir.path("ab") + "/trajectory.txt");
	ASSERT_EQ(one.size(), log.truth.size());
	ASSERT_EQ(two.size(), log.truth.size());
	const auto [oneMean, oneMax] = log.error(one);
	const auto [twoMean, twoMax] = log.error(two);
	EXPECT_LT(twoMean, 1.1 * oneMean + 0.005) << "one run " << oneMean;
	EXPECT_LT(twoMax, 0.05);
	// The header says which poses are which session, and session.ini lists both parts.
	const std::string text = pmslam::testing::readText(dir.path("ab") + "/trajectory.txt");
	EXPECT_NE(text.find("sessions: 1 = poses 1-80 (" + log.first + "), 2 = poses 81-160 (" + log.second + ")"),
			  std::string::npos)
		<< text.substr(0, 400);
	const pmslam::Session s = pmslam::loadSession(dir.path("ab"));
	ASSERT_EQ(s.parts.size(), 2u);
	EXPECT_EQ(s.parts[1].log, log.second);
	EXPECT_EQ(s.parts[1].scans, 80u);

	// A third session on the two: three parts in one graph (a node per keyframe of each).
	r = run(quote(kApp) + " --quiet --continue " + quote(dir.path("ab")) + " --out " + quote(dir.path("abb")) + " " +
			quote(log.second));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const pmslam::Session three = pmslam::loadSession(dir.path("abb"));
	ASSERT_EQ(three.parts.size(), 3u);
	ASSERT_TRUE(three.graph);
	EXPECT_EQ(three.graph->nodeCount(), three.keyframes.size());
	EXPECT_EQ(three.trajectory.size(), 240u);
	EXPECT_LT(log.error(three.trajectory).second, 0.05);

	// An older folder without session.ini reads as one part.
	fs::remove(dir.path("a") + "/session.ini");
	r = run(quote(kApp) + " --quiet --continue " + quote(dir.path("a")) + " --initial-pose=" +
			pmslam::testing::fmt(two[80].x) + "," + pmslam::testing::fmt(two[80].y) + "," +
			pmslam::testing::fmt(two[80].yaw * 180 / M_PI) + " --out " + quote(dir.path("ab2")) + " " + quote(log.second));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(pmslam::testing::readText(dir.path("ab2") + "/trajectory.txt").find("1 = poses 1-80 (log unknown)"),
			  std::string::npos);
	EXPECT_LT(log.error(pmslam::loadTrajectory(dir.path("ab2") + "/trajectory.txt")).second, 0.05);
}

// Two sessions mapped apart (the second in its own frame, as another robot or another day would) merge:
// the second's folder given as the log replays its keyframes, its own trajectory as their odometry, and
// they land where the truth has them in the first one's frame.
TEST(Sessions, TwoSessionsMappedApartMergeIntoOneFrame)
{
	pmslam::testing::ScratchDir dir("sessions-merge");
	const CutLog log(dir);
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("a")) + " " + quote(log.first)).exitCode, 0);
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("b")) + " " + quote(log.second)).exitCode, 0);
	const auto r = run(quote(kApp) + " --continue " + quote(dir.path("a")) + " --out " + quote(dir.path("ab")) + " " +
					   quote(dir.path("b")));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("global localisation: start found at"), std::string::npos) << r.output;
	const pmslam::Session merged = pmslam::loadSession(dir.path("ab"));
	ASSERT_EQ(merged.parts.size(), 2u);
	const pmslam::Session b = pmslam::loadSession(dir.path("b"));
	EXPECT_EQ(merged.parts[1].scans, b.keyframes.size());	// one pose per keyframe replayed
	// Each replayed keyframe's pose against the truth at its scan's time.
	const pmslam::testing::CarmenLogSpec spec;
	const double t0 = spec.t0 + spec.dt * double(log.cut) + 30;
	double worst = 0;
	for (std::size_t i = log.cut; i < merged.trajectory.size(); ++i)
	{
		const auto k = log.cut + std::size_t(std::lround((merged.trajectory[i].timestamp - t0) / spec.dt));
		ASSERT_LT(k, log.truth.size());
		const TPose2D truth = pmslam::testing::relativeToFirst(log.truth, k);
		worst = std::max(worst, std::hypot(merged.trajectory[i].x - truth.x, merged.trajectory[i].y - truth.y));
	}
	EXPECT_LT(worst, 0.05);
}

namespace
{
// Two furnished rooms joined by a corridor 6 m long and 1 m wide: a west room (x 0-8 m), the corridor
// (x 8-14 m, y 2.5-3.5 m) and an east room (x 14-22 m), each 6 m deep, their furniture different.
pmslam::testing::SyntheticWorld twoRooms()
{
	pmslam::testing::SyntheticWorld w;
	for (double x0 : {0.0, 14.0})
	{
		const double x1 = x0 + 8;
		w.segments.push_back({x0, 0, x1, 0});
		w.segments.push_back({x0, 6, x1, 6});
		// The outer wall whole, the corridor's side with a door 1 m wide.
		const double outer = x0 == 0 ? x0 : x1, inner = x0 == 0 ? x1 : x0;
		w.segments.push_back({outer, 0, outer, 6});
		w.segments.push_back({inner, 0, inner, 2.5});
		w.segments.push_back({inner, 3.5, inner, 6});
	}
	w.segments.push_back({8, 2.5, 14, 2.5});
	w.segments.push_back({8, 3.5, 14, 3.5});
	w.addBox(2, 4, 3, 4.5);	 // the west room's furniture
	w.addBox(5.5, 1.8, 5.9, 2.2);
	w.addBox(6.5, 4.2, 7.3, 4.6);
	w.addBox(16.5, 4.6, 17.5, 5.4);  // the east room's
	w.addBox(20.8, 0.4, 21.4, 1.6);
	w.addBox(19, 4.0, 19.3, 4.3);
	return w;
}

// Through `waypoints` (x, y) at 0.1 m per scan, turning on the spot 0.1 rad per scan at each.
std::vector<TPose2D> drive(const std::vector<std::pair<double, double>>& waypoints)
{
	std::vector<TPose2D> out;
	double phi = std::atan2(waypoints[1].second - waypoints[0].second, waypoints[1].first - waypoints[0].first);
	for (std::size_t w = 0; w + 1 < waypoints.size(); ++w)
	{
		const auto [x0, y0] = waypoints[w];
		const auto [x1, y1] = waypoints[w + 1];
		const double heading = std::atan2(y1 - y0, x1 - x0);
		for (double d = mrpt::math::wrapToPi(heading - phi); std::abs(d) > 1e-9; d = mrpt::math::wrapToPi(heading - phi))
		{
			phi += std::clamp(d, -0.1, 0.1);
			out.push_back({x0, y0, phi});
		}
		const double len = std::hypot(x1 - x0, y1 - y0);
		for (double s = 0; s < len; s += 0.1) out.push_back({x0 + s / len * (x1 - x0), y0 + s / len * (y1 - y0), phi});
	}
	return out;
}
}  // namespace

// A second robot that starts where the first never went: its session begins in the east room, and only
// its way back through the corridor into the west room overlaps the first robot's map. The search goes
// along it until the west room decides, and the place found there is carried back to its first scan by
// its own scans' motion: every pose of both sessions in the first one's frame, where the truth has them.
// The same for its raw log. The two rooms are congruent by a half turn and furnished differently: before the
// search went along on more evidence (D54), the east room was taken for the west one turned round, 19 m off.
TEST(Sessions, ASecondRobotThatStartsOffTheMapMergesWhereItComesOntoIt)
{
	pmslam::testing::ScratchDir dir("sessions-off-map");
	const auto world = twoRooms();
	const auto truthA = drive({{1.5, 3}, {7, 3}, {7, 1}, {1, 1}, {1, 3}, {4, 3}});
	const auto truthB = drive({{20.5, 3}, {18, 3}, {18, 1.0}, {15.5, 1.0}, {15.5, 3}, {7, 3}, {7, 1}, {2, 1}, {2, 3}});
	pmslam::testing::CarmenLogSpec spec;
	using pmslam::testing::driftingOdometry;
	const std::string a = dir.write("a.clf", pmslam::testing::carmenLog(world, truthA, driftingOdometry(truthA, 1.02, 0.02), spec));
	spec.t0 += 3600;  // another day; B's odometry starts elsewhere and drifts its own way
	const auto odoB = driftingOdometry(truthB, 0.98, -0.03, CPose2D(-40, 12, 2.0));
	const std::string b = dir.write("b.clf", pmslam::testing::carmenLog(world, truthB, odoB, spec));
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("A")) + " " + quote(a)).exitCode, 0);
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("B")) + " " + quote(b)).exitCode, 0);
	// B's poses against the truth in A's frame (A's first pose at the origin), by timestamp.
	const auto worstOfB = [&](const pmslam::Trajectory& t) {
		double worst = 0;
		std::size_t n = 0;
		for (const auto& p : t)
		{
			const double k = (p.timestamp - spec.t0) / spec.dt;
			if (k < -0.5) continue;	 // A's
			const TPose2D truth = (CPose2D(truthB[std::size_t(std::lround(k))]) - CPose2D(truthA[0])).asTPose();
			worst = std::max(worst, std::hypot(p.x - truth.x, p.y - truth.y));
			++n;
		}
		return std::make_pair(worst, n);
	};
	for (const std::string& second : {dir.path("B"), b})
	{
		const std::string out = dir.path(second == b ? "AB-log" : "AB");
		const auto r =
			run(quote(kApp) + " --continue " + quote(dir.path("A")) + " --out " + quote(out) + " " + quote(second));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		EXPECT_NE(r.output.find("global localisation: start found at"), std::string::npos) << r.output;
		const auto [worst, poses] = worstOfB(pmslam::loadTrajectory(out + "/trajectory.txt"));
		std::printf("%s: %zu poses of B, worst %.3f m from the truth\n", second.c_str(), poses, worst);
		EXPECT_GT(poses, second == b ? truthB.size() - 1 : 20u);
		EXPECT_LT(worst, 0.1);
	}
}

// A log of another building, no stretch of it on the session's map, is refused after the search went along all
// of it, not forced onto a look-alike.
TEST(Sessions, ALogOfAnotherPlaceIsNotContinued)
{
	const std::string sample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
	if (!fs::exists(sample)) GTEST_SKIP() << sample << " not installed (comes with mrpt-common)";
	pmslam::testing::ScratchDir dir("sessions-foreign");
	const CutLog log(dir);
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("a")) + " " + quote(log.first)).exitCode, 0);
	const auto r = run(quote(kApp) + " --continue " + quote(dir.path("a")) + " --out " + quote(dir.path("out")) + " " +
					   quote(sample));
	EXPECT_EQ(r.exitCode, 3) << r.output;
	EXPECT_NE(r.output.find("no place on " + dir.path("a") + "'s map explains any stretch of the log"), std::string::npos)
		<< r.output;
	EXPECT_FALSE(fs::exists(dir.path("out") + "/trajectory.txt"));
}

// Lifelong (--lifelong): a room whose cabinet moved is driven again 19 times, each run continuing the last.
// Earlier keyframes the new run covers give way: after the first pass with the cabinet moved the map shows
// it where it now stands and no longer where it stood, and the keyframes stay as many as one pass makes
// (without --lifelong they grow by a pass each time).
TEST(Sessions, LifelongMapsFollowAMovedCabinetWithBoundedKeyframes)
{
	pmslam::testing::ScratchDir dir("sessions-lifelong");
	const auto path = pmslam::testing::roomPath(80);
	const auto before = pmslam::testing::furnishedRoom();
	pmslam::testing::SyntheticWorld after;	// the cabinet at (1.0..1.95, 0.95..1.7) moved to (-1.0..-0.25, 1.5..2.25)
	after.addBox(-4.025, -3.025, 5.025, 3.025);
	after.addBox(-0.975, 1.525, -0.225, 2.275);
	after.addBox(-2.475, -1.975, -1.775, -1.275);
	after.segments.push_back({-4.025, 0.525, -2.025, 0.525});
	after.segments.push_back({3.025, -3.025, 3.025, -1.525});
	const auto odo = pmslam::testing::driftingOdometry(path, 1.02, 0.02);
	const std::string first = dir.write("before.clf", pmslam::testing::carmenLog(before, path, odo, {}));
	const std::string again = dir.write("after.clf", pmslam::testing::carmenLog(after, path, odo, {}));
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("s0")) + " " + quote(first)).exitCode, 0);
	const std::size_t onePass = pmslam::loadSession(dir.path("s0")).keyframes.size();
	// The map frame is the first pose's: world (x, y) is map (x + 1.5, y + 0.5).
	// Occupied: a cell within 0.1 m that MRPT's grid holds as more likely occupied than free.
	const auto occupied = [&](const std::string& folder, double x, double y) {
		const auto map = pmslam::loadSession(folder).grid;
		for (double dy = -0.1; dy <= 0.1; dy += 0.05)
			for (double dx = -0.1; dx <= 0.1; dx += 0.05)
				if (map.getPos(float(x + dx + 1.5), float(y + dy + 0.5)) < 0.5f) return true;
		return false;
	};
	EXPECT_TRUE(occupied(dir.path("s0"), 1.5, 0.975));	// the cabinet's south face, where it stood
	EXPECT_FALSE(occupied(dir.path("s0"), -0.6, 1.525));  // and where it will stand
	std::string last = dir.path("s0");
	for (int pass = 1; pass < 20; ++pass)
	{
		const std::string out = dir.path("s" + std::to_string(pass));
		const auto r = run(quote(kApp) + " --quiet --lifelong --continue " + quote(last) + " --out " + quote(out) + " " +
						   quote(again));
		ASSERT_EQ(r.exitCode, 0) << "pass " << pass << "\n" << r.output;
		last = out;
		const pmslam::Session s = pmslam::loadSession(out);
		EXPECT_LE(s.keyframes.size(), 2 * onePass) << "pass " << pass;
		ASSERT_TRUE(s.graph);
		EXPECT_EQ(s.graph->nodeCount(), s.keyframes.size());
		EXPECT_EQ(s.trajectory.size(), path.size() * std::size_t(pass + 1));
		if (pass == 2)
		{
			EXPECT_FALSE(occupied(out, 1.5, 0.975)) << "pass " << pass;  // where the cabinet stood
			EXPECT_TRUE(occupied(out, -0.6, 1.525)) << "pass " << pass;  // its south face where it stands
		}
	}
}

// What cannot be continued is said in one line naming the file, exit status 2, and nothing is written.
TEST(Sessions, WhatCannotBeContinuedIsAOneLineError)
{
	pmslam::testing::ScratchDir dir("sessions-bad");
	const CutLog log(dir);
	ASSERT_EQ(run(quote(kApp) + " --quiet --out " + quote(dir.path("a")) + " " + quote(log.first)).exitCode, 0);
	const auto tryContinue = [&](const std::string& from, const std::string& expected) {
		const auto r = run(quote(kApp) + " --quiet --continue " + quote(from) + " --out " + quote(dir.path("out")) +
						   " " + quote(log.second));
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
		EXPECT_FALSE(fs::exists(dir.path("out") + "/trajectory.txt")) << from;
	};
	tryContinue(dir.path("nowhere"), "not a folder");
	// Into itself: the session continued is never modified.
	const auto r = run(quote(kApp) + " --quiet --continue " + quote(dir.path("a")) + " --out " + quote(dir.path("a")) +
					   " " + quote(log.second));
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("is never modified: give another --out"), std::string::npos) << r.output;
	// A newer format, parts that do not add up, a damaged simple map, another resolution.
	fs::copy(dir.path("a"), dir.path("newer"));
	std::string ini = pmslam::testing::readText(dir.path("a") + "/session.ini");
	dir.write("newer/session.ini", std::regex_replace(ini, std::regex("format = 1"), "format = 7"));
	tryContinue(dir.path("newer"), "format 7 is newer than this pmslam reads (1)");
	fs::copy(dir.path("a"), dir.path("short"));
	dir.write("short/session.ini", std::regex_replace(ini, std::regex("scans = 80"), "scans = 79"));
	tryContinue(dir.path("short"), "its parts have 79 scans, trajectory.txt 80");
	fs::copy(dir.path("a"), dir.path("graph"));
	dir.write("graph/graph.graph", "VERTEX_SE2 0 0 0 0\n");
	tryContinue(dir.path("graph"), "graph/graph.graph: 1 nodes for");
	fs::copy(dir.path("a"), dir.path("damaged"));
	dir.write("damaged/map.simplemap.gz", "not a simple map");
	tryContinue(dir.path("damaged"), "damaged/map.simplemap.gz: not an MRPT simple map");
	fs::copy(dir.path("a"), dir.path("coarse"));
	dir.write("coarse/session.ini", std::regex_replace(ini, std::regex("resolution = 0.05"), "resolution = 0.1"));
	tryContinue(dir.path("coarse"), "its map is at 0.100000 m per cell");
}
