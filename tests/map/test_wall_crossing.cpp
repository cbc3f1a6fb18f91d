// OccupancyDistanceGridMap::crossedWallFraction (D47): a scan seen from where it was taken passes
// through no wall of the map; seen from a pose in the next room, or turned, most of its beams do.
// Against the world's own geometry as the brute force: a beam crosses a wall when the world's ray
// from that pose ends before the beam does.
#include <gtest/gtest.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/sensor/ScanPoints.h>

#include <cmath>
#include <vector>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;

namespace
{
// Two 4 m × 4 m rooms side by side, joined by a 1 m door, mapped by scans from inside both.
struct TwoRooms
{
	pmslam::testing::SyntheticWorld world;
	pmslam::OccupancyDistanceGridMap map;
	TwoRooms()
	{
		world.addBox(0, 0, 8, 4);
		world.addBox(4, 0, 4.05, 1.5);
		world.addBox(4, 2.5, 4.05, 4);
		world.addBox(1.0, 2.8, 1.6, 3.4);  // a cupboard, so the rooms differ
		for (const TPose2D& p : {TPose2D(1.5, 1.5, 0), TPose2D(2.5, 2.0, 1), TPose2D(6, 2, 2), TPose2D(5.5, 1, -1)})
			map.insertScan(scan(p), p);
	}
	pmslam::ScanPoints scan(const TPose2D& p) const
	{
		return pmslam::scanToPoints(world.scan(p, 361, 2 * M_PI * 359 / 360, 10.0, 0.0, 1));
	}
	// The share of `s`'s beams (robot frame) that the world stops short of their end, by more than `margin`.
	double crossedByGeometry(const pmslam::ScanPoints& s, const TPose2D& p, double margin) const
	{
		std::size_t counted = 0, crossed = 0;
		for (const auto& h : s.hits)
		{
			const double r = std::hypot(h.x, h.y);
			if (r <= margin) continue;
			++counted;
			crossed += world.castRay(p.x, p.y, p.phi + std::atan2(h.y, h.x)) < r - margin - 0.05;
		}
		return counted ? double(crossed) / double(counted) : 0;
	}
};
}  // namespace

TEST(WallCrossing, TheTruePoseCrossesNoWallAndAWrongOneCrossesWhatTheWorldSays)
{
	const TwoRooms t;
	const TPose2D truth(2.0, 1.2, 0.3);
	const auto s = t.scan(truth);
	EXPECT_LT(t.map.crossedWallFraction(s, truth, 0.35), 0.02);
	// The same scan placed in the other room, and turned in its own room: beams pass through walls,
	// as many as the world's geometry says (within the map's rasterisation of the walls).
	for (const TPose2D& wrong : {TPose2D(6.0, 2.2, 0.3), TPose2D(2.0, 1.2, 0.3 + M_PI / 2), TPose2D(2.6, 1.9, 2.0)})
	{
		const double byMap = t.map.crossedWallFraction(s, wrong, 0.35);
		const double byWorld = t.crossedByGeometry(s, wrong, 0.35);
		EXPECT_GT(byWorld, 0.15) << wrong.x << " " << wrong.y << " " << wrong.phi;
		EXPECT_NEAR(byMap, byWorld, 0.1) << wrong.x << " " << wrong.y << " " << wrong.phi;
	}
}

TEST(WallCrossing, BeamsShorterThanTheMarginAreNotCounted)
{
	const TwoRooms t;
	pmslam::ScanPoints s;
	s.hits = {{0.2f, 0.0f}, {0.0f, 0.3f}};
	EXPECT_EQ(t.map.crossedWallFraction(s, TPose2D(3.9, 1, 0), 0.35), 0.0);
	s.hits.push_back({1.0f, 0.0f});	 // from x = 3.9 through the wall at x = 4
	EXPECT_DOUBLE_EQ(t.map.crossedWallFraction(s, TPose2D(3.7, 1, 0), 0.35), 1.0);
}
