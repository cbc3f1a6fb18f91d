// Test support: a large loop of corridors for loop closure, and a drive around it.
//
// A ring of 3 m corridors around a 100 m x 80 m block. The walls carry recesses (doorways) at
// irregular spacing, dense in the first two corridors and sparse (20-30 m apart) in the last
// two, where a 15 m laser often sees two plain walls only: there the front-end slides along
// the corridor and its drift grows to metres over a lap, which only a loop closure removes.
#pragma once

#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <random>
#include <vector>

#include "SyntheticWorld.h"

namespace pmslam::testing
{
constexpr double kRingW = 100, kRingH = 80, kRingCorridor = 3;

/** A wall from (x0,y0) to (x1,y1) whose outside is on its right, with features 0.9 m wide at
 * `at` (m along it): recesses 0.6 m deep and pilasters 0.3 m proud, in turn. */
inline void wallWithRecesses(SyntheticWorld& w, double x0, double y0, double x1, double y1, const std::vector<double>& at)
{
	const double len = std::hypot(x1 - x0, y1 - y0), ux = (x1 - x0) / len, uy = (y1 - y0) / len;
	const double nx = uy, ny = -ux;	 // the right of the direction: into the wall
	double s = 0;
	int n = 0;
	auto p = [&](double a, double d) { return std::pair<double, double>(x0 + ux * a + nx * d, y0 + uy * a + ny * d); };
	for (double a : at)
	{
		// Recesses and pilasters in turn: a pilaster's faces across the corridor are seen from afar.
		const double depth = n++ % 2 ? -0.3 : 0.6;
		const auto [ax, ay] = p(s, 0);
		const auto [bx, by] = p(a, 0);
		w.segments.push_back({ax, ay, bx, by});
		const auto [cx, cy] = p(a, depth);
		const auto [dx, dy] = p(a + 0.9, depth);
		const auto [ex, ey] = p(a + 0.9, 0);
		w.segments.push_back({bx, by, cx, cy});
		w.segments.push_back({cx, cy, dx, dy});
		w.segments.push_back({dx, dy, ex, ey});
		s = a + 0.9;
	}
	const auto [ax, ay] = p(s, 0);
	const auto [bx, by] = p(len, 0);
	w.segments.push_back({ax, ay, bx, by});
}

/** Recess positions from `from` to `to` with gaps in [minGap, maxGap] (deterministic). */
inline std::vector<double> recessesAlong(double from, double to, double minGap, double maxGap, unsigned seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> gap(minGap, maxGap);
	std::vector<double> out;
	for (double a = from + gap(rng); a < to - 1.5; a += gap(rng)) out.push_back(a);
	return out;
}

/** The ring: outer wall (0,0)-(W,H), inner block (c, c)-(W-c, H-c), counter-clockwise lap
 * along y = c/2 (east), x = W - c/2 (north), y = H - c/2 (west), x = c/2 (south). */
inline SyntheticWorld ringWorld()
{
	SyntheticWorld w;
	const double W = kRingW, H = kRingH, c = kRingCorridor;
	// Dense features along the south and east corridors, sparse along north and west. Outer
	// walls counter-clockwise (outside on the right), the inner block's clockwise (block on the right).
	wallWithRecesses(w, 0, 0, W, 0, recessesAlong(0, W, 3, 8, 1));	// south, outer
	wallWithRecesses(w, W - c, c, c, c, recessesAlong(0, W - 2 * c, 3, 8, 2));  // south, inner
	wallWithRecesses(w, W, 0, W, H, recessesAlong(0, H, 3, 8, 3));	// east, outer
	wallWithRecesses(w, W - c, H - c, W - c, c, recessesAlong(0, H - 2 * c, 3, 8, 4));  // east, inner
	wallWithRecesses(w, W, H, 0, H, recessesAlong(0, W, 15, 25, 5));  // north, outer
	wallWithRecesses(w, c, H - c, W - c, H - c, recessesAlong(0, W - 2 * c, 15, 25, 6));	// north, inner
	wallWithRecesses(w, 0, H, 0, 0, recessesAlong(0, H, 15, 25, 7));  // west, outer
	wallWithRecesses(w, c, c, c, H - c, recessesAlong(0, H - 2 * c, 15, 25, 8));  // west, inner
	return w;
}

/** `laps` laps of the ring's centre line, counter-clockwise from (c/2 + 2, c/2) heading east,
 * a pose every `step` metres, quarter-circle corners of radius c/2 - 0.3, a gentle weave. */
inline std::vector<mrpt::math::TPose2D> ringPath(double laps, double step)
{
	const double W = kRingW, H = kRingH, h = kRingCorridor / 2, r = h - 0.3;
	// Corner centres (the path turns left around each) and straight legs between them.
	const double cx[4] = {W - h - r, W - h - r, h + r, h + r}, cy[4] = {h + r, H - h - r, H - h - r, h + r};
	std::vector<mrpt::math::TPose2D> out;
	const double legLen[4] = {cx[0] - (h + r), cy[1] - cy[0], cx[1] - cx[2], cy[2] - cy[3]};
	const double arc = M_PI / 2 * r;
	double lapLen = 0;
	for (double l : legLen) lapLen += l + arc;
	const double total = laps * lapLen;
	for (double s = 0; s <= total; s += step)
	{
		double a = std::fmod(s, lapLen);
		mrpt::math::TPose2D p;
		for (int k = 0; k < 4; ++k)
		{
			const double heading = k * M_PI / 2;
			const int prev = (k + 3) % 4;
			if (a <= legLen[k])
			{
				// Leg k: from the end of corner prev's arc to corner k, along `heading`.
				const double sx = cx[prev] + r * std::cos(heading - M_PI / 2), sy = cy[prev] + r * std::sin(heading - M_PI / 2);
				// A weave that vanishes at both ends of the leg.
				const double f = 2 * M_PI * std::max(1.0, std::round(legLen[k] / 40)) / legLen[k];
				const double weave = 0.25 * std::sin(f * a);
				p = {sx + a * std::cos(heading) - weave * std::sin(heading), sy + a * std::sin(heading) + weave * std::cos(heading),
					 heading + std::atan(0.25 * f * std::cos(f * a))};
				break;
			}
			a -= legLen[k];
			if (a <= arc)
			{
				const double t = heading - M_PI / 2 + a / r;
				p = {cx[k] + r * std::cos(t), cy[k] + r * std::sin(t), t + M_PI / 2};
				break;
			}
			a -= arc;
		}
		p.phi = std::remainder(p.phi, 2 * M_PI);
		out.push_back(p);
	}
	return out;
}

/** Segments within `range` of (x, y): ray casting a big world scan by scan. */
inline SyntheticWorld nearbyPart(const SyntheticWorld& w, double x, double y, double range)
{
	SyntheticWorld out;
	for (const auto& s : w.segments)
	{
		const double minX = std::min(s.x0, s.x1) - range, maxX = std::max(s.x0, s.x1) + range;
		const double minY = std::min(s.y0, s.y1) - range, maxY = std::max(s.y0, s.y1) + range;
		if (x >= minX && x <= maxX && y >= minY && y <= maxY) out.segments.push_back(s);
	}
	return out;
}

}  // namespace pmslam::testing
