/* pmslam — do a scan's beams pass through the map's walls? (see WallCrossing.h) */
#include <pmslam/map/GridLine.h>
#include <pmslam/map/WallCrossing.h>

#include <cmath>

namespace pmslam
{
double crossedObstacleFraction(const DynamicDistanceMap& map, const ScanPoints& scan, const mrpt::math::TPose2D& pose,
							   double margin)
{
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	const double ox = pose.x + c * scan.sensorOrigin.x - s * scan.sensorOrigin.y;
	const double oy = pose.y + s * scan.sensorOrigin.x + c * scan.sensorOrigin.y;
	const int sx = map.worldToCell(ox), sy = map.worldToCell(oy);
	std::size_t counted = 0, crossed = 0;
	for (const auto& p : scan.hits)
	{
		const double ex = pose.x + c * p.x - s * p.y - ox, ey = pose.y + s * p.x + c * p.y - oy;
		const double length = std::hypot(ex, ey);
		if (length <= margin) continue;
		const double k = (length - margin) / length;
		++counted;
		bool hit = false;
		forEachCellOnLine(sx, sy, map.worldToCell(ox + k * ex), map.worldToCell(oy + k * ey), [&](int x, int y) {
			hit = map.isObstacle(x, y);
			return !hit;
		});
		crossed += hit;
	}
	return counted ? double(crossed) / double(counted) : 0.0;
}

}  // namespace pmslam
