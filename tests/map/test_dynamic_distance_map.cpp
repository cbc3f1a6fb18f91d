// DynamicDistanceMap against a brute-force EDT after random edits, and its interpolation.
#include <gtest/gtest.h>
#include <pmslam/map/DynamicDistanceMap.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>

using pmslam::DynamicDistanceMap;

namespace
{
// Exact truncated squared distance (in cells) from every cell of a window to the obstacle set.
int bruteForceSq(const std::set<std::pair<int, int>>& obstacles, int x, int y, int maxSq)
{
	int best = -1;
	for (const auto& [ox, oy] : obstacles)
	{
		const int d = (ox - x) * (ox - x) + (oy - y) * (oy - y);
		if (d <= maxSq && (best < 0 || d < best)) best = d;
	}
	return best;
}

void expectEqualsBruteForce(const DynamicDistanceMap& map, const std::set<std::pair<int, int>>& obstacles,
							int x0, int y0, int x1, int y1)
{
	int mismatches = 0;
	for (int y = y0; y <= y1; ++y)
		for (int x = x0; x <= x1; ++x)
		{
			const int expected = bruteForceSq(obstacles, x, y, map.maxSquaredCells());
			const int got = map.squaredDistanceCells(x, y);
			if (expected != got && ++mismatches <= 5)
				ADD_FAILURE() << "cell (" << x << "," << y << "): brute force " << expected << ", map " << got;
			EXPECT_EQ(map.isObstacle(x, y), obstacles.count({x, y}) == 1);
		}
	EXPECT_EQ(mismatches, 0);
}

struct EditCase
{
	double maxDistance;
	int steps;
	int editsPerStep;
	unsigned seed;
};

class RandomEdits : public ::testing::TestWithParam<EditCase>
{
};
}  // namespace

TEST_P(RandomEdits, IncrementalEqualsBruteForce)
{
	const auto p = GetParam();
	DynamicDistanceMap map(0.05, p.maxDistance);
	std::mt19937 rng(p.seed);
	// A window straddling the origin, so negative cell indices and several blocks are exercised.
	const int lo = -45, hi = 52;
	std::uniform_int_distribution<int> coord(lo, hi);
	std::set<std::pair<int, int>> obstacles;
	int totalEdits = 0;
	for (int step = 0; step < p.steps; ++step)
	{
		for (int e = 0; e < p.editsPerStep; ++e, ++totalEdits)
		{
			// Mix isolated points and short wall segments (the shape laser scans produce).
			const int x = coord(rng), y = coord(rng);
			const bool add = obstacles.empty() || (rng() % 100) < 55;
			if (add)
			{
				const int len = 1 + rng() % 6, dir = rng() % 2;
				for (int k = 0; k < len; ++k)
				{
					const int cx = std::min(hi, x + (dir ? k : 0)), cy = std::min(hi, y + (dir ? 0 : k));
					map.addObstacle(cx, cy);
					obstacles.insert({cx, cy});
				}
			}
			else
			{
				auto it = obstacles.begin();
				std::advance(it, rng() % obstacles.size());
				map.removeObstacle(it->first, it->second);
				obstacles.erase(it);
			}
		}
		map.update();
		if (step % 10 == 9 || step == p.steps - 1)
			expectEqualsBruteForce(map, obstacles, lo - 12, lo - 12, hi + 12, hi + 12);
		if (HasFailure()) return;
	}
	EXPECT_GE(totalEdits, 1000);
}

INSTANTIATE_TEST_SUITE_P(DynamicDistanceMap, RandomEdits,
						 ::testing::Values(EditCase{0.5, 60, 30, 1}, EditCase{0.5, 40, 80, 2},
										   EditCase{0.3, 200, 8, 3}, EditCase{1.0, 30, 40, 4}));

TEST(DynamicDistanceMap, RemovingEverythingLeavesNoDistance)
{
	DynamicDistanceMap map(0.05, 0.5);
	for (int i = -20; i < 20; ++i) map.addObstacle(i, 3);
	map.update();
	EXPECT_EQ(map.squaredDistanceCells(0, 0), 9);
	for (int i = -20; i < 20; ++i) map.removeObstacle(i, 3);
	map.update();
	for (int y = -15; y < 20; ++y)
		for (int x = -35; x < 35; ++x) ASSERT_EQ(map.squaredDistanceCells(x, y), -1) << x << "," << y;
	EXPECT_FLOAT_EQ(map.distanceAt(0.0, 0.15), 0.5f);
}

TEST(DynamicDistanceMap, AddRemoveBeforeUpdateIsConsistent)
{
	DynamicDistanceMap map(0.05, 0.5);
	map.addObstacle(0, 0);
	map.removeObstacle(0, 0);
	map.addObstacle(5, 5);
	map.update();
	EXPECT_FALSE(map.isObstacle(0, 0));
	EXPECT_EQ(map.squaredDistanceCells(0, 0), 50 <= map.maxSquaredCells() ? 50 : -1);
	EXPECT_EQ(map.squaredDistanceCells(5, 7), 4);
}

