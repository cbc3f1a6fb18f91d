// pm-slam-app end to end on synthetic Carmen logs with known truth, where tracking is hard:
// a stretch of scans from another world (tracking lost: said loudly, exit 3), a turn into an
// unmapped corridor (the map must grow there), and wheel slips (the wide search recovers).
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/io/Trajectory.h>
#include <pmslam/slam/Tracker.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <regex>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;
using mrpt::math::TPose2D;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kInject = PMSLAM_BINARY_DIR "/bin/pm-fault-inject";
const bool kVerbose = std::getenv("PMSLAM_TEST_VERBOSE") != nullptr;

struct AppRun
{
	RunResult result;
	pmslam::Trajectory traj;
	std::vector<std::vector<double>> timing;  // the columns of timing.txt, per scan
	fs::path out;
};

AppRun mapLog(const ScratchDir& d, const std::string& log, const std::string& name, const std::string& extra = "")
{
	AppRun a;
	a.out = d.path("out-" + name);
	a.result = run(quote(kApp) + " --no-progress " + extra + " --out " + quote(a.out.string()) + " " + quote(log));
	if (fs::exists(a.out / "trajectory.txt")) a.traj = pmslam::loadTrajectory((a.out / "trajectory.txt").string());
	std::ifstream in(a.out / "timing.txt");
	for (std::string line; std::getline(in, line);)
	{
		if (line.empty() || line[0] == '#') continue;
		std::istringstream ss(line);
		std::vector<double> row;
		for (double v; ss >> v;) row.push_back(v);
		a.timing.push_back(row);
	}
	if (kVerbose) std::cout << name << ": exit " << a.result.exitCode << "\n" << a.result.output;
	return a;
}

/** Position error of scan k against the truth relative to its first pose. */
double errorAt(const pmslam::Trajectory& traj, const std::vector<TPose2D>& truth, std::size_t k)
{
	const auto t = relativeToFirst(truth, k);
	return std::hypot(traj[k].x - t.x, traj[k].y - t.y);
}
double maxError(const pmslam::Trajectory& traj, const std::vector<TPose2D>& truth)
{
	double m = 0;
	for (std::size_t k = 0; k < std::min(traj.size(), truth.size()); ++k) m = std::max(m, errorAt(traj, truth, k));
	return m;
}

const fs::path kDatasets = PMSLAM_SOURCE_DIR "/../shared/datasets";

/** Benchmark log `name`'s Carmen file in ../shared/datasets (absent there: the tests that need it skip). */
fs::path benchmarkLog(const std::string& name) { return kDatasets / name / (name + ".clf"); }

/** One run of bench/robustness.sh: `fault` (pm-fault-inject's arguments, the seed included) injected into
 * benchmark log `name`, mapped with the defaults (exit 0 expected), scored on the log's relations and
 * printed as `label`. */
pmslam::RelativePoseErrors mapFaultedBenchmarkLog(const std::string& name, const std::string& fault,
												  const std::string& scratch, const std::string& label)
{
	ScratchDir d(scratch);
	const std::string faulted = d.path("faulted.clf");
	const auto inject = run(quote(kInject) + " " + fault + " " + quote(benchmarkLog(name).string()) + " " + quote(faulted));
	EXPECT_EQ(inject.exitCode, 0) << inject.output;
	if (inject.exitCode != 0)
	{
		pmslam::RelativePoseErrors none;
		none.transMean = none.rotMeanDeg = std::nan("");  // fails every bound the tests set
		return none;
	}
	const auto a = mapLog(d, faulted, "defaults");
	EXPECT_EQ(a.result.exitCode, 0) << a.result.output;
	const auto rel = pmslam::loadRelations((kDatasets / name / (name + ".relations")).string());
	const auto err = pmslam::evaluateRelativePoses(a.traj, rel);
	std::cout << label << ": " << err.transMean << " m, " << err.rotMeanDeg << " deg\n";
	return err;
}

/** Longest run of consecutive scans with tracking state 3 (match rejected) in timing.txt. */
std::size_t longestRejectedRun(const AppRun& a)
{
	std::size_t best = 0, cur = 0;
	for (const auto& row : a.timing)
	{
		cur = row.size() >= 9 && row[8] == 3 ? cur + 1 : 0;
		best = std::max(best, cur);
	}
	return best;
}

std::size_t countLines(const std::string& text, const std::string& what)
{
	std::size_t n = 0;
	for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
	return n;
}

/** The lines of a Carmen log written by carmenLog without ODOM lines: two header lines, one per scan. */
std::vector<std::string> splitLines(const std::string& s)
{
	std::vector<std::string> v;
	std::istringstream ss(s);
	for (std::string l; std::getline(ss, l);) v.push_back(l);
	return v;
}

