// Rivals: look-alike places kept until the scans decide. In a square room whose walls look the same in
// four headings, with a lidar that sees 2 m, the first scans fit several places; only the view of the one
// thing that breaks the symmetry tells them apart, and then the right one must win — and in the same room
// without it, nothing may be decided.
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

