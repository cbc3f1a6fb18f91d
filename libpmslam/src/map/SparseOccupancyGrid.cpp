/* pmslam — occupancy cells stored only where scans have touched (see SparseOccupancyGrid.h). */
#include <pmslam/map/SparseOccupancyGrid.h>

#include <algorithm>
#include <cstring>
#include <utility>

namespace pmslam
{

SparseOccupancyGrid::SparseOccupancyGrid() = default;
SparseOccupancyGrid::~SparseOccupancyGrid() = default;
SparseOccupancyGrid::SparseOccupancyGrid(SparseOccupancyGrid&& o) noexcept { *this = std::move(o); }
SparseOccupancyGrid& SparseOccupancyGrid::operator=(SparseOccupancyGrid&& o) noexcept
{
	if (this == &o) return *this;
	m_blocks = std::move(o.m_blocks);
	m_pass = o.m_pass;
	m_last = o.m_last;	// the blocks moved with the directory; the source keeps none
	m_lastBx = o.m_lastBx;
	m_lastBy = o.m_lastBy;
	o.m_blocks.clear();
	o.m_last = nullptr;
	return *this;
}

void SparseOccupancyGrid::beginPass()
{
	m_last = nullptr;  // its marks may be the last pass's
	if (++m_pass == 0)
	{
		// 2^32 scans later: forget the old marks rather than confuse them with new ones.
		m_blocks.forEach([](int, int, SparseOccupancyBlock& b) { b.pass = 0; });
		m_pass = 1;
	}
}

bool SparseOccupancyGrid::allocatedBounds(int& x0, int& y0, int& x1, int& y1) const
{
	return m_blocks.cellBounds(x0, y0, x1, y1);
}

bool SparseOccupancyGrid::evidenceBounds(int& x0, int& y0, int& x1, int& y1) const
{
	CellBounds b;
	forEachObserved([&b](int cx, int cy, Cell) { b.add(cx, cy); });
	return b.get(x0, y0, x1, y1);
}

void SparseOccupancyGrid::readRow(int cy, int cx0, int n, Cell* out) const
{
	constexpr int S = Blocks::kSide;
	const int by = Blocks::blockOf(cy), row = (cy & (S - 1)) << Blocks::kShift;
	for (int i = 0; i < n;)
	{
		const int cx = cx0 + i;
		const int run = std::min(n - i, S - (cx & (S - 1)));  // up to the end of this block
		if (const SparseOccupancyBlock* b = m_blocks.find(Blocks::blockOf(cx), by))
			std::memcpy(out + i, b->cells + row + (cx & (S - 1)), std::size_t(run));
		else
			std::memset(out + i, 0, std::size_t(run));
		i += run;
	}
}

void SparseOccupancyGrid::clear()
{
	m_blocks.clear();
	m_pass = 0;
	m_last = nullptr;
}

std::size_t SparseOccupancyGrid::observedCells() const
{
	std::size_t n = 0;
	forEachObserved([&n](int, int, Cell) { ++n; });
	return n;
}

const SparseOccupancyGrid::Cell* SparseOccupancyGrid::blockCells(int bx, int by) const
{
	const SparseOccupancyBlock* b = m_blocks.find(bx, by);
	return b ? b->cells : nullptr;
}

SparseOccupancyGrid::Cell* SparseOccupancyGrid::obtainBlockCells(int bx, int by)
{
	return blockFor(bx * Blocks::kSide, by * Blocks::kSide).cells;
}

void SparseOccupancyGrid::releaseBlock(int bx, int by)
{
	if (m_last == m_blocks.find(bx, by)) m_last = nullptr;
	m_blocks.release(bx, by);
}

std::size_t SparseOccupancyGrid::blockCount() const { return m_blocks.count(); }
std::size_t SparseOccupancyGrid::memoryBytes() const { return m_blocks.memoryBytes(); }

}  // namespace pmslam