/** A world nothing of the furnished room looks like: a field of slanted sticks at odd angles. */
SyntheticWorld stickField()
{
	SyntheticWorld w;
	std::mt19937 rng(42);
	std::uniform_real_distribution<double> u(-9, 9), a(0, M_PI);
	for (int i = 0; i < 60; ++i)
	{
		const double x = u(rng), y = u(rng), t = a(rng);
		w.segments.push_back({x, y, x + 0.6 * std::cos(t), y + 0.6 * std::sin(t)});
	}
	return w;
}

/** An L-shaped building: corridor 1 along +x (y in [-1, 1], x in [-1, L1]), turning left at its end
 * into corridor 2 along +y (x in [L1 - W2, L1], y from 1 to L2). Both have niches and pillars so that
 * they can be matched along their length. */
struct LBuilding
{
	double L1 = 20, W2 = 2, L2 = 20;
	double door = 0;  ///< > 0: corridor 2 is entered through a door this wide in a wall at y = 1
	SyntheticWorld world() const
	{
		SyntheticWorld w;
		const double x2 = L1 - W2;	// corridor 2's left wall
		w.segments.push_back({-1, -1, L1, -1});
		w.segments.push_back({L1, -1, L1, L2});
		w.segments.push_back({L1, L2, x2, L2});
		w.segments.push_back({x2, L2, x2, 1});
		w.segments.push_back({x2, 1, -1, 1});
		if (door > 0)
		{
			const double xc = L1 - W2 / 2;
			w.segments.push_back({x2, 1, xc - door / 2, 1});
			w.segments.push_back({xc + door / 2, 1, L1, 1});
		}
		w.segments.push_back({-1, 1, -1, -1});
		// Corridor 1: boxes against the walls every 3 m, alternating sides.
		for (int i = 0; i * 3.0 + 1.0 < x2 - 1; ++i)
		{
			const double x = 1.0 + 3.0 * i;
			if (i % 2)
				w.addBox(x, 0.7, x + 0.4, 1.0);
			else
				w.addBox(x, -1.0, x + 0.5, -0.75);
		}
		// Corridor 2: the same, along y.
		for (int i = 0; i * 2.5 + 3.0 < L2 - 1; ++i)
		{
			const double y = 3.0 + 2.5 * i;
			if (i % 2)
				w.addBox(x2, y, x2 + 0.3, y + 0.4);
			else
				w.addBox(L1 - 0.25, y, L1, y + 0.5);
		}
		return w;
	}
	/** Along corridor 1 to the corner, a turn on the spot in `turnScans` scans, up corridor 2. */
	std::vector<TPose2D> path(double step, std::size_t turnScans) const
	{
		std::vector<TPose2D> p;
		const double xc = L1 - W2 / 2;
		for (double x = 0; x < xc; x += step) p.push_back({x, 0, 0});
		for (std::size_t k = 0; k < turnScans; ++k) p.push_back({xc, 0, M_PI / 2 * double(k) / double(turnScans)});
		for (double y = 0; y < L2 - 2; y += step) p.push_back({xc, y, M_PI / 2});
		return p;
	}
};
}  // namespace

