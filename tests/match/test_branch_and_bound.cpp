// BranchAndBoundSearch and LikelihoodPyramid: the pyramid's levels are max pools, the bounds are
// bounds, and the search returns exactly what scoring every lattice pose returns; globally it
// finds the true pose, and in a symmetric room it reports the symmetric poses alike.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/match/BranchAndBoundSearch.h>
#include <pmslam/match/LikelihoodPyramid.h>

#include <random>

#include "BranchAndBoundSupport.h"

using namespace pmslam;
using namespace pmslam::testing;
using mrpt::math::TPose2D;

namespace
{
// A random world on its distance map, the same for a given seed.
struct Case
{
	SyntheticWorld world;
	DynamicDistanceMap map;
	double w, h;
};

Case randomCase(std::mt19937& rng, double res, double w, double h)
{
	Case c{randomRooms(rng, w, h, 2, 4), DynamicDistanceMap(res, 0.5), w, h};
	rasterise(c.world, c.map);
	return c;
}

// The brute-force candidates that a relative floor keeps.
std::vector<BruteCandidate> keepAbove(std::vector<BruteCandidate> c, double relative)
{
	if (c.empty()) return c;
	const int64_t floor = int64_t(std::ceil(relative * double(c.front().score) - 1e-9));
	while (c.back().score < floor) c.pop_back();
	return c;
}

void expectSameCandidates(const BranchAndBoundSearch::Result& bnb, const std::vector<BruteCandidate>& brute,
						  const std::string& what)
{
	ASSERT_EQ(bnb.candidates.size(), brute.size()) << what;
	for (std::size_t c = 0; c < brute.size(); ++c)
	{
		EXPECT_EQ(bnb.candidates[c].rawScore, brute[c].score) << what << " candidate " << c;
		EXPECT_EQ(bnb.candidates[c].a, brute[c].a) << what << " candidate " << c;
		EXPECT_EQ(bnb.candidates[c].i, brute[c].i) << what << " candidate " << c;
		EXPECT_EQ(bnb.candidates[c].j, brute[c].j) << what << " candidate " << c;
	}
}
}  // namespace

TEST(LikelihoodPyramid, LevelsAreMaxPoolsOfLevelZero)
{
	std::mt19937 rng(11);
	Case c = randomCase(rng, 0.05, 4, 3);
	// A window cutting through the map, so that cells on both sides of its border are probed.
	const LikelihoodPyramid::CellWindow win{5, -3, 70, 50};
	LikelihoodPyramid::Options o;
	o.levels = 6;
	const LikelihoodPyramid pyr(c.map, win, o);
	std::uniform_int_distribution<int> ux(win.minX - 40, win.maxX + 40), uy(win.minY - 40, win.maxY + 40);
	for (int probe = 0; probe < 400; ++probe)
	{
		const int x = ux(rng), y = uy(rng);
		const bool inside = x >= win.minX && x <= win.maxX && y >= win.minY && y <= win.maxY;
		EXPECT_EQ(pyr.value(0, x, y), inside ? pyr.quantise(c.map.cellDistance(x, y)) : 0) << x << "," << y;
		for (int h = 1; h < o.levels; ++h)
		{
			int best = 0;
			for (int dy = 0; dy < (1 << h); ++dy)
				for (int dx = 0; dx < (1 << h); ++dx) best = std::max(best, pyr.value(0, x + dx, y + dy));
			ASSERT_EQ(pyr.value(h, x, y), best) << "level " << h << " at " << x << "," << y;
		}
	}
	EXPECT_EQ(pyr.quantise(0), LikelihoodPyramid::kMaxValue);
	EXPECT_EQ(pyr.quantise(0.5), 0);
}

