// SeenThrough: which returns of a scan another scan, taken from nearby, saw through. Ray-cast rooms
// with pillars and long walls seen at grazing angles: what the building is made of is never seen
// through, whatever the two poses; a blob in front of one scan (a passer-by) is, return for return.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/sensor/SeenThrough.h>

#include <random>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using pmslam::testing::SyntheticWorld;

namespace
{
// A 12 m x 5 m hall (its long walls seen at grazing angles from its ends) and four pillars of 0.3 m.
SyntheticWorld hall()
{
	SyntheticWorld w;
	w.addBox(0, 0, 12, 5);
	for (double x : {3.0, 6.0, 9.0}) w.addBox(x, 1.2, x + 0.3, 1.5);
	w.addBox(7.5, 3.5, 7.8, 3.8);
	return w;
}

pmslam::ScanPoints pointsOf(const SyntheticWorld& w, const TPose2D& pose, unsigned seed)
{
	pmslam::ScanPointsOptions o;
	o.noReturnCarveRange = 30;
	return pmslam::scanToPoints(w.scan(pose, 181, M_PI, 30.0, 0.01, seed), o);
}

// A robot is at least 0.4 m from anything (its own radius): a pose closer would stand in a pillar.
bool clear(const SyntheticWorld& w, const TPose2D& p)
{
	for (int k = 0; k < 72; ++k)
		if (w.castRay(p.x, p.y, k * M_PI / 36) < 0.4) return false;
	return true;
}

// `b`'s pose in `a`'s robot frame.
TPose2D relative(const TPose2D& a, const TPose2D& b) { return (CPose2D(b) - CPose2D(a)).asTPose(); }
}  // namespace

// Two scans of the same hall from poses up to 1.4 m and 57 degrees apart, 1000 pairs: the walls (at
// grazing angles too), the pillars and their edges are never seen through.
TEST(SeenThrough, WhatTheBuildingIsMadeOfIsNeverSeenThrough)
{
	const SyntheticWorld world = hall();
	std::mt19937 rng(3);
	std::uniform_real_distribution<double> x(0.8, 11.2), y(0.6, 4.4), phi(-M_PI, M_PI), d(-1.0, 1.0), dphi(-0.5, 0.5);
	std::size_t points = 0, seen = 0;
	for (int pair = 0; pair < 1000; ++pair)
	{
		const TPose2D a(x(rng), y(rng), phi(rng));
		const TPose2D b(a.x + d(rng), a.y + d(rng), a.phi + dphi(rng));
		if (!clear(world, a) || !clear(world, b)) continue;
		const auto pa = pointsOf(world, a, unsigned(2 * pair + 1)), pb = pointsOf(world, b, unsigned(2 * pair + 2));
		const std::vector<bool> through = pmslam::seenThrough(pa, {{relative(a, b), &pb}});
		ASSERT_EQ(through.size(), pa.hits.size());
		points += through.size();
		for (bool t : through) seen += t;
	}
	std::printf("returns seen through: %zu of %zu\n", seen, points);
	EXPECT_GT(points, 25000u);
	EXPECT_EQ(seen, 0u);
}

// A blob 1-2 m in front of the robot in one scan, absent from the scan 0.3 m before: each of its
// returns, and none other, is seen through. Without the earlier scan nothing is.
TEST(SeenThrough, APasserByIsSeenThroughByTheScanBefore)
{
	const SyntheticWorld world = hall();
	const TPose2D before(2.0, 2.5, 0.0), now(2.3, 2.55, 0.05);
	auto obs = world.scan(now, 181, M_PI, 30.0, 0.01, 7);
	for (std::size_t k = 100; k < 120; ++k) obs.setScanRange(k, float(1.0 + 0.05 * double(k - 100)));
	pmslam::ScanPointsOptions o;
	o.noReturnCarveRange = 30;
	const pmslam::ScanPoints scan = pmslam::scanToPoints(obs, o);
	const pmslam::ScanPoints earlier = pointsOf(world, before, 8);
	ASSERT_EQ(scan.hits.size(), 181u);
	const std::vector<bool> through = pmslam::seenThrough(scan, {{relative(now, before), &earlier}});
	for (std::size_t k = 0; k < through.size(); ++k) EXPECT_EQ(through[k], k >= 100 && k < 120) << "beam " << k;
	for (bool t : pmslam::seenThrough(scan, {})) EXPECT_FALSE(t);
}

// A 360-degree scan: bearings on either side of ±180 degrees are neighbours.
TEST(SeenThrough, BearingsWrapRoundTheCircle)
{
	pmslam::ScanPoints view;
	view.hits = {{-5.0f, 0.01f}, {-5.0f, -0.01f}, {5.0f, 0.0f}};
	const pmslam::ScanView v(view);
	EXPECT_TRUE(v.seesThrough({-2.0, 0.0}, 0.25, 0.1));
	EXPECT_FALSE(v.seesThrough({-4.9, 0.0}, 0.25, 0.1));
	EXPECT_FALSE(v.seesThrough({0.0, 2.0}, 0.25, 0.1));	 // no beam near that bearing
}
