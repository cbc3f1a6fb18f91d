// Rivals: look-alike places kept until the scans decide. In a square room whose walls look the same in
// four headings, with a lidar that sees 2 m, the first scans fit several places; only the view of the one
// thing that breaks the symmetry tells them apart, and then the right one must win — and in the same room
// without it, nothing may be decided. And a robot turning in place must not lose to a look-alike that
// merely follows the odometry.
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/GlobalLocalizer.h>

#include <cmath>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using pmslam::GlobalLocalizer;
using pmslam::testing::SyntheticWorld;

namespace
{
SyntheticWorld squareRoom(bool withBox)
{
	SyntheticWorld w;
	w.addBox(-3.025, -3.025, 3.025, 3.025);
	if (withBox) w.addBox(1.825, -2.325, 2.325, -1.825);  // the one asymmetric thing, in the south-east corner
	return w;
}

struct Outcome
{
	GlobalLocalizer::State state = GlobalLocalizer::State::Searching;
	std::size_t scans = 0;
	double error = 0, yawError = 0;	 // of the decided start against the truth
	std::size_t hypotheses = 0;
};

// Starts in the south-west corner (which looks like the other three) and drives along the south wall towards
// the south-east corner and its box, then turns on the spot; a 2 m lidar, odometry exact.
TPose2D alongTheSouthWall(int k)
{
	return k < 200 ? TPose2D(-2.3 + 3.0 * k / 200.0, -2.3, 0)	// along the south wall
				   : TPose2D(0.7, -2.3, (k - 200) / 60.0);	 // turning, the box in view
}

Outcome drive(const SyntheticWorld& w, TPose2D (*path)(int) = alongTheSouthWall)
{
	mrpt::maps::COccupancyGridMap2D grid(-4, 4, -4, 4, 0.05f);
	w.rasterise(grid);
	pmslam::GlobalLocalizerOptions o;
	pmslam::GlobalLocalizer g(grid, pmslam::PerfectMatchMatcher::TConfigParams(), pmslam::ScanPointsOptions(), o);
	const TPose2D start = path(0);
	Outcome out;
	for (int k = 0; k < 600 && g.state() == GlobalLocalizer::State::Searching; ++k)
	{
		const TPose2D truth = path(k);
		const auto scan = w.scan(truth, 361, 1.5 * M_PI, 2.0, 0.005, unsigned(k + 1));
		g.addScan(scan, truth);
		out.scans = k + 1;
	}
	out.state = g.state();
	out.hypotheses = g.hypotheses();
	if (const auto best = g.best())
	{
		out.error = std::hypot(best->origin.x - start.x, best->origin.y - start.y);
		out.yawError = std::abs(mrpt::math::wrapToPi(best->origin.phi - start.phi));
	}
	return out;
}
}  // namespace

TEST(Rivals, TheViewThatBreaksASymmetryDecidesForTheRightPlace)
{
	const Outcome o = drive(squareRoom(true));
	ASSERT_EQ(o.state, GlobalLocalizer::State::Found) << o.scans << " scans, " << o.hypotheses << " places";
	EXPECT_GT(o.scans, 1u) << "one scan of a plain wall cannot have decided";
	EXPECT_LT(o.error, 0.2);
	EXPECT_LT(o.yawError, 3 * M_PI / 180);
}

TEST(Rivals, WithoutItNothingIsDecided)
{
	const Outcome o = drive(squareRoom(false));
	EXPECT_NE(o.state, GlobalLocalizer::State::Found) << "decided at " << o.scans << " scans on a symmetric room";
}

// Turning in place where the odometry says the robot creeps forward (a lidar ahead of the axle, or wheel
// readings timed against the scans, misplace the base by centimetres over a turn): the right place is held
// by what it sees (a pillar) and does not creep; a look-alike down a plain stretch of the corridor, which
// nothing holds along it, follows the odometry. The right place fits better (the look-alike's scans end on
// a pillar that is not there); weighing each view by how well a place's own motion agrees with the
// odometry's must not hand the decision to the look-alike: over a turn, the odometry's translation is
// that much less sure (RivalsOptions::motionNoisePerTurn; aces, decisions.md D43).
TEST(Rivals, ATurnInPlaceDoesNotHandTheDecisionToALookAlikeThatFollowsTheOdometry)
{
	SyntheticWorld w;
	w.addBox(-12.025, -1.025, 12.025, 1.025);  // a corridor 2 m wide, 24 m long
	w.addBox(0.6, 0.75, 0.8, 1.025);  // a pillar on its north wall, 0.7 m east of the right place
	mrpt::maps::COccupancyGridMap2D grid(-13, 13, -2, 2, 0.05f);
	w.rasterise(grid);
	const pmslam::PerfectMatchMatcher::TConfigParams params;
	const pmslam::PerfectMatchMatcher matcher(params);
	const auto map = pmslam::PerfectMatchMatcher::distanceMapFromGrid(grid, params.maxDistance, params.occupiedThreshold);
	const TPose2D right(0, 0, 0), lookAlike(-7, 0, 0);
	pmslam::Rivals rivals{pmslam::RivalsOptions()};
	const auto pointsAt = [&](const TPose2D& pose, unsigned seed) {
		return pmslam::scanToPoints(w.scan(pose, 361, 2 * M_PI, 3.0, 0.01, seed)).hits;
	};
	const auto first = pointsAt(right, 1);
	for (const TPose2D& p : {right, lookAlike})
	{
		pmslam::PerfectMatchMatcher::MatchInfo info;
		const TPose2D at = matcher.alignPoints(map, first, p, &info);
		rivals.add(at, at, info);
	}
	ASSERT_EQ(rivals.size(), 2u);
	// 2° a scan, and 8 mm of creep forward in the odometry each scan.
	bool decided = false;
	for (int k = 1; k <= 90 && !decided; ++k)
	{
		const TPose2D truth(0, 0, mrpt::math::wrapToPi(k * 2 * M_PI / 180));
		rivals.follow(matcher, map, pointsAt(truth, unsigned(k + 1)), TPose2D(0.008, 0, 2 * M_PI / 180));
		decided = rivals.decide();
	}
	ASSERT_TRUE(decided);
	EXPECT_LT(std::hypot(rivals.leader().pose.x - right.x, rivals.leader().pose.y - right.y), 0.3)
		<< "decided at " << rivals.leader().pose.x << ", " << rivals.leader().pose.y;
}
