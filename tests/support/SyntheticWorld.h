// Test support: a world of line segments, exact ray casting, and its rasterisation.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace pmslam::testing
{
struct Segment
{
	double x0, y0, x1, y1;
};

class SyntheticWorld
{
   public:
	std::vector<Segment> segments;

	void addBox(double x0, double y0, double x1, double y1)
	{
		segments.push_back({x0, y0, x1, y0});
		segments.push_back({x1, y0, x1, y1});
		segments.push_back({x1, y1, x0, y1});
		segments.push_back({x0, y1, x0, y0});
	}

	/** Distance along the ray from (ox, oy) with direction angle a to the first segment, or +inf. */
	double castRay(double ox, double oy, double a) const
	{
		const double dx = std::cos(a), dy = std::sin(a);
		double best = std::numeric_limits<double>::infinity();
		for (const auto& s : segments)
		{
			const double ex = s.x1 - s.x0, ey = s.y1 - s.y0;
			const double den = dx * ey - dy * ex;
			if (std::abs(den) < 1e-12) continue;
			const double wx = s.x0 - ox, wy = s.y0 - oy;
			const double t = (wx * ey - wy * ex) / den;	 // along the ray
			const double u = (wx * dy - wy * dx) / den;	 // along the segment
			if (t > 1e-9 && u >= 0 && u <= 1) best = std::min(best, t);
		}
		return best;
	}

	/** A scan of `beams` readings over `aperture` from robot pose `pose` (sensor at the robot centre
	 * unless sensorPose is given), with Gaussian range noise; misses become invalid at maxRange. */
	mrpt::obs::CObservation2DRangeScan scan(const mrpt::math::TPose2D& pose, std::size_t beams = 361,
											double aperture = M_PI, double maxRange = 30.0, double noise = 0.0,
											unsigned seed = 1,
											const mrpt::poses::CPose3D& sensorPose = mrpt::poses::CPose3D()) const
	{
		mrpt::obs::CObservation2DRangeScan obs;
		obs.aperture = static_cast<float>(aperture);
		obs.rightToLeft = true;
		obs.maxRange = static_cast<float>(maxRange);
		obs.sensorPose = sensorPose;
		obs.resizeScan(beams);
		std::mt19937 rng(seed);
		std::normal_distribution<double> n(0.0, noise);
		const mrpt::poses::CPose3D sensorInWorld = mrpt::poses::CPose3D(mrpt::poses::CPose2D(pose)) + sensorPose;
		for (std::size_t i = 0; i < beams; ++i)
		{
			// Cast in the world along the beam's direction from the sensor.
			const double a = obs.getScanAngle(i);
			double lx, ly, lz, tx, ty, tz;
			sensorInWorld.composePoint(std::cos(a), std::sin(a), 0.0, tx, ty, tz);
			lx = sensorInWorld.x();
			ly = sensorInWorld.y();
			lz = tz;
			(void)lz;
			const double r = castRay(lx, ly, std::atan2(ty - ly, tx - lx));
			if (std::isfinite(r) && r < maxRange)
			{
				obs.setScanRange(i, static_cast<float>(r + (noise > 0 ? n(rng) : 0.0)));
				obs.setScanRangeValidity(i, true);
			}
			else
			{
				obs.setScanRange(i, static_cast<float>(maxRange));
				obs.setScanRangeValidity(i, false);
			}
		}
		return obs;
	}

	/** Marks every cell touched by a segment as occupied (p_free = 0), the rest free. */
	void rasterise(mrpt::maps::COccupancyGridMap2D& grid) const
	{
		grid.fill(0.95f);
		const double step = grid.getResolution() / 20.0;
		for (const auto& s : segments)
		{
			const double len = std::hypot(s.x1 - s.x0, s.y1 - s.y0);
			const int n = static_cast<int>(len / step) + 1;
			for (int k = 0; k <= n; ++k)
			{
				const double t = double(k) / n;
				const int ix = grid.x2idx(s.x0 + t * (s.x1 - s.x0)), iy = grid.y2idx(s.y0 + t * (s.y1 - s.y0));
				if (ix >= 0 && iy >= 0 && ix < int(grid.getSizeX()) && iy < int(grid.getSizeY()))
					grid.setCell(ix, iy, 0.05f);
			}
		}
	}
};

/** A furnished room whose walls lie on cell centres of a 0.05 m grid (so rasterising is exact). */
inline SyntheticWorld furnishedRoom()
{
	SyntheticWorld w;
	w.addBox(-4.025, -3.025, 5.025, 3.025);
	w.addBox(1.025, 0.975, 1.975, 1.725);  // a cabinet
	w.addBox(-2.475, -1.975, -1.775, -1.275);  // a pillar
	w.segments.push_back({-4.025, 0.525, -2.025, 0.525});  // a half wall
	w.segments.push_back({3.025, -3.025, 3.025, -1.525});  // a partition
	return w;
}

/** Ray-casts `beams` beams over 180° in an occupancy grid and returns, in the robot frame, the
 * centre of the first cell with occupancy above 0.5 that each beam enters. A grid only knows its
 * obstacles up to a cell, and the centre is where the distance map puts them, so at the true pose
 * every point has distance zero: the cost minimum is exactly the truth. */
inline std::vector<mrpt::math::TPoint2Df> castCellCentresInGrid(const mrpt::maps::COccupancyGridMap2D& grid,
																 const mrpt::math::TPose2D& pose,
																 std::size_t beams = 361, double maxRange = 30.0)
{
	std::vector<mrpt::math::TPoint2Df> out;
	const double step = grid.getResolution() * 0.02, c = std::cos(pose.phi), s = std::sin(pose.phi);
	for (std::size_t i = 0; i < beams; ++i)
	{
		const double a = pose.phi - M_PI / 2 + M_PI * double(i) / double(beams - 1);
		const double dx = std::cos(a), dy = std::sin(a);
		for (double t = step; t < maxRange; t += step)
		{
			const int cx = grid.x2idx(pose.x + t * dx), cy = grid.y2idx(pose.y + t * dy);
			if (cx < 0 || cy < 0 || cx >= int(grid.getSizeX()) || cy >= int(grid.getSizeY())) break;
			if (grid.getCell(cx, cy) >= 0.5f) continue;
			const double wx = grid.idx2x(cx) - pose.x, wy = grid.idx2y(cy) - pose.y;
			out.emplace_back(static_cast<float>(c * wx + s * wy), static_cast<float>(-s * wx + c * wy));
			break;
		}
	}
	return out;
}

inline double angleDiff(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

}  // namespace pmslam::testing