TEST(BranchAndBoundSearch, BoundIsNeverBelowTheBestPoseBeneath)
{
	std::mt19937 rng(12);
	for (int trial = 0; trial < 3; ++trial)
	{
		Case c = randomCase(rng, 0.1, 6, 5);
		LikelihoodPyramid::Options po;
		po.levels = 7;
		const LikelihoodPyramid pyr(c.map, po);
		const BranchAndBoundSearch bnb(pyr);
		const auto lat = bnb.globalLattice(castScan(c.world, randomFreePose(rng, c.world, c.w, c.h), 90, 2 * M_PI));
		const auto scores = bruteForceScores(bnb, lat);
		const int nA = int(lat.angles.size());
		std::uniform_int_distribution<int> ua(0, nA - 1), ui(0, lat.nx - 1), uj(0, lat.ny - 1), uh(0, po.levels - 1);
		for (int probe = 0; probe < 300; ++probe)
		{
			const int a = ua(rng), h = uh(rng), w = 1 << h;
			// Nodes on the search's own grid and anywhere else (the neighbourhood search's nodes).
			const int i = probe % 2 ? ui(rng) / w * w : ui(rng), j = probe % 2 ? uj(rng) / w * w : uj(rng);
			int64_t best = -1;
			for (int y = j; y < std::min(lat.ny, j + w); ++y)
				for (int x = i; x < std::min(lat.nx, i + w); ++x)
					best = std::max<int64_t>(best, scores[(std::size_t(a) * lat.ny + y) * lat.nx + x]);
			const int64_t b = bnb.nodeBound(lat, h, a, i, j);
			ASSERT_GE(b, best) << "level " << h << " node " << a << "," << i << "," << j;
			if (h == 0)
			{
				ASSERT_EQ(b, best);
			}
			else
			{
				ASSERT_GE(b, bnb.nodeBound(lat, h - 1, a, i, j));
			}
		}
	}
}

TEST(BranchAndBoundSearch, WindowSearchEqualsBruteForce)
{
	std::mt19937 rng(13);
	std::uniform_real_distribution<double> off(-0.3, 0.3), offA(-0.1, 0.1);
	for (int trial = 0; trial < 40; ++trial)
	{
		Case c = randomCase(rng, 0.05, 6, 5);
		const LikelihoodPyramid pyr(c.map);
		BranchAndBoundSearch::Options o;
		o.candidates = 1 + trial % 4;
		o.maxPoints = trial % 2 ? 60 : 0;
		o.minRelativeScore = trial % 3 == 2 ? 0.9 : 0.0;
		const BranchAndBoundSearch bnb(pyr, o);
		const TPose2D truth = randomFreePose(rng, c.world, c.w, c.h);
		const TPose2D centre(truth.x + off(rng), truth.y + off(rng), truth.phi + offA(rng));
		const auto lat = bnb.windowLattice(castScan(c.world, truth, 181, M_PI), centre, 0.4, 0.15);
		const auto result = bnb.search(lat);
		const auto brute =
			keepAbove(bruteForceCandidates(bruteForceScores(bnb, lat), lat, o.candidates), o.minRelativeScore);
		expectSameCandidates(result, brute, "trial " + std::to_string(trial));
		// Far fewer poses scored than the lattice holds (the point of the exercise).
		EXPECT_LT(result.stats.leaves, result.stats.angles * result.stats.translations);
	}
}

TEST(BranchAndBoundSearch, GlobalSearchEqualsBruteForce)
{
	std::mt19937 rng(14);
	for (int trial = 0; trial < 8; ++trial)
	{
		Case c = randomCase(rng, 0.1, 6, 5);
		LikelihoodPyramid::Options po;
		po.levels = 4 + trial % 4;	// a top level smaller and larger than the map
		const LikelihoodPyramid pyr(c.map, po);
		BranchAndBoundSearch::Options o;
		o.candidates = 1 + trial % 3;
		o.maxPoints = 60;
		o.distinctLinear = trial % 2 ? 0.3 : 0.5;
		o.minRelativeScore = trial % 4 == 3 ? 0.7 : 0.0;
		const BranchAndBoundSearch bnb(pyr, o);
		const auto lat = bnb.globalLattice(castScan(c.world, randomFreePose(rng, c.world, c.w, c.h), 181, M_PI));
		const auto result = bnb.search(lat);
		const auto brute =
			keepAbove(bruteForceCandidates(bruteForceScores(bnb, lat), lat, o.candidates), o.minRelativeScore);
		expectSameCandidates(result, brute, "trial " + std::to_string(trial));
	}
}

