// Micro-benchmarks of DynamicDistanceMap on a 100 m × 100 m office floor at 0.05 m
// (2000 × 2000 cells), truncation 0.5 m:
//   BM_IncrementalUpdate/N  one scan's worth of changes (≈N cells flip: short new
//                           obstacles appear, short runs of wall disappear), propagated
//                           by update(); then undone by a second update() so every
//                           iteration starts from the same map. Reported per update.
//   BM_FullRebuild          the same map recomputed from scratch: a fresh
//                           DynamicDistanceMap, every obstacle added, one update().
//   BM_DistanceAt[Grad]     distanceAt() at random points within 0.5 m of a wall.
// Counters: "time_per_update" / "time_per_query" (seconds, lower is better),
// "cells_changed" (obstacle cells flipped per update), "cells_processed" (queue pops
// per update, as returned by update()).
#include <benchmark/benchmark.h>
#include <pmslam/map/DynamicDistanceMap.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace
{
constexpr double kRes = 0.05;  // m per cell
constexpr double kTrunc = 0.5;	// m
constexpr int kSide = 2000;	 // cells per side: 100 m
constexpr double kWorld = kSide * kRes;

using CellList = std::vector<std::pair<int, int>>;

int toCell(double v) { return static_cast<int>(std::floor(v / kRes + 1e-9)); }

/** Occupancy of the whole floor, one byte per cell, plus the list of obstacle cells. */
struct Floor
{
	std::vector<uint8_t> occ = std::vector<uint8_t>(std::size_t(kSide) * kSide, 0);
	CellList obstacles;

	bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < kSide && cy < kSide; }
	uint8_t& at(int cx, int cy) { return occ[std::size_t(cy) * kSide + cx]; }
	uint8_t at(int cx, int cy) const { return occ[std::size_t(cy) * kSide + cx]; }

	/** Rasterises a wall segment (metres): every cell the segment passes through. */
	void wall(double x0, double y0, double x1, double y1)
	{
		const double len = std::hypot(x1 - x0, y1 - y0);
		const int n = static_cast<int>(len / (kRes * 0.25)) + 1;
		for (int k = 0; k <= n; ++k)
		{
			const double t = double(k) / n;
			const int cx = toCell(x0 + t * (x1 - x0)), cy = toCell(y0 + t * (y1 - y0));
			if (inside(cx, cy)) at(cx, cy) = 1;
		}
	}
	void box(double x0, double y0, double x1, double y1)
	{
		wall(x0, y0, x1, y0);
		wall(x1, y0, x1, y1);
		wall(x1, y1, x0, y1);
		wall(x0, y1, x0, y0);
	}
	/** A wall from x0 to x1 at height y with door gaps [d, d + w) for each d in doors. */
	void wallWithDoors(double x0, double x1, double y, const std::vector<double>& doors, double w)
	{
		double x = x0;
		for (double d : doors)
		{
			if (d > x) wall(x, y, d, y);
			x = d + w;
		}
		if (x < x1) wall(x, y, x1, y);
	}
	void collect()
	{
		obstacles.clear();
		for (int cy = 0; cy < kSide; ++cy)
			for (int cx = 0; cx < kSide; ++cx)
				if (at(cx, cy)) obstacles.emplace_back(cx, cy);
	}
};

/** An office floor: 8 bands, each a 2 m corridor flanked by two rows of 4 m × 5 m rooms
 * (doors 1 m wide onto the corridor), a desk in every room and a cabinet in every third,
 * pillars along the corridors, and an outer wall. */
