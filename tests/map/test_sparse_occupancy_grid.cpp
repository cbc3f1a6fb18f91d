// The live map's sparse storage: the same cells as a dense array would hold (brute force), memory that
// follows the area touched rather than its bounding box, and the MRPT views of it.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/map/SparseOccupancyGrid.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using pmslam::OccupancyDistanceGridMap;
using pmslam::SparseOccupancyGrid;

TEST(SparseOccupancyGrid, HoldsWhatADenseArrayWouldAndVisitsEachCellOncePerPass)
{
	// Random writes over a wide area with negative coordinates, against a std::map of the same cells.
	SparseOccupancyGrid g;
	std::map<std::pair<int, int>, int> truth;
	std::mt19937 rng(5);
	std::uniform_int_distribution<int> coord(-3000, 3000), small(-40, 40), value(-60, 60);
	for (int k = 0; k < 20000; ++k)
	{
		const int x = k % 3 ? small(rng) : coord(rng), y = k % 3 ? small(rng) : coord(rng);
		const int v = value(rng);
		g.at(x, y) = static_cast<SparseOccupancyGrid::Cell>(v);
		truth[{x, y}] = v;
	}
	std::size_t observed = 0;
	for (const auto& [c, v] : truth)
	{
		ASSERT_EQ(g.get(c.first, c.second), v) << c.first << "," << c.second;
		observed += v != 0;
	}
	EXPECT_EQ(g.observedCells(), observed);
	EXPECT_EQ(g.get(100000, -100000), 0);  // never touched: the prior
	// Rows read across blocks, allocated or not, give the same cells.
	for (int y = -45; y <= 45; y += 7)
	{
		std::vector<SparseOccupancyGrid::Cell> row(200);
		g.readRow(y, -100, 200, row.data());
		for (int i = 0; i < 200; ++i)
		{
			const auto it = truth.find({-100 + i, y});
			ASSERT_EQ(row[std::size_t(i)], it == truth.end() ? 0 : it->second) << "x " << -100 + i << " y " << y;
		}
	}
	// Evidence bounds: the extreme non-zero cells, brute force.
	int x0, y0, x1, y1;
	ASSERT_TRUE(g.evidenceBounds(x0, y0, x1, y1));
	int bx0 = INT32_MAX, by0 = INT32_MAX, bx1 = INT32_MIN, by1 = INT32_MIN;
	for (const auto& [c, v] : truth)
		if (v != 0)
			bx0 = std::min(bx0, c.first), by0 = std::min(by0, c.second), bx1 = std::max(bx1, c.first),
			by1 = std::max(by1, c.second);
	EXPECT_EQ(std::make_tuple(x0, y0, x1, y1), std::make_tuple(bx0, by0, bx1, by1));
	// visitOnce: the first call per pass answers, the second does not; a new pass answers again.
	g.beginPass();
	EXPECT_NE(g.visitOnce(7, -9), nullptr);
	EXPECT_EQ(g.visitOnce(7, -9), nullptr);
	EXPECT_NE(g.visitOnce(8, -9), nullptr);
	g.beginPass();
	EXPECT_NE(g.visitOnce(7, -9), nullptr);
}

TEST(SparseOccupancyGrid, MemoryFollowsTheAreaTouchedNotItsBoundingBox)
{
	// Two 3 m × 3 m patches 1 km apart on a diagonal: a dense 5 cm grid of their bounding box would
	// hold 400 million cells; the sparse one holds the patches' blocks (and a directory of pointers).
	SparseOccupancyGrid one, two;
	auto patch = [](SparseOccupancyGrid& g, int cx, int cy) {
		for (int y = 0; y < 60; ++y)
			for (int x = 0; x < 60; ++x) g.at(cx + x, cy + y) = -5;
	};
	patch(one, 0, 0);
	patch(two, 0, 0);
	patch(two, 14144, 14144);  // 1 km along the diagonal, on the same block boundaries
	const std::size_t perPatch = one.memoryBytes();
	EXPECT_LT(perPatch, 40u * 1024);
	EXPECT_EQ(two.blockCount(), 2 * one.blockCount());
	// The blocks double; the directory (8 bytes per 32×32 cells of the bounding box) is what remains.
	EXPECT_LT(two.memoryBytes(), 2 * perPatch + 14142.0 * 14142 / 1024 * 8 * 2.5);
	EXPECT_LT(two.memoryBytes(), 1e-2 * 20000.0 * 20000.0);	 // a dense grid: 400 MB
}