TEST(BranchAndBoundSearch, MinScoreDropsOnlyWhatIsBelowIt)
{
	std::mt19937 rng(15);
	Case c = randomCase(rng, 0.1, 6, 5);
	const LikelihoodPyramid pyr(c.map);
	BranchAndBoundSearch::Options o;
	o.candidates = 5;
	const auto pts = castScan(c.world, randomFreePose(rng, c.world, c.w, c.h), 181, M_PI);
	const auto all = BranchAndBoundSearch(pyr, o).searchGlobal(pts);
	ASSERT_EQ(all.candidates.size(), 5u);
	o.minScore = all.candidates[2].score;  // keeps the first three exactly
	const auto some = BranchAndBoundSearch(pyr, o).searchGlobal(pts);
	ASSERT_EQ(some.candidates.size(), 3u);
	for (int k = 0; k < 3; ++k) EXPECT_EQ(some.candidates[k].rawScore, all.candidates[k].rawScore);
	EXPECT_LT(some.stats.nodes, all.stats.nodes);
}

TEST(BranchAndBoundSearch, GlobalSearchFindsTheTruePose)
{
	std::mt19937 rng(16);
	for (int trial = 0; trial < 12; ++trial)
	{
		Case c = randomCase(rng, 0.05, 10, 8);
		const LikelihoodPyramid pyr(c.map);
		const BranchAndBoundSearch bnb(pyr);
		const TPose2D truth = randomFreePose(rng, c.world, c.w, c.h);
		const auto lat = bnb.globalLattice(castScan(c.world, truth, 360, 2 * M_PI));
		const auto result = bnb.search(lat);
		ASSERT_EQ(result.candidates.size(), 1u);
		const TPose2D& p = result.candidates[0].pose;
		// The nearest lattice pose is within half a cell and half a step; its neighbours count too.
		EXPECT_LE(std::abs(p.x - truth.x), 0.05) << "trial " << trial;
		EXPECT_LE(std::abs(p.y - truth.y), 0.05) << "trial " << trial;
		EXPECT_LE(std::abs(angleDiff(p.phi, truth.phi)), lat.angularStep) << "trial " << trial;
		EXPECT_GT(result.candidates[0].score, 0.6);
	}
}

TEST(BranchAndBoundSearch, StockGridThroughTheAlignersDistanceLayer)
{
	// An MRPT grid whose origin is not on a multiple of the resolution: poses come back in its frame.
	std::mt19937 rng(17);
	const SyntheticWorld world = randomRooms(rng, 9, 7, 2, 4);
	mrpt::maps::COccupancyGridMap2D grid(-0.63, 9.71, -0.42, 7.58, 0.05);
	world.rasterise(grid);
	const LikelihoodPyramid pyr = LikelihoodPyramid::fromGrid(grid);
	EXPECT_NE(pyr.frameOffset().x, 0.0);
	const BranchAndBoundSearch bnb(pyr);
	for (int trial = 0; trial < 4; ++trial)
	{
		const TPose2D truth = randomFreePose(rng, world, 9, 7);
		const auto result = bnb.searchGlobal(castScan(world, truth, 360, 2 * M_PI));
		ASSERT_EQ(result.candidates.size(), 1u);
		const TPose2D& p = result.candidates[0].pose;
		EXPECT_LE(std::abs(p.x - truth.x), 0.05) << "trial " << trial;
		EXPECT_LE(std::abs(p.y - truth.y), 0.05) << "trial " << trial;
		EXPECT_LE(std::abs(angleDiff(p.phi, truth.phi)), 0.01) << "trial " << trial;
	}
}