TEST(Robustness, LostTrackingIsLoud)
{
	// 40 s in the furnished room; from t0+12 s to t0+27 s the scans come from another world.
	ScratchDir d("robust-lost");
	const auto truth = roomPath(400);
	CarmenLogSpec spec;
	const auto room = splitLines(carmenLog(furnishedRoom(), truth, truth, spec));
	const auto other = splitLines(carmenLog(stickField(), truth, truth, spec));
	ASSERT_EQ(room.size(), truth.size() + 2);
	const double from = spec.t0 + 12.0, to = spec.t0 + 27.0;
	std::string text;
	for (std::size_t i = 0; i < room.size(); ++i)
	{
		const double t = spec.t0 + spec.dt * (double(i) - 2);
		text += (i >= 2 && t >= from - 1e-9 && t < to - 1e-9 ? other[i] : room[i]) + "\n";
	}
	const auto log = d.write("lost.clf", text);

	// The other world's scans land over the room's mapped space: not new ground, so they stay
	// rejected (inserting them at the odometry pose would draw the other world into the room).
	const auto a = mapLog(d, log, "lost");
	EXPECT_EQ(a.result.output.find("see new ground"), std::string::npos) << a.result.output;
	EXPECT_EQ(a.result.exitCode, 3) << a.result.output;
	ASSERT_EQ(a.traj.size(), truth.size()) << a.result.output;
	// One warning, whose span covers the injected stretch (and ends soon after it).
	ASSERT_EQ(countLines(a.result.output, "tracking lost from t="), 1u) << a.result.output;
	std::smatch m;
	ASSERT_TRUE(std::regex_search(a.result.output, m, std::regex(R"(tracking lost from t=([0-9.]+) to t=([0-9.]+))")));
	const double gapFrom = std::stod(m[1]), gapTo = std::stod(m[2]);
	EXPECT_GE(gapFrom, from - 1e-6);
	EXPECT_LE(gapFrom, from + 0.5);
	EXPECT_GE(gapTo, to - 1e-6);
	EXPECT_LE(gapTo, to + 1.0);
	EXPECT_NE(a.result.output.find("tracking: LOST (exit status 3)"), std::string::npos) << a.result.output;
	// timing.txt: rejected (3) throughout the stretch, never outside the warned span.
	ASSERT_EQ(a.timing.size(), truth.size());
	std::size_t rejectedInside = 0, inside = 0;
	for (const auto& row : a.timing)
	{
		ASSERT_GE(row.size(), 10u);
		const double t = row[0];
		if (t >= gapFrom - 1e-6 && t < gapTo - 1e-6)
		{
			++inside;
			rejectedInside += row[8] == 3;
		}
		else
			EXPECT_NE(row[8], 3) << "t=" << t;
	}
	EXPECT_GE(inside, 150u);
	EXPECT_EQ(rejectedInside, inside);
	// Back in the room the robot is where it should be (odometry is exact here).
	EXPECT_LT(errorAt(a.traj, truth, truth.size() - 1), 0.05);

	// A larger --max-untracked: exit 0, but the warning stays.
	const auto b = mapLog(d, log, "lost-tolerated", "--max-untracked 60");
	EXPECT_EQ(b.result.exitCode, 0) << b.result.output;
	EXPECT_EQ(countLines(b.result.output, "tracking lost from t="), 1u) << b.result.output;
	// Not "ok": the run went longer than 3 s without an accepted match, and found its way back.
	EXPECT_NE(b.result.output.find("tracking: recovered"), std::string::npos) << b.result.output;

	// Were they new ground (here: a threshold of 1 % of the scan in unobserved cells), 2 s into the
	// stretch they would go in at the odometry pose, loudly, and tracking would go on from there.
	const auto c = mapLog(d, log, "lost-new-ground", "--set MappingApplication.newGroundUnexplored=0.01");
	EXPECT_EQ(c.result.exitCode, 0) << c.result.output;
	ASSERT_TRUE(std::regex_search(c.result.output, m,
								  std::regex(R"(warning: at t=([0-9.]+), after ([0-9.]+) s without an accepted match, the scans see new ground)")))
		<< c.result.output;
	EXPECT_NEAR(std::stod(m[1]), from + 2.0, 0.5);
	EXPECT_NEAR(std::stod(m[2]), 2.0, 0.5);
	std::size_t reanchored = 0;
	for (const auto& row : c.timing) reanchored += row[8] == 4;
	EXPECT_GE(reanchored, 1u);
	EXPECT_NE(c.result.output.find("scans inserted at the odometry pose on new ground"), std::string::npos);
}

// D57: scans reported while lost sit where the odometry predicts them, and across the loss that
// prediction carries one error, which the match ending the loss measures. In the furnished room the
// wheels slip (0.25 m and 10 degrees) as 2.5 s of scans from another world begin; they are rejected
// and reported at the slipped prediction. Back in the room the wide search finds the robot, and the
// stretch is moved by what it measured: within 0.004 m of the truth (0.27 m without D57).
TEST(Robustness, ScansReportedWhileLostAreMovedByTheErrorTheMatchEndingTheLossMeasures)
{
	ScratchDir d("robust-lost-revised");
	const auto truth = roomPath(300);
	CarmenLogSpec spec;
	const std::size_t from = 120, to = 145;  // scans from the other world: t0 + 12 s to t0 + 14.5 s
	const mrpt::poses::CPose2D at(truth[from]);
	const mrpt::poses::CPose2D slip = at + mrpt::poses::CPose2D(0.15, 0.2, mrpt::DEG2RAD(10.0)) + (-at);
	std::vector<TPose2D> odometry = truth;
	for (std::size_t k = from; k < truth.size(); ++k) odometry[k] = (slip + mrpt::poses::CPose2D(truth[k])).asTPose();
	const auto room = splitLines(carmenLog(furnishedRoom(), truth, odometry, spec));
	const auto other = splitLines(carmenLog(stickField(), truth, odometry, spec));
	std::string text;
	for (std::size_t i = 0; i < room.size(); ++i) text += (i >= from + 2 && i < to + 2 ? other[i] : room[i]) + "\n";
	const auto log = d.write("lost-slip.clf", text);

	const auto a = mapLog(d, log, "lost-slip");
	ASSERT_EQ(a.traj.size(), truth.size()) << a.result.output;
	std::size_t rejected = 0;
	double worst = 0;
	for (std::size_t k = from; k < to; ++k)
	{
		rejected += a.timing[k][8] == 3;
		worst = std::max(worst, errorAt(a.traj, truth, k));
	}
	EXPECT_GE(rejected, to - from - 2);	 // lost through the stretch
	EXPECT_LT(worst, 0.05);
	EXPECT_LT(errorAt(a.traj, truth, truth.size() - 1), 0.05);
	std::cout << "lost for " << rejected << " scans after a slip: worst error of their reported poses " << worst << " m\n";
}

