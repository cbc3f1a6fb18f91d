// The map following the graph in part: after some scans move, re-inserting only the blocks they
// touch (OccupancyDistanceGridMap::replaceBlocks with a patch) leaves exactly the cells and the
// distance layer of a map rebuilt from every scan at its new pose (brute force), while touching
// only part of the map. And BlockMask's box query against a brute-force scan of the box.
#include <gtest/gtest.h>
#include <pmslam/map/BlockMask.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/sensor/ScanPoints.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using pmslam::BlockMask;
using pmslam::OccupancyDistanceGridMap;
using pmslam::ScanPoints;
using pmslam::SparseOccupancyGrid;

namespace
{
// An 80 m corridor with pillars, scanned every 0.5 m along it (8 m range).
struct Corridor
{
	pmslam::testing::SyntheticWorld world;
	std::vector<TPose2D> poses;
	std::vector<ScanPoints> scans;
	Corridor()
	{
		world.addBox(-1, -2, 81, 2);
		for (int k = 0; k < 20; ++k) world.addBox(4.0 * k + 1, 1.4 - (k % 3) * 0.3, 4.0 * k + 1.4, 2);
		for (int k = 0; k < 160; ++k)
		{
			const TPose2D p(0.5 * k, 0.2 * std::sin(0.3 * k), 0.05 * std::cos(0.2 * k));
			poses.push_back(p);
			scans.push_back(pmslam::scanToPoints(world.scan(p, 361, 2 * M_PI * 359 / 360, 8.0, 0.01, unsigned(k + 1))));
		}
	}
};

OccupancyDistanceGridMap build(const std::vector<ScanPoints>& scans, const std::vector<TPose2D>& poses)
{
	OccupancyDistanceGridMap g;
	for (std::size_t i = 0; i < scans.size(); ++i) g.insertScan(scans[i], poses[i]);
	return g;
}

// Every cell and every distance sample of the two maps' joint extent (plus the truncation) agree.
void expectSameMap(const OccupancyDistanceGridMap& a, const OccupancyDistanceGridMap& b)
{
	int ax0, ay0, ax1, ay1, bx0, by0, bx1, by1;
	ASSERT_TRUE(a.cells().allocatedBounds(ax0, ay0, ax1, ay1));
	ASSERT_TRUE(b.cells().allocatedBounds(bx0, by0, bx1, by1));
	const int m = 12;  // cells: past the 0.5 m truncation
	std::size_t cells = 0, differentCells = 0, differentDistances = 0;
	for (int y = std::min(ay0, by0) - m; y <= std::max(ay1, by1) + m; ++y)
		for (int x = std::min(ax0, bx0) - m; x <= std::max(ax1, bx1) + m; ++x)
		{
			++cells;
			differentCells += a.cells().get(x, y) != b.cells().get(x, y);
			differentDistances += a.distanceMap().cellDistance(x, y) != b.distanceMap().cellDistance(x, y);
		}
	EXPECT_GT(cells, 100000u);
	EXPECT_EQ(differentCells, 0u);
	EXPECT_EQ(differentDistances, 0u);
}
}  // namespace

TEST(GridPatch, ReplacingTheMovedScansBlocksGivesTheRebuiltMap)
{
	const Corridor c;
	OccupancyDistanceGridMap live = build(c.scans, c.poses);
	// A loop closure moves a stretch of the corridor (scans 60..79) by up to 0.4 m and 4 degrees.
	std::vector<TPose2D> moved = c.poses;
	std::vector<bool> isMoved(c.poses.size(), false);
	for (std::size_t i = 60; i < 80; ++i)
	{
		const double f = double(i - 59) / 20;
		moved[i] = TPose2D(c.poses[i].x + 0.4 * f, c.poses[i].y - 0.2 * f, c.poses[i].phi + 0.07 * f);
		isMoved[i] = true;
	}
	OccupancyDistanceGridMap patch;
	BlockMask blocks;
	for (std::size_t i = 0; i < c.poses.size(); ++i)
		if (isMoved[i])
		{
			patch.addBlocksTouched(c.scans[i], c.poses[i], blocks);
			patch.addBlocksTouched(c.scans[i], moved[i], blocks);
		}
	blocks.freeze();
	for (std::size_t i = 0; i < c.poses.size(); ++i) patch.insertScanWithin(c.scans[i], moved[i], blocks);
	// The patch allocates no block outside the set.
	std::size_t outside = 0;
	patch.cells().forEachObserved([&](int x, int y, SparseOccupancyGrid::Cell) {
		outside += !blocks.contains(SparseOccupancyGrid::Blocks::blockOf(x), SparseOccupancyGrid::Blocks::blockOf(y));
	});
	EXPECT_EQ(outside, 0u);
	// Part of the map, not all of it.
	EXPECT_LT(blocks.count(), live.cells().blockCount() * 3 / 4);
	EXPECT_GT(blocks.count(), 10u);

	const std::size_t blocksBefore = live.distanceMap().allocatedBlocks();
	const std::size_t flips = live.replaceBlocks(patch, blocks);
	EXPECT_GT(flips, 50u);	// the moved walls did move
	const OccupancyDistanceGridMap fresh = build(c.scans, moved);
	expectSameMap(live, fresh);
	// Storage follows: the blocks no scan reaches any more are given back (the memory of a map whose
	// loop moved is that of the map where it now is, not of both places).
	EXPECT_EQ(live.cells().blockCount(), fresh.cells().blockCount());
	std::printf("distance blocks: before %zu, after %zu, built anew %zu\n", blocksBefore,
				live.distanceMap().allocatedBlocks(), fresh.distanceMap().allocatedBlocks());
	EXPECT_LE(live.distanceMap().allocatedBlocks(), fresh.distanceMap().allocatedBlocks());

	// The map goes on as a map: a later scan changes it as it would change the rebuilt one.
	OccupancyDistanceGridMap rebuilt = build(c.scans, moved);
	const TPose2D extra(32.3, 0.1, 0.3);
	const ScanPoints s = pmslam::scanToPoints(c.world.scan(extra, 361, 2 * M_PI * 359 / 360, 8.0, 0.01, 999));
	live.insertScan(s, extra);
	rebuilt.insertScan(s, extra);
	expectSameMap(live, rebuilt);
}