TEST(BranchAndBoundSearch, SquareRoomGivesFourNearEqualCandidates)
{
	// A 4 m square room: a scan fits at the true pose and at its three rotations by 90° about the
	// centre. The search must report all four, scored alike, before anything else. Asked for five
	// within 80 % of the best, it returns just those four.
	SyntheticWorld world;
	world.addBox(0.025, 0.025, 4.025, 4.025);
	DynamicDistanceMap map(0.05, 0.5);
	rasterise(world, map);
	const LikelihoodPyramid pyr(map);
	BranchAndBoundSearch::Options o;
	o.candidates = 5;
	o.minRelativeScore = 0.8;
	const BranchAndBoundSearch bnb(pyr, o);
	const TPose2D truth(1.3, 2.9, 0.4);
	const auto lat = bnb.globalLattice(castScan(world, truth, 360, 2 * M_PI));
	const auto result = bnb.search(lat);
	// Exactly four: nothing else scores within 80 % of the best.
	ASSERT_EQ(result.candidates.size(), 4u);
	const double best = result.candidates[0].score;
	for (int k = 0; k < 4; ++k)
	{
		const TPose2D& p = result.candidates[std::size_t(k)].pose;
		EXPECT_GT(result.candidates[std::size_t(k)].score, 0.95 * best) << "candidate " << k;
		// Which rotation of the truth about the centre (2.025, 2.025) is it?
		bool matched = false;
		for (int q = 0; q < 4; ++q)
		{
			const double c = std::cos(q * M_PI / 2), s = std::sin(q * M_PI / 2);
			const double x = 2.025 + c * (truth.x - 2.025) - s * (truth.y - 2.025);
			const double y = 2.025 + s * (truth.x - 2.025) + c * (truth.y - 2.025);
			matched |= std::hypot(p.x - x, p.y - y) < 0.08 &&
					   std::abs(angleDiff(p.phi, truth.phi + q * M_PI / 2)) <= 2 * lat.angularStep;
		}
		EXPECT_TRUE(matched) << "candidate " << k << " at " << p.x << "," << p.y << "," << p.phi;
	}
	// Without the floor the fifth comes too, and it is no symmetric copy: clearly worse.
	o.minRelativeScore = 0;
	const auto all = BranchAndBoundSearch(pyr, o).search(lat);
	ASSERT_EQ(all.candidates.size(), 5u);
	for (int k = 0; k < 4; ++k) EXPECT_EQ(all.candidates[std::size_t(k)].rawScore, result.candidates[std::size_t(k)].rawScore);
	EXPECT_LT(all.candidates[4].score, 0.8 * best);
}

TEST(BranchAndBoundSearch, IrregularRoomIsNotAmbiguous)
{
	// The same measure in an irregular world: the second candidate scores well below the first.
	std::mt19937 rng(18);
	const SyntheticWorld world = randomRooms(rng, 10, 8, 2, 4);
	DynamicDistanceMap map(0.05, 0.5);
	rasterise(world, map);
	const LikelihoodPyramid pyr(map);
	BranchAndBoundSearch::Options o;
	o.candidates = 2;
	const TPose2D truth = randomFreePose(rng, world, 10, 8);
	const auto result = BranchAndBoundSearch(pyr, o).searchGlobal(castScan(world, truth, 360, 2 * M_PI));
	ASSERT_EQ(result.candidates.size(), 2u);
	EXPECT_NEAR(result.candidates[0].pose.x, truth.x, 0.05);
	EXPECT_NEAR(result.candidates[0].pose.y, truth.y, 0.05);
	EXPECT_LT(result.candidates[1].score, 0.8 * result.candidates[0].score);
}

TEST(LikelihoodPyramid, CoarsenedLevelZeroIsTheDilatedMaxOfTheFineOne)
{
	std::mt19937 rng(19);
	Case c = randomCase(rng, 0.05, 4, 3);
	const LikelihoodPyramid fine(c.map);
	const int factor = 4, dilation = 2;
	const LikelihoodPyramid coarse = fine.coarsened(factor, dilation, 5);
	EXPECT_DOUBLE_EQ(coarse.resolution(), 0.2);
	EXPECT_EQ(coarse.levels(), 5);
	const auto& w = coarse.window();
	std::uniform_int_distribution<int> ux(w.minX - 5, w.maxX + 5), uy(w.minY - 5, w.maxY + 5);
	int nonZero = 0;
	for (int probe = 0; probe < 300; ++probe)
	{
		const int x = ux(rng), y = uy(rng);
		const bool inside = x >= w.minX && x <= w.maxX && y >= w.minY && y <= w.maxY;
		int best = 0;
		for (int fy = y * factor - dilation; fy < (y + 1) * factor + dilation; ++fy)
			for (int fx = x * factor - dilation; fx < (x + 1) * factor + dilation; ++fx)
				best = std::max(best, fine.value(0, fx, fy));
		ASSERT_EQ(coarse.value(0, x, y), inside ? best : 0) << x << "," << y;
		nonZero += best > 0;
		for (int h = 1; h < coarse.levels(); ++h)
		{
			int pooled = 0;
			for (int dy = 0; dy < (1 << h); ++dy)
				for (int dx = 0; dx < (1 << h); ++dx) pooled = std::max(pooled, coarse.value(0, x + dx, y + dy));
			ASSERT_EQ(coarse.value(h, x, y), pooled) << "level " << h << " at " << x << "," << y;
		}
	}
	EXPECT_GT(nonZero, 30);	// the probes did see walls
}

