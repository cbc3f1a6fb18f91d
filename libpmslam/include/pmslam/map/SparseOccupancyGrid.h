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
#include <pmslam/map/GridLine.h>

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
	/** visitOnce() along the Bresenham line from (x, y) to (ex, ey), the end excluded (the cells
	 * forEachCellOnLine gives): f(cx, cy, cell) for each cell not yet visited in this pass. The
	 * insertion's inner loop (every cell a beam crosses), so the block is looked up once per block. */
	template <class F>
	void visitLineOnce(int x, int y, int ex, int ey, F&& f)
	{
		visitLineOnceWithin(x, y, ex, ey, [](int, int) { return true; }, f);
	}
	/** The same for the cells whose block (bx, by) keep() accepts: the others are neither visited nor
	 * allocated (a map re-inserted in part: OccupancyDistanceGridMap::insertScanWithin). */
	template <class Keep, class F>
	void visitLineOnceWithin(int x, int y, int ex, int ey, Keep&& keep, F&& f);

	/** The cells of block (bx, by), row-major (kSide × kSide), or nullptr where none is allocated. */
	const Cell* blockCells(int bx, int by) const;
	/** The same, allocated if needed. */
	Cell* obtainBlockCells(int bx, int by);
	/** Frees block (bx, by): its cells read 0 (never observed) again. */
	void releaseBlock(int bx, int by);

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
	SparseOccupancyBlock& blockFor(int cx, int cy);
	Cell* claim(SparseOccupancyBlock& b, int i);

	Blocks m_blocks;
	uint32_t m_pass = 0;
	// The block of the last cell asked for: a beam's cells mostly share one (blocks never move).
	SparseOccupancyBlock* m_last = nullptr;
	int m_lastBx = 0, m_lastBy = 0;
};

struct SparseOccupancyBlock
{
	static constexpr int N = SparseOccupancyGrid::Blocks::kSide * SparseOccupancyGrid::Blocks::kSide;
	SparseOccupancyGrid::Cell cells[N] = {};
	uint32_t pass = 0;	// the pass `visited` belongs to
	uint64_t visited[N / 64] = {};
};

// Inline: the scan insertion calls these for every cell a beam crosses.
inline SparseOccupancyGrid::Cell SparseOccupancyGrid::get(int cx, int cy) const
{
	const SparseOccupancyBlock* b = m_blocks.find(Blocks::blockOf(cx), Blocks::blockOf(cy));
	return b ? b->cells[Blocks::inBlock(cx, cy)] : Cell(0);
}

inline SparseOccupancyBlock& SparseOccupancyGrid::blockFor(int cx, int cy)
{
	const int bx = Blocks::blockOf(cx), by = Blocks::blockOf(cy);
	if (!m_last || bx != m_lastBx || by != m_lastBy)
	{
		m_last = &m_blocks.obtain(bx, by, [] { return std::make_unique<SparseOccupancyBlock>(); });
		m_lastBx = bx;
		m_lastBy = by;
		// Marks left by an earlier pass are cleared the first time this pass reaches the block
		// (beginPass() forgets the cached block, so every block comes through here).
		if (m_last->pass != m_pass)
		{
			for (auto& w : m_last->visited) w = 0;
			m_last->pass = m_pass;
		}
	}
	return *m_last;
}

inline SparseOccupancyGrid::Cell& SparseOccupancyGrid::at(int cx, int cy)
{
	return blockFor(cx, cy).cells[Blocks::inBlock(cx, cy)];
}

// The cell i of block b (from blockFor(), so its marks are this pass's) if not yet visited in
// this pass, marking it visited; else nullptr.
inline SparseOccupancyGrid::Cell* SparseOccupancyGrid::claim(SparseOccupancyBlock& b, int i)
{
	uint64_t& word = b.visited[i >> 6];
	const uint64_t bit = uint64_t(1) << (i & 63);
	if (word & bit) return nullptr;
	word |= bit;
	return &b.cells[i];
}

inline SparseOccupancyGrid::Cell* SparseOccupancyGrid::visitOnce(int cx, int cy)
{
	return claim(blockFor(cx, cy), Blocks::inBlock(cx, cy));
}

template <class Keep, class F>
void SparseOccupancyGrid::visitLineOnceWithin(int x, int y, int ex, int ey, Keep&& keep, F&& f)
{
	// The block is looked up (and keep() asked) only where the line crosses into another one.
	SparseOccupancyBlock* b = nullptr;
	bool kept = false, first = true;
	int bx = 0, by = 0;
	forEachCellOnLine(x, y, ex, ey, [&](int cx, int cy) {
		if (first || Blocks::blockOf(cx) != bx || Blocks::blockOf(cy) != by)
		{
			first = false;
			bx = Blocks::blockOf(cx);
			by = Blocks::blockOf(cy);
			kept = keep(bx, by);
			if (kept) b = &blockFor(cx, cy);
		}
		if (kept)
			if (Cell* c = claim(*b, Blocks::inBlock(cx, cy))) f(cx, cy, *c);
		return true;
	});
}

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