TEST(Robustness, LostTrackingIsLoudWhateverTheStampsSay)
{
	// A simulator that stamps each scan with the time it wrote it: 0.3 ms apart. 400 scans of the
	// room, then 500 from another world (rejected: 0.15 s by the stamps, but 500 scans, 5 s of the
	// fastest lidar's), then 200 of the room. Counted by the stamps alone, this said "tracking: ok"
	// and exit 0 (TrackingGap::length()).
	ScratchDir d("robust-lost-fast");
	const auto truth = roomPath(1100);
	CarmenLogSpec spec;
	spec.dt = 0.0003;
	const auto room = splitLines(carmenLog(furnishedRoom(), truth, truth, spec));
	const auto other = splitLines(carmenLog(stickField(), truth, truth, spec));
	std::string text;
	for (std::size_t i = 0; i < room.size(); ++i) text += (i >= 2 + 400 && i < 2 + 900 ? other[i] : room[i]) + "\n";
	const auto a = mapLog(d, d.write("fast.clf", text), "fast", "--max-untracked 4");
	EXPECT_EQ(a.result.exitCode, 3) << a.result.output;
	EXPECT_NE(a.result.output.find("tracking: LOST (exit status 3)"), std::string::npos) << a.result.output;
	ASSERT_EQ(countLines(a.result.output, "tracking lost from t="), 1u) << a.result.output;
	std::smatch m;
	ASSERT_TRUE(std::regex_search(a.result.output, m, std::regex(R"(\(([0-9.]+) s of log, ([0-9]+) rejected matches)")));
	EXPECT_GE(std::stoul(m[2]), 400u);	// nearly all of the other world's scans
	EXPECT_NEAR(std::stod(m[1]), double(std::stoul(m[2])) / pmslam::TrackingGap::kMaxScanRate, 0.05);
}

namespace
{
/** Fraction of the points along a wall (x0 + s·(x1−x0), …) with an occupied cell within 0.1 m in the map. */
double wallMapped(const mrpt::maps::COccupancyGridMap2D& g, double x0, double y0, double x1, double y1)
{
	std::size_t hit = 0, n = 0;
	for (double s = 0; s <= 1.0; s += 0.01, ++n)
	{
		const double x = x0 + s * (x1 - x0), y = y0 + s * (y1 - y0);
		bool occ = false;
		for (double dx = -0.1; dx <= 0.1 + 1e-9; dx += 0.05)
			for (double dy = -0.1; dy <= 0.1 + 1e-9; dy += 0.05)
			{
				const int cx = g.x2idx(x + dx), cy = g.y2idx(y + dy);
				if (cx >= 0 && cy >= 0 && cx < int(g.getSizeX()) && cy < int(g.getSizeY()) && g.getCell(cx, cy) < 0.3f)
					occ = true;
			}
		hit += occ;
	}
	return double(hit) / double(n);
}

/** The L-shaped building's log: 0.05 m per scan, a turn on the spot in 10 scans, odometry 2 % long
 * and turning 2°/m. */
struct LLog
{
	LBuilding b;
	std::vector<TPose2D> truth;
	std::string write(const ScratchDir& d)
	{
		truth = b.path(0.05, 10);
		const auto odo = driftingOdometry(truth, 1.02, 2.0 * M_PI / 180);
		return d.write("l.clf", carmenLog(b.world(), truth, odo, CarmenLogSpec()));
	}
};
}  // namespace

