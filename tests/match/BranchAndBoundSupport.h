// Test and benchmark support for BranchAndBoundSearch: worlds of segments rasterised on a
// DynamicDistanceMap, ray-cast scans, and the brute-force reference that scores every lattice pose.
#pragma once

#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/match/BranchAndBoundSearch.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "../support/SyntheticWorld.h"

namespace pmslam::testing
{
/** Marks every cell a segment passes through as an obstacle (sampled at a tenth of a cell). */
inline void rasterise(const SyntheticWorld& world, DynamicDistanceMap& map)
{
	const double step = map.resolution() / 10;
	for (const auto& s : world.segments)
	{
		const int n = int(std::hypot(s.x1 - s.x0, s.y1 - s.y0) / step) + 1;
		for (int k = 0; k <= n; ++k)
		{
			const double t = double(k) / n;
			map.addObstacle(map.worldToCell(s.x0 + t * (s.x1 - s.x0)), map.worldToCell(s.y0 + t * (s.y1 - s.y0)));
		}
	}
	map.update();
}

inline double distanceToSegment(const Segment& s, double x, double y)
{
	const double ex = s.x1 - s.x0, ey = s.y1 - s.y0, l2 = ex * ex + ey * ey;
	const double t = l2 > 0 ? std::clamp(((x - s.x0) * ex + (y - s.y0) * ey) / l2, 0.0, 1.0) : 0.0;
	return std::hypot(s.x0 + t * ex - x, s.y0 + t * ey - y);
}

inline double clearance(const SyntheticWorld& world, double x, double y)
{
	double d = 1e9;
	for (const auto& s : world.segments) d = std::min(d, distanceToSegment(s, x, y));
	return d;
}

/** Robot-frame points of `beams` rays over `fov` (centred ahead) cast from `pose`; misses dropped. */
inline std::vector<mrpt::math::TPoint2Df> castScan(const SyntheticWorld& world, const mrpt::math::TPose2D& pose,
												   int beams, double fov, double maxRange = 30.0)
{
	std::vector<mrpt::math::TPoint2Df> pts;
	for (int b = 0; b < beams; ++b)
	{
		// A full circle does not repeat its first beam.
		const double rel = fov >= 2 * M_PI - 1e-9 ? -M_PI + 2 * M_PI * b / beams : -fov / 2 + fov * b / (beams - 1);
		const double r = world.castRay(pose.x, pose.y, pose.phi + rel);
		if (std::isfinite(r) && r < maxRange)
			pts.emplace_back(float(r * std::cos(rel)), float(r * std::sin(rel)));
	}
	return pts;
}

/** A walled rectangle [0, w] × [0, h] with random partitions (with doorways) and random boxes:
 * irregular enough that a scan fits one place. Coordinates avoid cell boundaries only by chance. */
inline SyntheticWorld randomRooms(std::mt19937& rng, double w, double h, int partitions, int boxes)
{
	std::uniform_real_distribution<double> u(0, 1);
	SyntheticWorld world;
	world.addBox(0.02, 0.02, w - 0.02, h - 0.02);
	for (int p = 0; p < partitions; ++p)
	{
		// A wall across part of the room, with a 0.9 m doorway somewhere along it.
		const bool vertical = u(rng) < 0.5;
		const double along = (vertical ? w : h) * (0.25 + 0.5 * u(rng));
		const double len = (vertical ? h : w) * (0.4 + 0.4 * u(rng));
		const double start = u(rng) < 0.5 ? 0.02 : (vertical ? h : w) - 0.02 - len;
		const double door = start + 0.3 + (len - 1.2) * u(rng);
		auto add = [&](double a0, double a1) {
			if (a1 - a0 < 0.1) return;
			if (vertical)
				world.segments.push_back({along, a0, along, a1});
			else
				world.segments.push_back({a0, along, a1, along});
		};
		add(start, door);
		add(door + 0.9, start + len);
	}
	for (int b = 0; b < boxes; ++b)
	{
		const double x = 0.4 + (w - 1.6) * u(rng), y = 0.4 + (h - 1.6) * u(rng);
		world.addBox(x, y, x + 0.2 + 0.6 * u(rng), y + 0.2 + 0.6 * u(rng));
	}
	return world;
}

/** A pose at least `minClearance` from every wall, inside [margin, w-margin] × [margin, h-margin]. */
inline mrpt::math::TPose2D randomFreePose(std::mt19937& rng, const SyntheticWorld& world, double w, double h,
										  double minClearance = 0.4)
{
	std::uniform_real_distribution<double> ux(0.3, w - 0.3), uy(0.3, h - 0.3), ua(-M_PI, M_PI);
	for (;;)
	{
		const mrpt::math::TPose2D p(ux(rng), uy(rng), ua(rng));
		if (clearance(world, p.x, p.y) >= minClearance) return p;
	}
}

/** Every lattice pose's score, index (a·ny + j)·nx + i, by the definition of the score (level 0 of
 * the pyramid at each point's cell shifted by (i, j)); summed row by row, not as the search does. */
inline std::vector<int32_t> bruteForceScores(const BranchAndBoundSearch& search,
											 const BranchAndBoundSearch::Lattice& lattice, int firstAngle = 0,
											 int angleCount = -1)
{
	const auto& l0 = search.pyramid().level(0);
	const int nA = int(lattice.angles.size()), nx = lattice.nx, ny = lattice.ny;
	if (angleCount < 0) angleCount = nA - firstAngle;
	std::vector<int32_t> scores(std::size_t(angleCount) * nx * ny, 0);
	for (int a = firstAngle; a < firstAngle + angleCount; ++a)
	{
		int32_t* slice = &scores[std::size_t(a - firstAngle) * nx * ny];
		for (const auto& [cx, cy] : search.pointCells(lattice, a))
			for (int j = 0; j < ny; ++j)
			{
				const int y = cy + j - l0.y0;
				if (y < 0 || y >= l0.height) continue;	// outside the window: the point scores 0
				const uint8_t* row = &l0.cells[std::size_t(y) * l0.width];
				// Columns inside level 0; the rest score 0.
				const int i0 = std::max(0, l0.x0 - cx), i1 = std::min(nx, l0.x0 + l0.width - cx);
				int32_t* acc = slice + std::size_t(j) * nx;
				for (int i = i0; i < i1; ++i) acc[i] += row[cx + i - l0.x0];
			}
	}
	return scores;
}

struct BruteCandidate
{
	int a, i, j;
	int64_t score;
};

/** The K best distinct candidates by their definition: poses in (score, smaller index) order,
 * each kept when no pose of its neighbourhood ranks above it. */
inline std::vector<BruteCandidate> bruteForceCandidates(const std::vector<int32_t>& scores,
														const BranchAndBoundSearch::Lattice& lattice, std::size_t k)
{
	const int nA = int(lattice.angles.size()), nx = lattice.nx, ny = lattice.ny;
	std::vector<int64_t> order(scores.size());
	std::iota(order.begin(), order.end(), 0);
	auto above = [&](int64_t l, int64_t r) { return scores[l] != scores[r] ? scores[l] > scores[r] : l < r; };
	std::sort(order.begin(), order.end(), above);
	const int ar = lattice.angularRadius, lr = int(std::floor(lattice.linearRadius + 1e-9));
	const double r2 = lattice.linearRadius * lattice.linearRadius;
	std::vector<BruteCandidate> out;
	for (int64_t idx : order)
	{
		if (out.size() >= k) break;
		const int i = int(idx % nx), j = int(idx / nx % ny), a = int(idx / (int64_t(nx) * ny));
		bool peak = true;
		for (int da = -ar; da <= ar && peak; ++da)
		{
			int b = a + da;
			if (lattice.wrapsAround)
				b = (b % nA + nA) % nA;
			else if (b < 0 || b >= nA)
				continue;
			for (int dj = -lr; dj <= lr && peak; ++dj)
				for (int di = -lr; di <= lr && peak; ++di)
				{
					const int x = i + di, y = j + dj;
					if (x < 0 || y < 0 || x >= nx || y >= ny || di * di + dj * dj > r2) continue;
					if (above((int64_t(b) * ny + y) * nx + x, idx)) peak = false;
				}
		}
		if (peak) out.push_back({a, i, j, scores[std::size_t(idx)]});
	}
	return out;
}

}  // namespace pmslam::testing