Floor makeOffice()
{
	Floor f;
	f.box(0.3, 0.3, kWorld - 0.3, kWorld - 0.3);
	const double xs = 2.0, xe = 98.0, roomW = 4.0;
	const int nRooms = static_cast<int>((xe - xs) / roomW);	 // 24 per row
	int roomNo = 0;
	for (int k = 0; k < 8; ++k)
	{
		const double b = 2.0 + 12.0 * k;  // corridor between y = b and y = b + 2
		std::vector<double> northDoors, southDoors;
		for (int j = 0; j < nRooms; ++j)
		{
			northDoors.push_back(xs + roomW * j + 1.5);	 // rooms above this corridor
			southDoors.push_back(xs + roomW * j + 0.5);	 // rooms below (previous band's upper row)
		}
		f.wallWithDoors(xs, xe, b, k > 0 ? southDoors : std::vector<double>{}, 1.0);
		f.wallWithDoors(xs, xe, b + 2.0, northDoors, 1.0);
		f.wall(xs, b + 7.0, xe, b + 7.0);  // back-to-back rooms
		for (int j = 0; j <= nRooms; ++j) f.wall(xs + roomW * j, b + 2.0, xs + roomW * j, b + 12.0);
		for (int j = 0; j < nRooms; j += 2)	 // pillars in the corridor
			f.box(xs + roomW * j + 3.7, b + 0.15, xs + roomW * j + 4.1, b + 0.55);
		for (int row = 0; row < 2; ++row)
			for (int j = 0; j < nRooms; ++j, ++roomNo)
			{
				const double rx = xs + roomW * j, ry = b + 2.0 + 5.0 * row;
				const double dx = 0.6 + 0.3 * (roomNo % 5), dy = 1.2 + 0.4 * (roomNo % 4);
				f.box(rx + dx, ry + dy, rx + dx + 1.2, ry + dy + 0.6);	// desk
				if (roomNo % 3 == 0) f.box(rx + 3.1, ry + 3.8, rx + 3.7, ry + 4.6);	 // cabinet
			}
	}
	// The top strip above the last band: one long room with a few columns.
	for (int j = 0; j < 12; ++j) f.box(5.0 + 8.0 * j, 94.0, 5.5 + 8.0 * j, 94.5);
	f.collect();
	return f;
}

const Floor& office()
{
	static const Floor f = makeOffice();
	return f;
}

void fillMap(pmslam::DynamicDistanceMap& m, const CellList& cells)
{
	for (const auto& [cx, cy] : cells) m.addObstacle(cx, cy);
	m.update();
}

/** The office's distance map, built once and shared (incremental benchmarks restore it). */
pmslam::DynamicDistanceMap& baseMap()
{
	static pmslam::DynamicDistanceMap m = [] {
		pmslam::DynamicDistanceMap d(kRes, kTrunc);
		fillMap(d, office().obstacles);
		return d;
	}();
	return m;
}

/** One scan's worth of changes around a scan origin. */
struct ChangeSet
{
	CellList added, removed;
	int ox, oy;	 // origin cell
};

/** ~3/4 of `target` cells appear as short L-shaped obstacles (furniture, people, a door
 * closing) in free space within 8 m of a room centre; ~1/4 disappear as runs of at most
 * 10 cells (0.5 m) of existing wall or furniture in the same area. */
ChangeSet makeChangeSet(const Floor& f, int target, unsigned seed)
{
	std::mt19937 rng(seed);
	ChangeSet cs;
	// Scan origin: the centre of a random room.
	std::uniform_int_distribution<int> band(0, 7), col(0, 23), row(0, 1);
	const double ox = 2.0 + 4.0 * col(rng) + 2.0, oy = 2.0 + 12.0 * band(rng) + 2.0 + 5.0 * row(rng) + 2.5;
	cs.ox = toCell(ox);
	cs.oy = toCell(oy);
	const int radius = toCell(8.0);
	std::uniform_int_distribution<int> off(-radius, radius), leg(8, 22), orient(0, 3);
	std::vector<uint8_t> taken(f.occ.size(), 0);

	const int wantAdded = target * 3 / 4, wantRemoved = target - wantAdded;
	for (int attempt = 0; int(cs.added.size()) < wantAdded && attempt < 100000; ++attempt)
	{
		const int cx = cs.ox + off(rng), cy = cs.oy + off(rng);
		const int lx = leg(rng), ly = leg(rng), o = orient(rng);
		const int sx = (o & 1) ? -1 : 1, sy = (o & 2) ? -1 : 1;
		CellList piece;
		for (int i = 0; i < lx; ++i) piece.emplace_back(cx + sx * i, cy);
		for (int i = 1; i < ly; ++i) piece.emplace_back(cx, cy + sy * i);
		const bool ok = std::all_of(piece.begin(), piece.end(), [&](const std::pair<int, int>& c) {
			if (!f.inside(c.first, c.second)) return false;
			// Keep one free cell around existing obstacles so the piece is "new" space.
			for (int ny = -1; ny <= 1; ++ny)
				for (int nx = -1; nx <= 1; ++nx)
					if (f.inside(c.first + nx, c.second + ny) && f.at(c.first + nx, c.second + ny)) return false;
			return !taken[std::size_t(c.second) * kSide + c.first];
		});
		if (!ok) continue;
		for (const auto& c : piece)
		{
			if (int(cs.added.size()) >= wantAdded) break;  // the last piece may be cut short
			taken[std::size_t(c.second) * kSide + c.first] = 1;
			cs.added.push_back(c);
		}
	}
	for (int attempt = 0; int(cs.removed.size()) < wantRemoved && attempt < 100000; ++attempt)
	{
		const int cx = cs.ox + off(rng), cy = cs.oy + off(rng);
		if (!f.inside(cx, cy) || !f.at(cx, cy) || taken[std::size_t(cy) * kSide + cx]) continue;
		const bool horizontal = f.inside(cx + 1, cy) && f.at(cx + 1, cy);
		const int want = std::min(10, wantRemoved - int(cs.removed.size()));
		for (int i = 0; i < want; ++i)
		{
			const int x = horizontal ? cx + i : cx, y = horizontal ? cy : cy + i;
			if (!f.inside(x, y) || !f.at(x, y) || taken[std::size_t(y) * kSide + x]) break;
			taken[std::size_t(y) * kSide + x] = 1;
			cs.removed.emplace_back(x, y);
		}
	}
	return cs;
}