// The overlap rule (minOverlapGoodness) is not shown to matter here: with
// --set MappingApplication.minOverlapGoodness=0 this world passes too (no match is rejected), as did
// every variant tried (a turn in 1 scan, 0.3 m per scan, a 5-8 m laser range, a 0.9 m door into a
// 6 m wide corridor 2): each scan adds too little new ground for the goodness to fall below minGoodness.
TEST(Robustness, TurnIntoAnUnmappedCorridorIsTrackedAndMapped)
{
	ScratchDir d("robust-l");
	LLog l;
	const auto log = l.write(d);
	const auto a = mapLog(d, log, "l");
	ASSERT_EQ(a.result.exitCode, 0) << a.result.output;
	ASSERT_EQ(a.traj.size(), l.truth.size());
	// Measured from 2 m before the corner on: the start of this noise-free log is a separate weakness.
	// The first scans snap back to the first keyframe (its far walls are dotted, and a scan from a
	// little further on fits the dots best where it was): the SLAM then lags the truth along corridor 1
	// by up to 0.8 m, depending on the arithmetic of the cells the walls fall on, exactly at cell
	// edges here (the same log started one scan later lags 0.7 m with every version so far).
	std::size_t t0 = 0;
	while (t0 < l.truth.size() && l.truth[t0].x < l.b.L1 - l.b.W2 / 2 - 2) ++t0;
	ASSERT_LT(t0, l.truth.size());
	const auto lagged = relativeToFirst(l.truth, t0);
	const double ox = a.traj[t0].x - lagged.x, oy = a.traj[t0].y - lagged.y;
	std::cout << "along corridor 1 the SLAM lags by (" << ox << ", " << oy << ") m\n";
	ASSERT_LT(std::abs(a.traj[t0].yaw - lagged.phi), mrpt::DEG2RAD(1.0));
	double worst = 0;
	for (std::size_t k = t0; k < l.truth.size(); ++k)
	{
		const auto t = relativeToFirst(l.truth, k);
		worst = std::max(worst, std::hypot(a.traj[k].x - ox - t.x, a.traj[k].y - oy - t.y));
	}
	const auto end = relativeToFirst(l.truth, l.truth.size() - 1);
	EXPECT_LT(std::hypot(a.traj.back().x - ox - end.x, a.traj.back().y - oy - end.y), 0.1);
	EXPECT_LT(worst, 0.15);
	EXPECT_LE(longestRejectedRun(a), 5u);
	EXPECT_EQ(a.result.output.find("tracking lost"), std::string::npos) << a.result.output;
	// Corridor 2's walls (beyond what corridor 1 sees of them) are in the map, where the SLAM's frame
	// (shifted by its lag) has them.
	mrpt::maps::COccupancyGridMap2D grid;
	pmslam::loadGridMapGz((a.out / "map.gridmap.gz").string(), grid);
	const double x2 = l.b.L1 - l.b.W2;
	EXPECT_GT(wallMapped(grid, l.b.L1 + ox, 4.0 + oy, l.b.L1 + ox, l.b.L2 - 2 + oy), 0.9);
	EXPECT_GT(wallMapped(grid, x2 + ox, 4.0 + oy, x2 + ox, l.b.L2 - 2 + oy), 0.9);
	EXPECT_GT(wallMapped(grid, l.b.L1 + ox, l.b.L2 + oy, x2 + ox, l.b.L2 + oy), 0.9);  // its end wall
}

TEST(Robustness, HeadingSlipsKeepTheTrajectoryOnTheTruth)
{
	ScratchDir d("robust-slip");
	LLog l;
	const auto clean = l.write(d);
	const std::string slipped = d.path("slip.clf");
	const auto inj = run(quote(kInject) + " --fault slip --count 3 --seed 2 " + quote(clean) + " " + quote(slipped));
	ASSERT_EQ(inj.exitCode, 0) << inj.output;
	ASSERT_EQ(countLines(inj.output, "fault slip at"), 3u) << inj.output;

	const auto c = mapLog(d, clean, "clean");
	ASSERT_EQ(c.result.exitCode, 0) << c.result.output;
	const double cleanErr = maxError(c.traj, l.truth);
	const auto s = mapLog(d, slipped, "slip");
	ASSERT_EQ(s.result.exitCode, 0) << s.result.output;
	ASSERT_EQ(s.traj.size(), l.truth.size());
	const double slipErr = maxError(s.traj, l.truth);
	EXPECT_LT(slipErr, 2 * cleanErr + 0.02) << "clean " << cleanErr;
	const auto o = mapLog(d, slipped, "slip-nowide", "--set MappingApplication.wideSearchBelowGoodness=0");
	const double oldErr = o.traj.size() == l.truth.size() ? maxError(o.traj, l.truth) : 1e9;
	std::cout << "max error: clean " << cleanErr << " m, 3 slips " << slipErr << " m, 3 slips without the wide search "
			  << oldErr << " m\n";
	// Not asserted: on this world PM alone converges from the slips' 18-30 degree, 0.3 m prediction
	// errors (goodness ~0.97 after ~60 iterations), so the run without the wide search is just as good
	// and the wide search never runs. A world that shows the difference is still to be found.
	EXPECT_LT(oldErr, 2 * cleanErr + 0.02);
}