TEST(BranchAndBoundSearch, CoarseLatticeSearchEqualsBruteForce)
{
	// The coarse stage is search() on a coarsened pyramid: still the exact optimum of its lattice.
	std::mt19937 rng(20);
	for (int trial = 0; trial < 3; ++trial)
	{
		Case c = randomCase(rng, 0.05, 8, 6);
		const LikelihoodPyramid coarse = LikelihoodPyramid(c.map).coarsened(4, 2, 6);
		BranchAndBoundSearch::Options o;
		o.candidates = 3;
		o.maxPoints = 64;
		o.rangeQuantile = 0.5;
		const BranchAndBoundSearch bnb(coarse, o);
		const auto lat = bnb.globalLattice(castScan(c.world, randomFreePose(rng, c.world, c.w, c.h), 181, M_PI));
		expectSameCandidates(bnb.search(lat), bruteForceCandidates(bruteForceScores(bnb, lat), lat, o.candidates),
							 "trial " + std::to_string(trial));
	}
}

TEST(BranchAndBoundSearch, RangeQuantileSetsTheRotationStep)
{
	std::mt19937 rng(21);
	Case c = randomCase(rng, 0.05, 10, 8);
	const LikelihoodPyramid pyr(c.map);
	const auto pts = castScan(c.world, randomFreePose(rng, c.world, c.w, c.h), 360, 2 * M_PI);
	std::vector<double> ranges;
	for (const auto& p : pts) ranges.push_back(std::hypot(p.x, p.y));
	std::sort(ranges.begin(), ranges.end());
	BranchAndBoundSearch::Options o;
	const auto all = BranchAndBoundSearch(pyr, o).globalLattice(pts);
	EXPECT_EQ(all.angles.size(), std::size_t(std::ceil(2 * M_PI * ranges.back() / 0.05 - 1e-9)));
	o.rangeQuantile = 0.5;
	const auto median = BranchAndBoundSearch(pyr, o).globalLattice(pts);
	const double r = ranges[std::size_t(std::lround(0.5 * double(ranges.size() - 1)))];
	EXPECT_EQ(median.angles.size(), std::size_t(std::ceil(2 * M_PI * r / 0.05 - 1e-9)));
	EXPECT_LT(median.angles.size(), all.angles.size());
}

TEST(BranchAndBoundSearch, CoarseToFineFindsTheTruePose)
{
	// Random worlds bigger than the coarse cells by far; a full scan and a half one.
	std::mt19937 rng(22);
	int found = 0, trials = 0;
	for (int trial = 0; trial < 10; ++trial)
	{
		Case c{randomRooms(rng, 16, 12, 5, 10), DynamicDistanceMap(0.05, 0.5), 16, 12};
		rasterise(c.world, c.map);
		const LikelihoodPyramid pyr(c.map);
		const BranchAndBoundSearch bnb(pyr);
		const TPose2D truth = randomFreePose(rng, c.world, c.w, c.h);
		const auto pts = trial % 2 ? castScan(c.world, truth, 181, M_PI) : castScan(c.world, truth, 360, 2 * M_PI);
		const auto result = bnb.searchGlobalCoarseToFine(pts);
		ASSERT_EQ(result.candidates.size(), 1u);
		EXPECT_GT(result.stats.refined, 0u);
		EXPECT_GT(result.stats.coarseSeconds, 0.0);
		const TPose2D& p = result.candidates[0].pose;
		// A refined pose is a fine cell centre within half a cell of the truth, and its heading
		// within a fine step or so.
		const double step = bnb.globalLattice(pts).angularStep;
		const bool ok = std::abs(p.x - truth.x) <= 0.05 && std::abs(p.y - truth.y) <= 0.05 &&
						std::abs(angleDiff(p.phi, truth.phi)) <= 1.5 * step;
		EXPECT_TRUE(ok) << "trial " << trial << ": " << p.x << "," << p.y << "," << p.phi << " truth " << truth.x
						<< "," << truth.y << "," << truth.phi;
		EXPECT_GT(result.candidates[0].score, 0.6) << "trial " << trial;
		found += ok;
		++trials;
	}
	EXPECT_EQ(found, trials);
}