// The loop closure builds a patch in two parts side by side (two disjoint sets of blocks, each part
// re-inserting every scan), then copies one part into the other: a cell depends only on the scans
// that reach it, so the result is the patch built in one piece, cell for cell.
TEST(GridPatch, APatchBuiltInTwoPartsIsThePatchBuiltInOne)
{
	const Corridor c;
	std::vector<TPose2D> moved = c.poses;
	for (std::size_t i = 40; i < 120; ++i) moved[i].y += 0.3 * std::sin(0.1 * double(i));
	OccupancyDistanceGridMap whole;
	BlockMask blocks;
	for (std::size_t i = 40; i < 120; ++i)
	{
		whole.addBlocksTouched(c.scans[i], c.poses[i], blocks);
		whole.addBlocksTouched(c.scans[i], moved[i], blocks);
	}
	blocks.freeze();
	BlockMask parts[2];	 // alternate columns of blocks: every scan reaches both parts
	blocks.forEach([&](int bx, int by) { parts[bx & 1].add(bx, by); });
	for (auto& p : parts) p.freeze();
	ASSERT_GT(parts[0].count(), 10u);
	ASSERT_GT(parts[1].count(), 10u);
	OccupancyDistanceGridMap first, second;
	for (std::size_t i = 0; i < c.poses.size(); ++i)
	{
		whole.insertScanWithin(c.scans[i], moved[i], blocks);
		first.insertScanWithin(c.scans[i], moved[i], parts[0]);
		second.insertScanWithin(c.scans[i], moved[i], parts[1]);
	}
	first.copyBlocks(second, parts[1]);
	std::size_t cells = 0, different = 0;
	blocks.forEach([&](int bx, int by) {
		constexpr int S = SparseOccupancyGrid::Blocks::kSide;
		for (int y = by * S; y < (by + 1) * S; ++y)
			for (int x = bx * S; x < (bx + 1) * S; ++x)
			{
				++cells;
				different += first.cells().get(x, y) != whole.cells().get(x, y);
			}
	});
	EXPECT_EQ(cells, blocks.count() * 1024u);
	EXPECT_EQ(different, 0u);
	EXPECT_EQ(first.cells().blockCount(), whole.cells().blockCount());
}

TEST(GridPatch, TheBlocksTouchedAreThoseInsertionChanges)
{
	// addBlocksTouched() against the blocks an insertion into an empty map allocates.
	const Corridor c;
	for (std::size_t i : {0u, 17u, 155u})
	{
		OccupancyDistanceGridMap g, probe;
		g.insertScan(c.scans[i], c.poses[i]);
		BlockMask m;
		probe.addBlocksTouched(c.scans[i], c.poses[i], m);
		m.freeze();
		std::set<std::pair<int, int>> allocated;
		int x0, y0, x1, y1;
		ASSERT_TRUE(g.cells().allocatedBounds(x0, y0, x1, y1));
		constexpr int S = SparseOccupancyGrid::Blocks::kSide;
		for (int by = y0 / S - 1; by <= y1 / S + 1; ++by)
			for (int bx = x0 / S - 1; bx <= x1 / S + 1; ++bx)
				if (g.cells().blockCells(bx, by)) allocated.insert({bx, by});
		std::set<std::pair<int, int>> inMask;
		m.forEach([&](int bx, int by) { inMask.insert({bx, by}); });
		EXPECT_EQ(inMask, allocated) << "scan " << i;
		EXPECT_EQ(m.count(), allocated.size());
	}
}

TEST(BlockMask, BoxQueryAgreesWithBruteForce)
{
	std::mt19937 rng(3);
	std::uniform_int_distribution<int> coord(-40, 40);
	BlockMask m;
	std::set<std::pair<int, int>> truth;
	for (int k = 0; k < 300; ++k)
	{
		const int x = coord(rng), y = coord(rng) / 2;
		m.add(x, y);
		truth.insert({x, y});
	}
	m.freeze();
	EXPECT_EQ(m.count(), truth.size());
	for (int x = -45; x <= 45; ++x)
		for (int y = -25; y <= 25; ++y) ASSERT_EQ(m.contains(x, y), truth.count({x, y}) > 0) << x << "," << y;
	std::uniform_int_distribution<int> corner(-60, 60), side(0, 12);
	for (int k = 0; k < 5000; ++k)
	{
		const int x0 = corner(rng), y0 = corner(rng), x1 = x0 + side(rng), y1 = y0 + side(rng);
		bool any = false;
		for (const auto& [x, y] : truth) any = any || (x >= x0 && x <= x1 && y >= y0 && y <= y1);
		ASSERT_EQ(m.meets(x0, y0, x1, y1), any) << x0 << "," << y0 << " .. " << x1 << "," << y1;
	}
	BlockMask none;
	none.freeze();
	EXPECT_TRUE(none.empty());
	EXPECT_FALSE(none.meets(-100, -100, 100, 100));
}