namespace
{
// Room A (west), a corridor east out of it that turns north, and room B at its north end, out of
// sight from room A and from the corridor's east leg.
SyntheticWorld twoRooms()
{
	SyntheticWorld w;
	auto wall = [&](double x0, double y0, double x1, double y1) { w.segments.push_back({x0, y0, x1, y1}); };
	// Room A, 6 x 6 m, a door in its east wall; a few boxes.
	wall(-3, -3, 3, -3), wall(-3, 3, 3, 3), wall(-3, -3, -3, 3), wall(3, -3, 3, -0.6), wall(3, 0.6, 3, 3);
	w.addBox(-2, 1.5, -1.2, 2.2), w.addBox(0.5, -2.5, 1.4, -1.9), w.addBox(-2.5, -1.0, -2.0, -0.2);
	// Corridor: east leg y in [-0.6, 0.6] to x = 13, north leg x in [11.8, 13] to y = 10.
	wall(3, -0.6, 13, -0.6), wall(3, 0.6, 11.8, 0.6), wall(13, -0.6, 13, 10), wall(11.8, 0.6, 11.8, 10);
	// Room B, 7 x 7 m above it, open at the corridor; boxes of its own.
	wall(9, 10, 11.8, 10), wall(13, 10, 16, 10), wall(9, 17, 16, 17), wall(9, 10, 9, 17), wall(16, 10, 16, 17);
	w.addBox(10, 15.5, 11, 16.3), w.addBox(14.2, 12, 15.2, 12.6), w.addBox(9.5, 12.5, 10.1, 13.4);
	return w;
}

// From the middle of room A east along the corridor, north up its second leg, into room B.
std::vector<TPose2D> twoRoomsPath()
{
	std::vector<TPose2D> p;
	for (double x = 0; x < 12.4; x += 0.05) p.push_back({x, 0, 0});
	for (int k = 1; k <= 18; ++k) p.push_back({12.4, 0, M_PI / 2 * k / 18});
	for (double y = 0.05; y < 15; y += 0.05) p.push_back({12.4, y, M_PI / 2});
	return p;
}
}  // namespace

TEST(Robustness, AfterALoggingGapOnNewGroundTheMapGrowsAgain)
{
	// Nothing is logged while the robot drives from the corridor's east leg (x = 6) into room B
	// (y = 11); odometry is exact, so where the log resumes its pose is right, but the scans see
	// only walls no scan has seen.
	ScratchDir d("robust-new-ground");
	const auto truth = twoRoomsPath();
	CarmenLogSpec spec;
	const auto lines = splitLines(carmenLog(twoRooms(), truth, truth, spec));
	ASSERT_EQ(lines.size(), truth.size() + 2);
	std::string text;
	std::size_t gapFrom = 0, gapTo = 0;
	for (std::size_t i = 0; i < lines.size(); ++i)
	{
		const bool inGap = i >= 2 && ((truth[i - 2].x > 6 && truth[i - 2].phi == 0) ||
									  (truth[i - 2].phi > 0 && truth[i - 2].y < 11));
		if (inGap && !gapFrom) gapFrom = i - 2;
		if (!inGap && gapFrom && !gapTo) gapTo = i - 2;
		if (!inGap) text += lines[i] + "\n";
	}
	ASSERT_GT(gapTo, gapFrom);
	const auto log = d.write("gap.clf", text);

	const auto a = mapLog(d, log, "new-ground");
	EXPECT_EQ(a.result.exitCode, 0) << a.result.output;
	EXPECT_NE(a.result.output.find("the scans see new ground"), std::string::npos) << a.result.output;
	ASSERT_FALSE(a.traj.empty());
	// The trajectory file has a pose per logged scan: the last one is the truth's last.
	const auto end = relativeToFirst(truth, truth.size() - 1);
	EXPECT_NEAR(a.traj.back().x, end.x, 0.1);
	EXPECT_NEAR(a.traj.back().y, end.y, 0.1);
	mrpt::maps::COccupancyGridMap2D grid;
	pmslam::loadGridMapGz((a.out / "map.gridmap.gz").string(), grid);
	EXPECT_GT(wallMapped(grid, 9.2, 17, 15.8, 17), 0.8);  // room B's far wall

	// Without the new-ground rule the robot stays lost to the end (8 s: exit 3 with --max-untracked 5)
	// and room B never enters the map.
	const auto b = mapLog(d, log, "stay-lost", "--max-untracked 5 --set MappingApplication.newGroundUnexplored=0");
	EXPECT_EQ(b.result.exitCode, 3) << b.result.output;
	mrpt::maps::COccupancyGridMap2D gridB;
	pmslam::loadGridMapGz((b.out / "map.gridmap.gz").string(), gridB);
	EXPECT_LT(wallMapped(gridB, 9.2, 17, 15.8, 17), 0.2);
}