TEST(BranchAndBoundSearch, CoarseToFineAgreesWithTheExhaustiveSearch)
{
	// On a map small enough for the exact fine search: the same place, and the refined score (the
	// fine score on the refinement's window, whose rotations differ) as good to within a percent.
	std::mt19937 rng(23);
	for (int trial = 0; trial < 4; ++trial)
	{
		Case c = randomCase(rng, 0.05, 10, 8);
		const LikelihoodPyramid pyr(c.map);
		const BranchAndBoundSearch bnb(pyr);
		const auto pts = castScan(c.world, randomFreePose(rng, c.world, c.w, c.h), 360, 2 * M_PI);
		const auto exact = bnb.searchGlobal(pts);
		const auto fast = bnb.searchGlobalCoarseToFine(pts);
		ASSERT_EQ(exact.candidates.size(), 1u);
		ASSERT_EQ(fast.candidates.size(), 1u);
		const TPose2D &e = exact.candidates[0].pose, &f = fast.candidates[0].pose;
		EXPECT_LE(std::hypot(e.x - f.x, e.y - f.y), 0.075) << "trial " << trial;
		EXPECT_LE(std::abs(angleDiff(e.phi, f.phi)), 0.02) << "trial " << trial;
		EXPECT_GT(fast.candidates[0].score, 0.99 * exact.candidates[0].score) << "trial " << trial;
		// The point of it: far less work.
		EXPECT_LT(fast.stats.nodes, exact.stats.nodes / 2) << "trial " << trial;
	}
}

TEST(BranchAndBoundSearch, CoarseToFineReportsTheSquareRoomsFourPoses)
{
	// The re-ranking keeps distinct candidates: the four symmetric poses of a square room, alike.
	SyntheticWorld world;
	world.addBox(0.025, 0.025, 6.025, 6.025);
	DynamicDistanceMap map(0.05, 0.5);
	rasterise(world, map);
	const LikelihoodPyramid pyr(map);
	BranchAndBoundSearch::Options o;
	o.candidates = 5;
	o.minRelativeScore = 0.8;
	const BranchAndBoundSearch bnb(pyr, o);
	const TPose2D truth(1.7, 4.1, -0.7);
	const auto result = bnb.searchGlobalCoarseToFine(castScan(world, truth, 360, 2 * M_PI));
	ASSERT_EQ(result.candidates.size(), 4u);
	for (int k = 0; k < 4; ++k)
	{
		const TPose2D& p = result.candidates[std::size_t(k)].pose;
		EXPECT_GT(result.candidates[std::size_t(k)].score, 0.95 * result.candidates[0].score) << "candidate " << k;
		bool matched = false;
		for (int q = 0; q < 4; ++q)
		{
			const double c = std::cos(q * M_PI / 2), s = std::sin(q * M_PI / 2);
			const double x = 3.025 + c * (truth.x - 3.025) - s * (truth.y - 3.025);
			const double y = 3.025 + s * (truth.x - 3.025) + c * (truth.y - 3.025);
			matched |= std::hypot(p.x - x, p.y - y) < 0.08 && std::abs(angleDiff(p.phi, truth.phi + q * M_PI / 2)) < 0.03;
		}
		EXPECT_TRUE(matched) << "candidate " << k << " at " << p.x << "," << p.y << "," << p.phi;
	}
}
