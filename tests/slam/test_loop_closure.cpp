// Loop closure end to end on synthetic logs the test generates: a ring of corridors around a
// 100 m x 80 m block driven twice with odometry drifting tens of metres. Without loop closure
// the front-end's own drift (it slides along the plain corridors) leaves the second lap metres
// off the first; with it the loop relations are back under 5 cm and every wall is single.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/PerfectMatchSlam.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "RingWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using namespace pmslam::testing;

namespace
{
constexpr double kStep = 0.15;	// m per scan (1.5 m/s at 10 Hz)

struct RingRun
{
	std::vector<TPose2D> truth, final, online;
	std::shared_ptr<const mrpt::maps::COccupancyGridMap2D> grid;
	pmslam::LoopClosureStats stats;
	std::size_t lapScans = 0;
};

// Odometry 3 % long, turning 0.25 degrees per metre too much, with noise: after a lap of 350 m
// it is ~90 degrees and tens of metres off.
std::vector<TPose2D> badOdometry(const std::vector<TPose2D>& truth)
{
	std::mt19937 rng(11);
	std::normal_distribution<double> n(0, 1);
	std::vector<TPose2D> out;
	CPose2D odo;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		if (k)
		{
			const CPose2D d = CPose2D(truth[k]) - CPose2D(truth[k - 1]);
			const double len = std::hypot(d.x(), d.y());
			odo = odo + CPose2D(d.x() * (1.03 + 0.01 * n(rng)), d.y() + 0.003 * n(rng),
								d.phi() + mrpt::DEG2RAD(0.25) * len + mrpt::DEG2RAD(0.2) * n(rng));
		}
		out.push_back(odo.asTPose());
	}
	return out;
}

RingRun drive(const SyntheticWorld& world, const std::vector<TPose2D>& truth, bool loopClosure, double degenerateBelow)
{
	RingRun r;
	r.truth = truth;
	const auto odometry = badOdometry(truth);
	pmslam::PerfectMatchSlam slam;
	slam.LC_options.enabled = loopClosure;
	slam.PM_options.degenerateBelow = degenerateBelow;
	slam.initialize();
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		const double t = 1000 + 0.1 * double(k);
		auto scan = nearbyPart(world, truth[k].x, truth[k].y, 31).scan(truth[k], 181, M_PI, 30.0, 0.01, unsigned(k + 1));
		scan.timestamp = mrpt::Clock::fromDouble(t);
		slam.processOdometry(odometry[k], t);
		r.online.push_back(slam.processScan(scan).pose);
		for (const auto& [i, p] : slam.takeSmoothedPoses()) r.online[i] = p;
	}
	for (const auto& [i, p] : slam.takeSmoothedPoses(true)) r.online[i] = p;
	slam.finishLoopClosure();
	r.final = slam.correctedTrajectory(r.online);
	r.grid = std::make_shared<mrpt::maps::COccupancyGridMap2D>(static_cast<const mrpt::maps::COccupancyGridMap2D&>(slam.grid()));
	if (slam.loopClosure()) r.stats = slam.loopClosure()->stats();
	return r;
}

// Relative pose error between scan k of the first lap and the scan at the same place a lap later.
struct LoopError
{
	double mean = 0, max = 0;
};
LoopError loopError(const std::vector<TPose2D>& est, const std::vector<TPose2D>& truth, std::size_t lap)
{
	LoopError e;
	std::size_t n = 0;
	for (std::size_t k = 0; k + lap < truth.size(); k += 20)
	{
		const CPose2D t = CPose2D(truth[k + lap]) - CPose2D(truth[k]);
		const CPose2D s = CPose2D(est[k + lap]) - CPose2D(est[k]);
		const double d = std::hypot(t.x() - s.x(), t.y() - s.y());
		e.mean += d;
		e.max = std::max(e.max, d);
		++n;
	}
	e.mean /= double(std::max<std::size_t>(n, 1));
	return e;
}

}  // namespace

// With the front-end keeping odometry along plain corridors (degenerateBelow), its drift over a
// lap is about a metre: the loop closure brings the laps to within centimetres.
TEST(LoopClosure, RingDrivenTwiceCloses)
{
	const SyntheticWorld world = ringWorld();
	const auto truth = ringPath(2.15, kStep);
	const auto lap = ringPath(1.0, kStep).size() - 1;  // scans per lap
	const RingRun with = drive(world, truth, true, 0.02);
	const RingRun without = drive(world, truth, false, 0.02);
	const LoopError ew = loopError(with.final, truth, lap), eo = loopError(without.final, truth, lap);
	std::printf("loop relations: with loop closure mean %.3f max %.3f m (online %.3f), without mean %.3f max %.3f m; "
				"closures %zu, loop edges %zu, optimisations %zu, rebuilds %zu\n",
				ew.mean, ew.max, loopError(with.online, truth, lap).mean, eo.mean, eo.max, with.stats.closures,
				with.stats.accepted, with.stats.optimizations, with.stats.rebuilds);
	// The test drives real drift: without loop closure the laps disagree by far more than 5 cm.
	EXPECT_GT(eo.mean, 0.3);
	EXPECT_GE(with.stats.closures, 1u);
	EXPECT_GE(with.stats.rebuilds, 1u);	 // the map followed the graph
	EXPECT_LT(ew.mean, 0.05);
	EXPECT_LT(ew.max, 0.5);
}

// With the default front-end the plain corridors let it slide metres per lap (a turn into an unseen
// corridor comes up short): most of that is closed too, the rest is the front-end's.
TEST(LoopClosure, RingWithTheDefaultFrontEndMostlyCloses)
{
	const SyntheticWorld world = ringWorld();
	const auto truth = ringPath(2.15, kStep);
	const auto lap = ringPath(1.0, kStep).size() - 1;
	const RingRun with = drive(world, truth, true, 0.0);
	const RingRun without = drive(world, truth, false, 0.0);
	const LoopError ew = loopError(with.final, truth, lap), eo = loopError(without.final, truth, lap);
	std::printf("loop relations: with loop closure mean %.3f max %.3f m, without mean %.3f max %.3f m\n", ew.mean, ew.max,
				eo.mean, eo.max);
	EXPECT_GT(eo.mean, 1.0);
	EXPECT_LT(ew.mean, eo.mean / 10);
}