// A worst seed of the fault benchmark (bench/robustness.sh) that a recovery of this round mends, on the
// benchmark log: the fault injected as the benchmark does, mapped with the defaults. After a 60 s logging
// gap (fr079, seed 2) the search finds a place 10 m off (0.71) and another pose scoring about as well:
// relocalizeAmbiguity leaves it undecided and the next scans find the robot; without it the
// re-localisation goes there and nothing brings it back (1.8 m).
TEST(Robustness, AmbiguousReLocalisationAfterAGapWaitsForTheRightPlace)
{
	const fs::path clf = benchmarkLog("fr079");
	if (!fs::exists(clf)) GTEST_SKIP() << clf << " absent: the benchmark logs live in ../shared/datasets beside the project";
	const auto err =
		mapFaultedBenchmarkLog("fr079", "--fault gap --count 2 --seconds 60 --seed 2", "benchmark-fault", "fr079 gap-b seed 2");
	EXPECT_LT(err.transMean, 0.05);	 // 1.5x the clean log's target (a failure is metres)
}

// D16 measured as its "change when" asked: while lost, the window grows with the time matches have been
// rejected, not with the time since the last accepted one. intel with three laser drop-outs of 300 scans
// (odometry going on; a harder level than the fault benchmark's targets, seed 3): after the third the
// prediction is 27 degrees and 1.2 m off and the first match is rejected. Counted from the last accepted match,
// 60 s before, the window opened at once to the whole circle and 8 m, and a corridor turned by 180 degrees
// (goodness 0.75) was taken: 1.18 m. Counted from the rejection, the window grows as the rejections go on and the
// right place is found first.
TEST(Robustness, AfterALongDropOutTheWindowGrowsFromTheFirstRejectionNotFromTheLastMatch)
{
	const fs::path clf = benchmarkLog("intel");
	if (!fs::exists(clf)) GTEST_SKIP() << clf << " absent: the benchmark logs live in ../shared/datasets beside the project";
	const auto err = mapFaultedBenchmarkLog("intel", "--fault dropout --count 3 --scans 300 --seed 3", "benchmark-dropout",
											"intel dropout-c seed 3");
	EXPECT_LT(err.transMean, 0.03);	 // clean 0.0166; the failure is a metre
}

// D53: carried during a 10 s logging gap across a field of sticks, odometry standing still meanwhile:
// the log resumes 16 m from where the tracker predicts (beyond any window its own search reaches), on
// ground the map already has. Without D53 the first scan after the gap was matched in the window at a
// wrong pose (goodness 0.17, its small overlap with the map agreeing: D13) and inserted, and the run
// mapped on from there, 14.4 m off, "tracking: ok". With it, the whole map has a place that explains
// the scan clearly better than the window's answer: nothing is inserted, the scans follow that place,
// and decide for it.
TEST(Robustness, ARobotCarriedOntoMappedGroundDuringAGapIsFoundOnTheWholeMap)
{
	ScratchDir d("robust-carried-gap");
	std::vector<TPose2D> truth;
	for (double x = -6; x < 6; x += 0.05) truth.push_back({x, -6, 0});
	for (int k = 1; k <= 18; ++k) truth.push_back({6, -6, M_PI / 2 * k / 18});
	for (double y = -5.95; y < 6; y += 0.05) truth.push_back({6, y, M_PI / 2});
	for (int k = 1; k <= 18; ++k) truth.push_back({6, 6, M_PI / 2 + M_PI / 2 * k / 18});
	for (double x = 5.95; x > 2; x -= 0.05) truth.push_back({x, 6, M_PI});
	const std::size_t resume = truth.size();
	// Resumed near the start, facing north-east, and on along that heading.
	for (double s = 0; s < 4; s += 0.05) truth.push_back({-5 + s * M_SQRT1_2, -6 + s * M_SQRT1_2, M_PI / 4});
	// Odometry: exact before the gap; after it, the same motion from where the reading stood.
	std::vector<TPose2D> odometry(truth.begin(), truth.begin() + std::ptrdiff_t(resume));
	const mrpt::poses::CPose2D stood(truth[resume - 1]), from(truth[resume]);
	for (std::size_t k = resume; k < truth.size(); ++k)
		odometry.push_back((stood + (mrpt::poses::CPose2D(truth[k]) - from)).asTPose());
	// Two parts with 10 s of log missing between them: the second stamped as if logged on.
	const auto cut = [&](const std::vector<TPose2D>& v, std::size_t from, std::size_t to) {
		return std::vector<TPose2D>(v.begin() + std::ptrdiff_t(from), v.begin() + std::ptrdiff_t(to));
	};
	CarmenLogSpec spec;
	std::string text = carmenLog(stickField(), cut(truth, 0, resume), cut(odometry, 0, resume), spec);
	spec.t0 += spec.dt * double(resume) + 10.0;
	const auto later = splitLines(carmenLog(stickField(), cut(truth, resume, truth.size()),
											cut(odometry, resume, truth.size()), spec));
	ASSERT_EQ(later.size(), truth.size() - resume + 2);
	for (std::size_t i = 2; i < later.size(); ++i) text += later[i] + "\n";  // without its two header lines
	const auto log = d.write("carried.clf", text);

	const auto a = mapLog(d, log, "carried");
	EXPECT_EQ(a.result.exitCode, 0) << a.result.output;
	ASSERT_EQ(a.traj.size(), truth.size());
	// Every scan after the gap where the truth has it, the ones reported while lost included.
	double worst = 0;
	for (std::size_t k = resume; k < truth.size(); ++k) worst = std::max(worst, errorAt(a.traj, truth, k));
	EXPECT_LT(worst, 0.15);
	double before = 0;
	for (std::size_t k = 0; k < resume; ++k) before = std::max(before, errorAt(a.traj, truth, k));
	EXPECT_LT(before, 0.1);
	std::cout << "carried during a gap: worst error after it " << worst << " m, before it " << before << " m\n";
}