namespace
{
// A room scanned from a few poses, for the map tests below.
OccupancyDistanceGridMap roomMap()
{
	const auto world = pmslam::testing::furnishedRoom();
	OccupancyDistanceGridMap m;
	for (const TPose2D p : {TPose2D(0, 0, 0), TPose2D(1.5, -1, 1.2), TPose2D(-2, 1, -2.0), TPose2D(3, 0.5, 2.8)})
		m.insertScan(pmslam::scanToPoints(world.scan(p, 361)), p);
	return m;
}
}  // namespace

TEST(OccupancyDistanceGridMap, MaterialisedViewAndDenseCopyHoldTheCells)
{
	OccupancyDistanceGridMap m = roomMap();
	const double r = m.updateOptions().resolution;
	EXPECT_EQ(m.getSizeX() * m.getSizeY(), 1u);  // the view is empty until asked for
	const mrpt::maps::COccupancyGridMap2D copy = m.denseCopy();
	m.materialize();
	for (const mrpt::maps::COccupancyGridMap2D* g : {static_cast<const mrpt::maps::COccupancyGridMap2D*>(&m), &copy})
	{
		// The view's origin is on the lattice, and every cell of the sparse map is in it, cell for cell.
		const int ox = int(std::lround(g->getXMin() / r)), oy = int(std::lround(g->getYMin() / r));
		EXPECT_NEAR(g->getXMin(), ox * r, 1e-5);
		std::size_t observed = 0, mismatched = 0;
		for (unsigned iy = 0; iy < g->getSizeY(); ++iy)
			for (unsigned ix = 0; ix < g->getSizeX(); ++ix)
			{
				const auto c = g->getRawMap()[iy * g->getSizeX() + ix];
				observed += c != 0;
				mismatched += c != m.cells().get(int(ix) + ox, int(iy) + oy);
			}
		EXPECT_EQ(mismatched, 0u);
		EXPECT_EQ(observed, m.cells().observedCells());
		EXPECT_GT(observed, 5000u);
	}
	// A world point reads the same through MRPT's accessor and through the sparse cells.
	const auto probe = [&](double x, double y) {
		return std::make_pair(m.getCell(m.x2idx(x), m.y2idx(y)),
							  mrpt::maps::COccupancyGridMap2D::l2p(
								  m.cells().get(int(std::floor(x / r)), int(std::floor(y / r)))));
	};
	// (Off cell edges: there float and double arithmetic may pick either neighbour.)
	for (double y = -3.013; y < 3; y += 0.37)
		for (double x = -4.013; x < 5; x += 0.41)
		{
			const auto [a, b] = probe(x, y);
			EXPECT_FLOAT_EQ(a, b) << x << "," << y;
		}
	// A scan inserted after the snapshot shows in the next one.
	const auto observedIn = [](const mrpt::maps::COccupancyGridMap2D& g) {
		return std::size_t(std::count_if(g.getRawMap().begin(), g.getRawMap().end(), [](auto c) { return c != 0; }));
	};
	const auto before = observedIn(m);
	const auto world = pmslam::testing::furnishedRoom();
	m.insertScan(pmslam::scanToPoints(world.scan(TPose2D(-3, -1, 0.4), 361)), TPose2D(-3, -1, 0.4));
	EXPECT_EQ(observedIn(m), before);  // the snapshot, untouched
	m.materialize();
	EXPECT_EQ(observedIn(m), m.cells().observedCells());
	EXPECT_GT(observedIn(m), before);
	m.releaseMaterialized();
	EXPECT_EQ(m.getSizeX() * m.getSizeY(), 1u);
	m.materialize();  // refilled after a release
	EXPECT_EQ(observedIn(m), m.cells().observedCells());
}

