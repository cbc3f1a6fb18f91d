/* pmslam — max-pooled pyramids of a per-cell likelihood, the bounds of a branch-and-bound search.
 *
 * Level 0 holds, for every cell of a window of the map, the likelihood that a scan point falls in
 * that cell: σ²/(σ²+d²), d the cell's truncated distance to the nearest obstacle (the score of
 * CorrelativeSearch and of Perfect Match), rescaled so that a cell at the truncation scores 0 and an
 * obstacle cell 255. Level h holds, for each cell (x, y), the maximum of level 0 over the 2^h × 2^h
 * cells [x, x+2^h) × [y, y+2^h) (Olson, "Real-time correlative scan matching", ICRA 2009; Hess et
 * al., "Real-time loop closure in 2D LIDAR SLAM", ICRA 2016). Summing level h over a scan's points
 * therefore bounds from above the score of every translation of that scan by 0..2^h-1 cells in x
 * and y: the max of a sum never exceeds the sum of the maxima.
 *
 * Why 8 bits: a 100 m × 100 m map at 5 cm has 4 M cells per level and the search wants 8-10
 * levels; bytes keep that at tens of MB (floats would be four times more) and keep more of the
 * pyramid in cache, where the search spends its time. Sums of bytes are exact integers, so the
 * search and a brute-force reference agree to the last bit and ties are well defined. The
 * quantisation step (1/255 of the peak likelihood) is far finer than what a one-cell shift
 * changes.
 *
 * Outside the window every cell scores 0 (as if beyond the truncation): each level is padded with
 * zeros so that a clamped look-up answers exactly the max over the window of 2^h cells.
 *
 * Frames: cell (i, j) covers [i·res, (i+1)·res) × [j·res, (j+1)·res) in the distance map's frame
 * (DynamicDistanceMap). A pyramid built from an MRPT grid has its own frame shifted by
 * frameOffset() (the grid's origin need not lie on a multiple of the resolution).
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPoint2D.h>
#include <pmslam/map/DynamicDistanceMap.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace pmslam
{
class LikelihoodPyramid
{
   public:
	struct Options
	{
		/** σ of the likelihood (m). About two cells: a lattice pose half a cell off the truth still
		 * scores most points high, while a pose a few cells off scores them low. */
		double sigma = 0.1;
		/** Levels 0..levels-1; the coarsest node spans 2^(levels-1) cells. More levels mean fewer
		 * root nodes for a whole-map search, at one more map-sized byte array each. */
		int levels = 9;
	};
	/** Inclusive cell bounds. */
	struct CellWindow
	{
		int minX = 0, minY = 0, maxX = -1, maxY = -1;
		int width() const { return maxX - minX + 1; }
		int height() const { return maxY - minY + 1; }
	};
	/** One level: cells [x0, x0+width) × [y0, y0+height), row-major. */
	struct Level
	{
		std::vector<uint8_t> cells;
		int x0 = 0, y0 = 0, width = 0, height = 0;
	};
	static constexpr int kMaxValue = 255;

	/** Over the cells of `window` of `map` (its distance layer). */
	LikelihoodPyramid(const DynamicDistanceMap& map, const CellWindow& window, const Options& options);
	LikelihoodPyramid(const DynamicDistanceMap& map, const CellWindow& window)
		: LikelihoodPyramid(map, window, Options())
	{
	}
	/** Over the whole allocated extent of `map` (an empty map gives an empty 1-cell window). */
	LikelihoodPyramid(const DynamicDistanceMap& map, const Options& options);
	explicit LikelihoodPyramid(const DynamicDistanceMap& map) : LikelihoodPyramid(map, Options()) {}
	/** For a stock MRPT grid: its distance layer is built as PerfectMatchAligner builds it (cells with
	 * occupancy above `occupiedThreshold` are obstacles, truncated at `maxDistance`), over the grid's
	 * cells; frameOffset() then maps the pyramid's frame to the grid's. */
	static LikelihoodPyramid fromGrid(const mrpt::maps::COccupancyGridMap2D& grid, double maxDistance,
									  double occupiedThreshold, const Options& options);
	static LikelihoodPyramid fromGrid(const mrpt::maps::COccupancyGridMap2D& grid, double maxDistance = 0.5,
									  double occupiedThreshold = 0.5)
	{
		return fromGrid(grid, maxDistance, occupiedThreshold, Options());
	}

	const Options& options() const { return m_options; }
	double resolution() const { return m_resolution; }
	int levels() const { return int(m_levels.size()); }
	const CellWindow& window() const { return m_window; }
	const Level& level(int h) const { return m_levels[std::size_t(h)]; }
	/** A point (x, y) of the pyramid's frame is (x + offset.x, y + offset.y) in the caller's map frame. */
	const mrpt::math::TPoint2D& frameOffset() const { return m_offset; }

	/** Level h at cell (cx, cy), any cell: the max of level 0 over [cx, cx+2^h) × [cy, cy+2^h). */
	int value(int h, int cx, int cy) const
	{
		const Level& l = m_levels[std::size_t(h)];
		const int x = std::clamp(cx - l.x0, 0, l.width - 1), y = std::clamp(cy - l.y0, 0, l.height - 1);
		return l.cells[std::size_t(y) * std::size_t(l.width) + std::size_t(x)];
	}
	/** A pyramid `factor` times coarser over the same area, for a coarse global lattice: its cell
	 * (I, J) covers fine cells [factor·I, factor·I + factor) (same frame, same offset), and its level
	 * 0 holds the max of this pyramid's level 0 over those cells widened by `dilation` fine cells on
	 * every side. Why widened: a coarse lattice pose lies up to half a coarse cell (plus what half a
	 * coarse rotation step moves a point) from the truth; with dilation ≥ that displacement, the true
	 * wall cell of every point stays inside the coarse cell it falls in, so the nearest coarse pose
	 * scores at least what the true pose scores on the fine field. Levels above are max pools as
	 * usual; `options` gives their count (σ is inherited: it only describes level 0's values). */
	LikelihoodPyramid coarsened(int factor, int dilation, int levels) const;

	/** The quantised likelihood of a distance d (m), as level 0 stores it. */
	int quantise(double d) const;

	/** Bytes held by the levels. */
	std::size_t memoryBytes() const;

   private:
	LikelihoodPyramid() = default;
	void buildLevel0(const DynamicDistanceMap& map);
	void buildLevel(int h);

	Options m_options;
	double m_resolution = 0.05, m_maxDistance = 0.5;
	CellWindow m_window;
	mrpt::math::TPoint2D m_offset{0, 0};
	std::vector<Level> m_levels;
};

}  // namespace pmslam
