// Global localisation by branch and bound (BranchAndBoundSearch over a LikelihoodPyramid) against
// the map's area.
//
// Worlds: synthetic buildings of S × S m (S = 20, 50, 100) at 0.05 m: east-west corridors 2 m wide
// every 12 m, each lined on both sides by 5 m deep rooms 3-6 m wide with a 0.9 m door onto it, and
// 0-3 pieces of furniture (0.3-1.2 m boxes) per room; fixed seed. The distance layer is a
// DynamicDistanceMap (truncation 0.5 m) with the walls rasterised; the pyramid covers its whole
// allocated extent (the building plus up to a block of margin).
//
// Queries: 20 fixed random poses in corridors or rooms (≥ 0.4 m from walls, seeing beyond 3 m),
// any heading; the exact searches take the first 5 (a 100 m search takes seconds). Scans are
// exact ray casts: 181 beams over 180° ("181") or 360 over 360° ("360"), 30 m max range; the third
// argument 1 makes them noisy as a robot's: 2 cm range noise, and one beam in ten cut short by
// something the map does not hold.
//
//  BM_PyramidBuild/S        builds the pyramid (9 levels, σ 0.1 m); counters: pyramid_MB,
//                           distance_map_MB, cells (level 0).
//  BM_GlobalSearch/S/beams/noise  one exact whole-map search (searchGlobal: K = 1, every heading,
//                           the step from the farthest point) per query; time per search (wall)
//                           and cpu_ms_per_search (this thread's CPU time: the machine may be
//                           shared); counters: ok (fraction within 0.1 m and 1° of the truth),
//                           missed (fraction answered wrong with a fine score below the truth's
//                           own, i.e. lost by the search rather than by the scan's ambiguity);
//                           means per search of score, angles, roots, nodes, leaves, climbs,
//                           Mposes (lattice size, millions); pyramid_MB.
//  BM_CoarseToFine/S/beams/noise  the same with searchGlobalCoarseToFine (default options), the
//                           coarse pyramid built once beforehand (coarse_MB); coarse_ms: the
//                           coarse stage's share; refined: coarse candidates refined per search.
//  BM_LocalizerSearch/S/beams/noise  the exact search with the options of pm-slam-app's
//                           localisation (GlobalLocalizer): the 8 best distinct places within 0.7
//                           of the best, 120 points, the rotation step from the 90th percentile
//                           range.
//  BM_GlobalSearchMinScore  the exact search with minScore 0.5: a threshold from the start.
//  (The exact 50 m and 100 m searches take seconds each: run with --benchmark_filter to pick.)
//  BM_BruteForce/20         the reference: every lattice pose of the 20 m map scored (row by row,
//                           vectorisable) for 16 rotations; counter full_s extrapolates to all
//                           rotations, the time a brute-force whole-map search would take.
#include <benchmark/benchmark.h>
#include <pmslam/match/BranchAndBoundSearch.h>
#include <pmslam/match/LikelihoodPyramid.h>
#include <pmslam/slam/GlobalLocalizer.h>

#include <chrono>
#include <ctime>
#include <map>
#include <memory>
#include <random>

#include "../tests/match/BranchAndBoundSupport.h"