// The loop verification asks a local map, never materialised, whether a pose stands in an occupied or an
// unexplored cell: the sparse accessors answer what the dense copy says, while MRPT's own getPos() reads the
// empty view (0.5 everywhere) and so cannot be asked (it was, and the test "the robot stands in space the
// earlier visit saw free" never fired).
TEST(OccupancyDistanceGridMap, OccupiedAndUnexploredAnswerWhatTheDenseCopySays)
{
	const OccupancyDistanceGridMap m = roomMap();
	const mrpt::maps::COccupancyGridMap2D dense = m.denseCopy();
	std::size_t occupied = 0, unexplored = 0, wrong = 0, viewSaysOccupied = 0;
	const double r = m.updateOptions().resolution;
	for (double y = -4.5 + r / 2; y < 4.5; y += r)
		for (double x = -5.5 + r / 2; x < 5.5; x += r)
		{
			const bool occ = m.isOccupied(x, y), unk = m.isUnexplored(x, y);
			occupied += occ;
			unexplored += unk;
			const float p = dense.getPos(float(x), float(y));
			wrong += occ != (p < 0.5f) || (unk && p != 0.5f);
			viewSaysOccupied += m.getPos(float(x), float(y)) < 0.5f;
		}
	EXPECT_GT(occupied, 300u);
	EXPECT_GT(unexplored, 300u);
	EXPECT_EQ(wrong, 0u);
	EXPECT_EQ(viewSaysOccupied, 0u);
}

TEST(OccupancyDistanceGridMap, DistanceLayerIsTheBruteForceDistanceToTheOccupiedCells)
{
	// Built scan by scan (incremental), and rebuilt in one pass (row by row): both the exact truncated
	// distance to the nearest occupied cell, which brute force over the cells gives.
	OccupancyDistanceGridMap m = roomMap();
	std::vector<std::pair<int, int>> occupied;
	m.cells().forEachObserved([&](int x, int y, SparseOccupancyGrid::Cell v) {
		if (v < 0) occupied.emplace_back(x, y);
	});
	ASSERT_GT(occupied.size(), 300u);
	const int maxSq = m.distanceMap().maxSquaredCells();
	auto bruteForce = [&](int x, int y) {
		int best = INT32_MAX;
		for (const auto& [ox, oy] : occupied) best = std::min(best, (ox - x) * (ox - x) + (oy - y) * (oy - y));
		return best > maxSq ? -1 : best;
	};
	// Returns how many of the probed cells differ from brute force.
	auto check = [&](const pmslam::DynamicDistanceMap& d) {
		std::size_t n = 0, wrong = 0;
		for (int y = -80; y < 80; y += 3)
			for (int x = -100; x < 120; x += 3, ++n) wrong += d.squaredDistanceCells(x, y) != bruteForce(x, y);
		EXPECT_GT(n, 3000u);
		return wrong;
	};
	EXPECT_EQ(check(m.distanceMap()), 0u);
	m.rebuildDistanceMap();
	EXPECT_EQ(check(m.distanceMap()), 0u);
	// The same cells loaded from a dense grid (assignCells) give the same layer.
	OccupancyDistanceGridMap loaded;
	const auto dense = m.denseCopy();
	loaded.assignCells(dense, int(std::lround(dense.getXMin() / dense.getResolution())),
					   int(std::lround(dense.getYMin() / dense.getResolution())));
	EXPECT_EQ(loaded.cells().observedCells(), m.cells().observedCells());
	EXPECT_EQ(check(loaded.distanceMap()), 0u);
}

TEST(OccupancyDistanceGridMap, ABadScanLeavesTheMapAsItWas)
{
	OccupancyDistanceGridMap m = roomMap();
	const auto before = m.cells().observedCells();
	pmslam::ScanPoints bad;
	bad.hits = {{1.f, 0.f}, {2.f, 1.f}, {1e30f, 0.f}};
	EXPECT_THROW(m.insertScan(bad, TPose2D(0.3, 0.2, 0.1)), std::invalid_argument);
	EXPECT_THROW(m.insertScan(pmslam::ScanPoints{}, TPose2D(std::nan(""), 0, 0)), std::invalid_argument);
	EXPECT_EQ(m.cells().observedCells(), before);
}

TEST(OccupancyDistanceGridMap, AReadingBeyondAKilometreIsLeftOut)
{
	// A damaged range (5 km) would carve a 100 000-cell beam through 3 000 blocks; it is left out,
	// the rest of the scan goes in.
	OccupancyDistanceGridMap m;
	pmslam::ScanPoints scan;
	scan.hits = {{2.f, 0.f}, {5000.f, 0.f}, {0.f, 2.f}};
	m.insertScan(scan, TPose2D(0, 0, 0));
	EXPECT_LT(m.cells().get(40, 0), 0);  // the 2 m return: occupied
	EXPECT_LT(m.cells().get(0, 40), 0);
	EXPECT_EQ(m.cells().get(60, 0), 0);	 // nothing carved towards the 5 km one
	EXPECT_LT(m.cells().blockCount(), 10u);
}