std::size_t apply(pmslam::DynamicDistanceMap& m, const ChangeSet& cs)
{
	for (const auto& [cx, cy] : cs.added) m.addObstacle(cx, cy);
	for (const auto& [cx, cy] : cs.removed) m.removeObstacle(cx, cy);
	return m.update();
}

std::size_t undo(pmslam::DynamicDistanceMap& m, const ChangeSet& cs)
{
	for (const auto& [cx, cy] : cs.added) m.removeObstacle(cx, cy);
	for (const auto& [cx, cy] : cs.removed) m.addObstacle(cx, cy);
	return m.update();
}

/** Squared distances in a window (to check that apply + undo restores the map). */
std::vector<int> window(const pmslam::DynamicDistanceMap& m, int ox, int oy, int r)
{
	std::vector<int> out;
	out.reserve(std::size_t(2 * r + 1) * (2 * r + 1));
	for (int y = oy - r; y <= oy + r; ++y)
		for (int x = ox - r; x <= ox + r; ++x) out.push_back(m.squaredDistanceCells(x, y));
	return out;
}

constexpr int kChangeSets = 16;

void BM_IncrementalUpdate(benchmark::State& state)
{
	const int target = static_cast<int>(state.range(0));
	const Floor& f = office();
	auto& map = baseMap();
	std::vector<ChangeSet> sets;
	double cellsChanged = 0;
	for (int s = 0; s < kChangeSets; ++s)
	{
		sets.push_back(makeChangeSet(f, target, 1000u * unsigned(target) + unsigned(s)));
		cellsChanged += double(sets.back().added.size() + sets.back().removed.size());
	}
	// Correctness guard: every change set must be seen by the map, and undone exactly.
	double processed = 0;
	for (const auto& cs : sets)
	{
		const int r = toCell(8.0) + toCell(kTrunc) + 2;
		const auto before = window(map, cs.ox, cs.oy, r);
		processed += double(apply(map, cs));
		for (const auto& [cx, cy] : cs.added)
			if (map.squaredDistanceCells(cx, cy) != 0)
			{
				state.SkipWithError("added cell not at distance 0");
				return;
			}
		for (const auto& [cx, cy] : cs.removed)
			if (map.isObstacle(cx, cy))
			{
				state.SkipWithError("removed cell still an obstacle");
				return;
			}
		processed += double(undo(map, cs));
		if (window(map, cs.ox, cs.oy, r) != before)
		{
			state.SkipWithError("apply + undo did not restore the distance map");
			return;
		}
	}

	std::size_t i = 0;
	for (auto _ : state)
	{
		const ChangeSet& cs = sets[i++ % sets.size()];
		benchmark::DoNotOptimize(apply(map, cs));
		benchmark::DoNotOptimize(undo(map, cs));
	}
	state.SetItemsProcessed(int64_t(state.iterations()) * 2);  // updates per second
	state.counters["time_per_update"] =
		benchmark::Counter(2, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
	state.counters["cells_changed"] = cellsChanged / kChangeSets;
	state.counters["cells_processed"] = processed / (2.0 * kChangeSets);
}
BENCHMARK(BM_IncrementalUpdate)->ArgName("cells")->Arg(100)->Arg(200)->Arg(400)->Unit(benchmark::kMicrosecond);

void BM_FullRebuild(benchmark::State& state)
{
	const Floor& f = office();
	{
		// Correctness guard: a rebuild equals the shared map (which has been updated
		// incrementally and restored if the incremental benchmark ran first).
		pmslam::DynamicDistanceMap m(kRes, kTrunc);
		fillMap(m, f.obstacles);
		const auto& base = baseMap();
		for (int y = 0; y < kSide; y += 3)
			for (int x = 0; x < kSide; x += 3)
				if (m.squaredDistanceCells(x, y) != base.squaredDistanceCells(x, y))
				{
					state.SkipWithError("full rebuild differs from the incrementally maintained map");
					return;
				}
	}
	std::size_t processed = 0, blocks = 0, bytes = 0;
	for (auto _ : state)
	{
		pmslam::DynamicDistanceMap m(kRes, kTrunc);
		for (const auto& [cx, cy] : f.obstacles) m.addObstacle(cx, cy);
		processed = m.update();
		blocks = m.allocatedBlocks();
		bytes = m.memoryBytes();
		benchmark::DoNotOptimize(m.squaredDistanceCells(1000, 1000));
	}
	state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(f.obstacles.size()));	 // obstacle cells/s
	state.counters["time_per_update"] =
		benchmark::Counter(1, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
	state.counters["cells_changed"] = double(f.obstacles.size());
	state.counters["cells_processed"] = double(processed);
	state.counters["blocks"] = double(blocks);
	state.counters["MB"] = double(bytes) / (1024.0 * 1024.0);
}
BENCHMARK(BM_FullRebuild)->Unit(benchmark::kMillisecond);

template <bool kGradient>
void BM_DistanceAt(benchmark::State& state)
{
	const Floor& f = office();
	const auto& map = baseMap();
	constexpr std::size_t kQueries = 1 << 16;
	std::mt19937 rng(7);
	std::uniform_int_distribution<std::size_t> pick(0, f.obstacles.size() - 1);
	std::uniform_real_distribution<double> off(-kTrunc, kTrunc);
	std::vector<std::pair<double, double>> pts(kQueries);
	for (auto& p : pts)
	{
		const auto& c = f.obstacles[pick(rng)];
		p = {(c.first + 0.5) * kRes + off(rng), (c.second + 0.5) * kRes + off(rng)};
	}
	double meanDist = 0;
	for (const auto& [x, y] : pts) meanDist += map.distanceAt(x, y);
	for (auto _ : state)
	{
		float sum = 0;
		double gsum = 0;
		for (const auto& [x, y] : pts)
		{
			if constexpr (kGradient)
			{
				double gx, gy;
				sum += map.distanceAt(x, y, &gx, &gy);
				gsum += gx + gy;
			}
			else
				sum += map.distanceAt(x, y);
		}
		benchmark::DoNotOptimize(sum);
		benchmark::DoNotOptimize(gsum);
	}
	state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(kQueries));	// queries per second
	state.counters["time_per_query"] = benchmark::Counter(
		double(kQueries), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
	state.counters["mean_distance_m"] = meanDist / kQueries;
}
BENCHMARK_TEMPLATE(BM_DistanceAt, false)->Name("BM_DistanceAt")->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_DistanceAt, true)->Name("BM_DistanceAtGrad")->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv)
{
	benchmark::Initialize(&argc, argv);
	if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
	const Floor& f = office();
	benchmark::AddCustomContext("floor", "100 m x 100 m office, 0.05 m cells (2000 x 2000), truncation 0.5 m");
	benchmark::AddCustomContext("obstacle_cells", std::to_string(f.obstacles.size()));
	benchmark::RunSpecifiedBenchmarks();
	benchmark::Shutdown();
	return 0;
}