namespace
{
using namespace pmslam;
using namespace pmslam::testing;
using mrpt::math::TPose2D;

SyntheticWorld building(double side, unsigned seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(0, 1);
	SyntheticWorld w;
	w.addBox(0, 0, side, side);
	auto wallWithDoors = [&](double y, const std::vector<double>& doors) {
		double x = 0;
		for (double d : doors)
		{
			w.segments.push_back({x, y, d, y});
			x = d + 0.9;
		}
		w.segments.push_back({x, y, side, y});
	};
	for (double y0 = 5; y0 + 2 <= side - 5 + 1e-9; y0 += 12)
	{
		// Corridor [y0, y0+2]; rooms [y0-5, y0] below and [y0+2, y0+7] above, split at random.
		for (int row = 0; row < 2; ++row)
		{
			const double wallY = row ? y0 + 2 : y0, farY = row ? y0 + 7 : y0 - 5;
			std::vector<double> doors;
			double x = 0;
			while (x < side - 3)
			{
				const double width = std::min(side - x, 3 + 3 * u(rng));
				doors.push_back(x + 0.3 + (width - 1.5) * u(rng));
				if (x + width < side - 1e-9) w.segments.push_back({x + width, wallY, x + width, farY});
				for (int f = int(4 * u(rng)); f > 0; --f)
				{
					const double fx = x + 0.3 + (width - 1.6) * u(rng), fy = std::min(wallY, farY) + 0.8 + 3 * u(rng);
					w.addBox(fx, fy, fx + 0.3 + 0.9 * u(rng), fy + 0.3 + 0.9 * u(rng));
				}
				x += width;
			}
			wallWithDoors(wallY, doors);
		}
	}
	return w;
}

struct Setup
{
	SyntheticWorld world;
	std::unique_ptr<DynamicDistanceMap> map;
	std::unique_ptr<LikelihoodPyramid> pyramid;
	std::vector<TPose2D> queries;
};

Setup& setup(int side)
{
	static std::map<int, Setup> cache;
	auto it = cache.find(side);
	if (it != cache.end()) return it->second;
	Setup& s = cache[side];
	s.world = building(side, 7);
	s.map = std::make_unique<DynamicDistanceMap>(0.05, 0.5);
	rasterise(s.world, *s.map);
	s.pyramid = std::make_unique<LikelihoodPyramid>(*s.map);
	std::mt19937 rng(3);
	// A pose inside a closed piece of furniture is "free" too: keep poses that see beyond 3 m.
	while (s.queries.size() < 20)
	{
		const TPose2D p = randomFreePose(rng, s.world, side, side);
		double far = 0;
		for (const auto& q : castScan(s.world, p, 360, 2 * M_PI)) far = std::max(far, double(std::hypot(q.x, q.y)));
		if (far > 3) s.queries.push_back(p);
	}
	return s;
}

std::vector<mrpt::math::TPoint2Df> scanOf(const Setup& s, const TPose2D& p, int beams)
{
	return beams == 181 ? castScan(s.world, p, 181, M_PI) : castScan(s.world, p, 360, 2 * M_PI);
}

// A scan as a robot sees it: ranges with 2 cm of noise, and one beam in ten cut short by
// something the map does not hold (people, moved chairs), at a random fraction of its range.
std::vector<mrpt::math::TPoint2Df> noisy(std::vector<mrpt::math::TPoint2Df> pts, unsigned seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> noise(0, 0.02);
	std::uniform_real_distribution<double> u(0, 1);
	for (auto& p : pts)
	{
		const double r = std::hypot(p.x, p.y);
		const double to = u(rng) < 0.1 ? r * (0.2 + 0.7 * u(rng)) : r + noise(rng);
		p.x = float(p.x * to / r);
		p.y = float(p.y * to / r);
	}
	return pts;
}

void BM_PyramidBuild(benchmark::State& state)
{
	Setup& s = setup(int(state.range(0)));
	for (auto _ : state)
	{
		LikelihoodPyramid p(*s.map);
		benchmark::DoNotOptimize(p.level(0).cells.data());
	}
	state.counters["pyramid_MB"] = s.pyramid->memoryBytes() / 1e6;
	state.counters["distance_map_MB"] = s.map->memoryBytes() / 1e6;
	state.counters["cells"] = double(s.pyramid->window().width()) * s.pyramid->window().height();
}

// CPU time of this thread: the machine running the benchmark may be shared, and wall time then
// counts the other programs' turns too.
double threadSeconds()
{
	timespec t{};
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

enum class Mode
{
	Exact,
	CoarseToFine
};

// The options pm-slam-app's localisation searches with (GlobalLocalizer's defaults: the 8 best
// distinct places within 0.7 of the best, 120 points), the rotation step, as its own, from the
// 90th percentile range.
BranchAndBoundSearch::Options localizerOptions()
{
	const GlobalLocalizerOptions localizer;
	BranchAndBoundSearch::Options o;
	o.candidates = localizer.candidates;
	o.minRelativeScore = localizer.candidateFloor;
	o.maxPoints = localizer.searchPoints;
	o.rangeQuantile = 0.9;
	return o;
}

void runSearches(benchmark::State& state, double minScore, Mode mode = Mode::Exact,
				 BranchAndBoundSearch::Options o = BranchAndBoundSearch::Options())
{
	Setup& s = setup(int(state.range(0)));
	const int beams = int(state.range(1));
	const bool withNoise = state.range(2) != 0;
	o.minScore = minScore;
	const BranchAndBoundSearch bnb(*s.pyramid, o);
	// Built outside the timed searches (once per map, like the pyramid).
	const LikelihoodPyramid coarse = bnb.coarsePyramid();
	double cpu = 0;
	std::vector<std::vector<mrpt::math::TPoint2Df>> scans;
	// The exact search of a big map takes seconds: 5 queries; the two-stage search all 20.
	const std::size_t queries = mode == Mode::Exact ? 5 : s.queries.size();
	for (std::size_t q = 0; q < queries; ++q)
		scans.push_back(withNoise ? noisy(scanOf(s, s.queries[q], beams), unsigned(q)) : scanOf(s, s.queries[q], beams));
	double ok = 0, missed = 0, score = 0, searches = 0, mposes = 0;
	BranchAndBoundSearch::Stats total;
	for (auto _ : state)
	{
		double iteration = 0;
		for (std::size_t q = 0; q < scans.size(); ++q)
		{
			const double c0 = threadSeconds();
			const auto r = mode == Mode::Exact ? bnb.searchGlobal(scans[q]) : bnb.searchGlobalCoarseToFine(scans[q], coarse);
			cpu += threadSeconds() - c0;
			iteration += r.stats.seconds;
			searches += 1;
			total.angles += r.stats.angles;
			total.translations = r.stats.translations;
			mposes += double(r.stats.angles) * r.stats.translations / 1e6;
			total.roots += r.stats.roots;
			total.nodes += r.stats.nodes;
			total.leaves += r.stats.leaves;
			total.climbs += r.stats.climbs;
			total.seconds += r.stats.seconds;
			total.coarseSeconds += r.stats.coarseSeconds;
			total.refined += r.stats.refined;
			const auto& t = s.queries[q];
			// The fine score at the truth (the best pose next to it): a wrong answer scoring less
			// is a miss of the search; one scoring more is the scan's ambiguity.
			const auto atTruth = bnb.searchWindow(scans[q], t, 0.1, 0.02);
			const double truthScore = atTruth.candidates.empty() ? 0 : atTruth.candidates[0].score;
			if (r.candidates.empty())
			{
				missed += truthScore > 0;
				continue;
			}
			const auto& p = r.candidates[0].pose;
			const bool found = std::hypot(p.x - t.x, p.y - t.y) < 0.1 && std::abs(angleDiff(p.phi, t.phi)) < M_PI / 180;
			ok += found;
			missed += !found && r.candidates[0].score < truthScore;
			score += r.candidates[0].score;
		}
		state.SetIterationTime(iteration);
	}
	state.counters["ms_per_search"] = 1e3 * total.seconds / searches;
	state.counters["cpu_ms_per_search"] = 1e3 * cpu / searches;
	state.counters["pyramid_MB"] = s.pyramid->memoryBytes() / 1e6;
	if (mode == Mode::CoarseToFine)
	{
		state.counters["coarse_MB"] = coarse.memoryBytes() / 1e6;
		state.counters["coarse_ms"] = 1e3 * total.coarseSeconds / searches;
		state.counters["refined"] = double(total.refined) / searches;
	}
	state.counters["ok"] = ok / searches;
	state.counters["missed"] = missed / searches;
	state.counters["score"] = score / searches;
	state.counters["angles"] = total.angles / searches;
	state.counters["Mposes"] = mposes / searches;
	state.counters["roots"] = total.roots / searches;
	state.counters["nodes"] = total.nodes / searches;
	state.counters["leaves"] = total.leaves / searches;
	state.counters["climbs"] = total.climbs / searches;
}

void BM_GlobalSearch(benchmark::State& state) { runSearches(state, 0.0); }
void BM_GlobalSearchMinScore(benchmark::State& state) { runSearches(state, 0.5); }
void BM_CoarseToFine(benchmark::State& state) { runSearches(state, 0.0, Mode::CoarseToFine); }
void BM_LocalizerSearch(benchmark::State& state) { runSearches(state, 0.0, Mode::Exact, localizerOptions()); }

void BM_BruteForce(benchmark::State& state)
{
	Setup& s = setup(int(state.range(0)));
	const BranchAndBoundSearch bnb(*s.pyramid);
	const auto lat = bnb.globalLattice(scanOf(s, s.queries[0], 181));
	const int slices = 16;
	double seconds = 0;
	for (auto _ : state)
	{
		const auto t0 = std::chrono::steady_clock::now();
		const auto scores = bruteForceScores(bnb, lat, 0, slices);
		benchmark::DoNotOptimize(scores.data());
		seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	}
	state.counters["slice_ms"] = 1e3 * seconds / slices;
	state.counters["full_s"] = seconds / slices * double(lat.angles.size());
	state.counters["angles"] = double(lat.angles.size());
}

}  // namespace

BENCHMARK(BM_PyramidBuild)->Arg(20)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_GlobalSearch)
	->Args({20, 181, 0})
	->Args({50, 181, 0})
	->Args({100, 181, 0})
	->Args({20, 360, 0})
	->Unit(benchmark::kMillisecond)
	->UseManualTime()
	->Iterations(1);
BENCHMARK(BM_LocalizerSearch)
	->Args({20, 181, 0})
	->Args({50, 181, 0})
	->Args({100, 181, 0})
	->Args({100, 181, 1})
	->Unit(benchmark::kMillisecond)
	->UseManualTime()
	->Iterations(1);
BENCHMARK(BM_CoarseToFine)
	->Args({20, 181, 0})
	->Args({50, 181, 0})
	->Args({100, 181, 0})
	->Args({20, 360, 0})
	->Args({100, 360, 0})
	->Args({20, 181, 1})
	->Args({50, 181, 1})
	->Args({100, 181, 1})
	->Args({100, 360, 1})
	->Unit(benchmark::kMillisecond)
	->UseManualTime()
	->Iterations(1);
BENCHMARK(BM_GlobalSearchMinScore)
	->Args({20, 181, 0})
	->Args({50, 181, 0})
	->Unit(benchmark::kMillisecond)
	->UseManualTime()
	->Iterations(1);
BENCHMARK(BM_BruteForce)->Arg(20)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_MAIN();