TEST(DynamicDistanceMap, InterpolatedGradientMatchesFiniteDifferences)
{
	DynamicDistanceMap map(0.05, 0.5);
	// A wall and a pillar so the field has varied slopes.
	for (int i = -30; i <= 30; ++i) map.addObstacle(i, -6);
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j) map.addObstacle(8 + i, 4 + j);
	map.update();
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> ux(-1.0, 1.0), uy(-0.6, 0.6);
	int checked = 0;
	const double h = 1e-5;
	for (int k = 0; k < 2000; ++k)
	{
		const double x = ux(rng), y = uy(rng);
		double gx, gy;
		const float d = map.distanceAt(x, y, &gx, &gy);
		EXPECT_GE(d, 0.0f);
		EXPECT_LE(d, 0.5f);
		// Skip points within h of a cell-centre line where the bilinear field has a kink.
		const double u = x / 0.05 - 0.5, v = y / 0.05 - 0.5;
		if (std::abs(u - std::round(u)) < 1e-3 || std::abs(v - std::round(v)) < 1e-3) continue;
		const double fx = (map.distanceAt(x + h, y) - map.distanceAt(x - h, y)) / (2 * h);
		const double fy = (map.distanceAt(x, y + h) - map.distanceAt(x, y - h)) / (2 * h);
		EXPECT_NEAR(gx, fx, 2e-2) << "at " << x << "," << y;
		EXPECT_NEAR(gy, fy, 2e-2) << "at " << x << "," << y;
		++checked;
	}
	EXPECT_GT(checked, 1900);
}

TEST(DynamicDistanceMap, InterpolationReproducesCellSamples)
{
	DynamicDistanceMap map(0.1, 1.0);
	map.addObstacle(-3, 2);
	map.update();
	for (int cy = -2; cy <= 6; ++cy)
		for (int cx = -8; cx <= 2; ++cx)
			EXPECT_NEAR(map.distanceAt((cx + 0.5) * 0.1, (cy + 0.5) * 0.1), map.cellDistance(cx, cy), 1e-5);
	EXPECT_NEAR(map.cellDistance(0, 2), 0.3, 1e-6);
	EXPECT_NEAR(map.cellDistance(-3, 6), 0.4, 1e-6);
}

TEST(DynamicDistanceMap, QueriesOutsideTouchedAreaAreSafe)
{
	DynamicDistanceMap map(0.05, 0.5);
	// Empty map: everything is far.
	EXPECT_FLOAT_EQ(map.distanceAt(1e6, -1e6), 0.5f);
	EXPECT_FLOAT_EQ(map.distanceAt(std::nan(""), 0.0), 0.5f);
	EXPECT_FLOAT_EQ(map.distanceAt(1e300, 1e300), 0.5f);
	EXPECT_EQ(map.squaredDistanceCells(123456, -98765), -1);
	map.addObstacle(0, 0);
	map.update();
	double gx = 1, gy = 1;
	EXPECT_FLOAT_EQ(map.distanceAt(-5000.0, 7000.0, &gx, &gy), 0.5f);
	EXPECT_EQ(gx, 0.0);
	EXPECT_EQ(gy, 0.0);
	EXPECT_FALSE(map.isObstacle(-100000, 100000));
	map.removeObstacle(400000, 400000);	 // never set: no effect, no allocation
	map.update();
	EXPECT_EQ(map.squaredDistanceCells(0, 0), 0);
}

TEST(DynamicDistanceMap, StorageGrowsWithTouchedAreaOnly)
{
	DynamicDistanceMap map(0.05, 0.5);
	EXPECT_EQ(map.allocatedBlocks(), 0u);
	map.addObstacle(0, 0);
	map.update();
	const auto oneSpot = map.allocatedBlocks();
	EXPECT_LE(oneSpot, 4u);
	// Two obstacles 2 km apart: only blocks near each are allocated.
	map.addObstacle(40000, -40000);
	map.update();
	EXPECT_LE(map.allocatedBlocks(), 2 * 4u);
	EXPECT_EQ(map.squaredDistanceCells(40003, -40000), 9);
	EXPECT_LT(map.memoryBytes(), 32u * 1024u * 1024u);
	int x0, y0, x1, y1;
	ASSERT_TRUE(map.touchedBounds(x0, y0, x1, y1));
	EXPECT_LE(x0, 0);
	EXPECT_GE(x1, 40000);
	EXPECT_LE(y0, -40000);
	EXPECT_GE(y1, 0);
}

// The correlative search reads lattice rows through forRowSamples(), a block look-up per block: the
// samples it gives are cellDistance() of the same cells, in order, across block edges, negative cells
// and blocks never allocated (the far value).
TEST(DynamicDistanceMap, RowSamplesAreTheCellDistances)
{
	DynamicDistanceMap m(0.05, 0.5);
	std::mt19937 rng(3);
	std::uniform_int_distribution<int> cell(-90, 90);
	for (int k = 0; k < 60; ++k) m.addObstacle(cell(rng), cell(rng));
	m.update();
	std::size_t compared = 0, wrong = 0, far = 0;
	for (int step = 1; step <= 5; ++step)
		for (int k = 0; k < 200; ++k)
		{
			const int cx0 = 2 * cell(rng), cy = 2 * cell(rng), count = 1 + k % 90;
			int next = 0;
			m.forRowSamples(cx0, cy, step, count, [&](int i, float d) {
				wrong += i != next++ || d != m.cellDistance(cx0 + i * step, cy);
				far += d == float(m.maxDistance());
				++compared;
			});
			wrong += next != count;
		}
	EXPECT_EQ(wrong, 0u);
	EXPECT_GT(compared, 40000u);
	EXPECT_GT(far, 1000u);
	EXPECT_LT(far, compared);
}
