/* pmslam — the cells of a straight line on the grid (Bresenham).
 *
 * Used where a beam carves free space through the map and where a picture of the map
 * draws the trajectory: integer steps only, so the same cells whatever the origin.
 */
#pragma once

#include <cstdlib>

namespace pmslam
{
/** Calls f(x, y) for the cells of the line from (x, y) to (ex, ey): the start included, the end
 * excluded (then f(ex, ey) is the caller's to make). Stops early when f returns false. */
template <class F>
void forEachCellOnLine(int x, int y, int ex, int ey, F&& f)
{
	const int dx = std::abs(ex - x), dy = -std::abs(ey - y);
	const int stepX = x < ex ? 1 : -1, stepY = y < ey ? 1 : -1;
	int err = dx + dy;
	while (x != ex || y != ey)
	{
		if (!f(x, y)) return;
		const int e2 = 2 * err;
		if (e2 >= dy)
		{
			err += dy;
			x += stepX;
		}
		if (e2 <= dx)
		{
			err += dx;
			y += stepY;
		}
	}
}

}  // namespace pmslam
