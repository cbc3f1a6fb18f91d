/* pmslam — occupancy cells stored only where scans have touched.
 *
 * The cells of the live map, in MRPT's own units (the log-odds of a cell being free,
 * 1/16 natural-log units in an int8, 0 = never observed: COccupancyGridMap2D::cellType),
 * on the same unbounded lattice as the distance layer: cell (i, j) covers
 * [i·res, (i+1)·res) × [j·res, (j+1)·res). Storage comes in 32×32 blocks allocated on
 * first touch, so a robot driving a long diagonal corridor pays for the corridor, not
 * for the square around it. A block costs 1.2 KB (1 byte per cell plus one bit per cell
 * for "already updated in this scan").
 */
#pragma once

#include <pmslam/map/BlockDirectory.h>

#include <cstddef>
#include <cstdint>
#include <memory>

namespace pmslam
{
class SparseOccupancyGrid
{
   public:
	using Cell = int8_t;  // mrpt::maps::COccupancyGridMap2D::cellType with MRPT's 8-bit cells
	using Blocks = BlockDirectory<struct SparseOccupancyBlock>;

	/** The cell's value; 0 (never observed) where no storage exists. */
	Cell get(int cx, int cy) const;
	/** The cell's storage, allocated if needed. */
	Cell& at(int cx, int cy);

	/** Starts a new pass (one scan): visitOnce() then answers each cell once. */
	void beginPass();
	/** The cell's storage the first time it is asked for in the current pass, else nullptr. */
	Cell* visitOnce(int cx, int cy);

	/** Inclusive cell bounds of the allocated blocks (false when empty). */
	bool allocatedBounds(int& x0, int& y0, int& x1, int& y1) const;
	/** Inclusive bounds of the cells holding any evidence (false when none): reads only allocated blocks. */
	bool evidenceBounds(int& x0, int& y0, int& x1, int& y1) const;
	/** Cells cx0 .. cx0+n-1 of row cy into out (0 where never observed). */
	void readRow(int cy, int cx0, int n, Cell* out) const;
	/** Calls f(cx, cy, value) for every cell of every allocated block whose value is not 0. */
	template <class F>
	void forEachObserved(F&& f) const;

	void clear();
	/** How many cells hold evidence (the area mapped, in cells). */
	std::size_t observedCells() const;
	std::size_t blockCount() const;
	std::size_t memoryBytes() const;

	SparseOccupancyGrid();
	~SparseOccupancyGrid();
	SparseOccupancyGrid(SparseOccupancyGrid&&) noexcept;
	SparseOccupancyGrid& operator=(SparseOccupancyGrid&&) noexcept;

   private:
	Blocks m_blocks;
	uint32_t m_pass = 0;
};

struct SparseOccupancyBlock
{
	static constexpr int N = SparseOccupancyGrid::Blocks::kSide * SparseOccupancyGrid::Blocks::kSide;
	SparseOccupancyGrid::Cell cells[N] = {};
	uint32_t pass = 0;	// the pass `visited` belongs to
	uint64_t visited[N / 64] = {};
};

template <class F>
void SparseOccupancyGrid::forEachObserved(F&& f) const
{
	constexpr int S = Blocks::kSide;
	m_blocks.forEach([&](int bx, int by, const SparseOccupancyBlock& b) {
		for (int i = 0; i < SparseOccupancyBlock::N; ++i)
			if (b.cells[i] != 0) f(bx * S + (i & (S - 1)), by * S + (i >> Blocks::kShift), b.cells[i]);
	});
}

}  // namespace pmslam