// The motion model over a logging gap: the odometry's error grows with the path the robot drove, and
// across a gap that path is unknown; the two readings' difference is only its least. Here the robot
// drives about for 60 s unlogged and the log resumes in room B, 2.9 m from where it stopped, its
// odometry 3 m east of the truth by then. Counted from the readings' difference (5.5 m) the window
// reached 1.05 m and the scans after the gap were put 3.0 m off. Counted from what the robot drives in
// 60 s at its own mean speed so far (0.48 m/s: a 3.4 m window), it reaches the robot: 0.04 m.
TEST(Robustness, AfterALongGapTheWindowCoversWhatTheRobotCouldHaveDriven)
{
	ScratchDir d("robust-long-gap");
	std::vector<TPose2D> truth = twoRoomsPath();
	const std::size_t resume = truth.size();
	// Resumed in room B facing west, and on westwards.
	for (double x = 14.5; x > 10.5; x -= 0.05) truth.push_back({x, 13, M_PI});
	// Odometry: exact before the gap; after it, 3 m east of the truth (the drift of the unlogged drive).
	std::vector<TPose2D> odometry(truth.begin(), truth.begin() + std::ptrdiff_t(resume));
	const mrpt::poses::CPose2D drift(3, 0, 0);
	for (std::size_t k = resume; k < truth.size(); ++k)
		odometry.push_back((drift + mrpt::poses::CPose2D(truth[k])).asTPose());
	const auto cut = [&](const std::vector<TPose2D>& v, std::size_t from, std::size_t to) {
		return std::vector<TPose2D>(v.begin() + std::ptrdiff_t(from), v.begin() + std::ptrdiff_t(to));
	};
	CarmenLogSpec spec;
	std::string text = carmenLog(twoRooms(), cut(truth, 0, resume), cut(odometry, 0, resume), spec);
	spec.t0 += spec.dt * double(resume) + 60.0;
	const auto later = splitLines(carmenLog(twoRooms(), cut(truth, resume, truth.size()),
											cut(odometry, resume, truth.size()), spec));
	ASSERT_EQ(later.size(), truth.size() - resume + 2);
	for (std::size_t i = 2; i < later.size(); ++i) text += later[i] + "\n";
	const auto log = d.write("long-gap.clf", text);

	const auto a = mapLog(d, log, "long-gap");
	EXPECT_EQ(a.result.exitCode, 0) << a.result.output;
	ASSERT_EQ(a.traj.size(), truth.size());
	double worst = 0;
	for (std::size_t k = resume; k < truth.size(); ++k) worst = std::max(worst, errorAt(a.traj, truth, k));
	EXPECT_LT(worst, 0.1);
	std::cout << "after a 60 s gap: worst error " << worst << " m\n";
}

// D56, on a worst seed of the fault benchmark's harder level (intel, three 120 s logging gaps, seed 1):
// after the third gap the robot is 3.2 m and 44 degrees from the prediction, partly on ground the
// gap skipped. The window's best pose explains 0.42 of the scan, but the 79 % of it that overlaps the
// map agrees only 0.53: a wrong pose. Taken and inserted (D7 alone), the run mapped on from it:
// 0.156 m. Not taken after a gap (lost until a scan explains itself), the next scans find the robot.
TEST(Robustness, AfterAGapAPoseTheMapContradictsIsNotTaken)
{
	const fs::path clf = benchmarkLog("intel");
	if (!fs::exists(clf)) GTEST_SKIP() << clf << " absent: the benchmark logs live in ../shared/datasets beside the project";
	const auto err = mapFaultedBenchmarkLog("intel", "--fault gap --count 3 --seconds 120 --seed 1", "benchmark-gap-overlap",
											"intel gap-c seed 1");
	EXPECT_LT(err.transMean, 0.025);	 // clean 0.0166; the failure is 0.156
}
