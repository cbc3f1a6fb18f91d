/* pmslam — a directory of square storage blocks over an unbounded lattice.
 *
 * The maps keep their cells in blocks of 32×32 allocated where something is first
 * written, so memory follows the area touched, not its bounding box. The directory
 * itself is a dense array of pointers over the blocks' bounding box (8 bytes per
 * 1024 cells: 3 MB for a square kilometre at 5 cm), so finding a block is two
 * subtractions and a load, which the matcher's inner loop can afford.
 *
 * Block coordinates are cell indices shifted right by kShift (floor division, also
 * for negative cells).
 */
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

namespace pmslam
{
/** The inclusive bounding box of the cells (or blocks) added to it. */
struct CellBounds
{
	int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
	bool any = false;
	void add(int x, int y)
	{
		x0 = any ? std::min(x0, x) : x;
		y0 = any ? std::min(y0, y) : y;
		x1 = any ? std::max(x1, x) : x;
		y1 = any ? std::max(y1, y) : y;
		any = true;
	}
	/** Copies the box out; false (nothing copied) when nothing was added. */
	bool get(int& ox0, int& oy0, int& ox1, int& oy1) const
	{
		if (any) ox0 = x0, oy0 = y0, ox1 = x1, oy1 = y1;
		return any;
	}
};

/** Grows the window [x0, x0+nx) × [y0, y0+ny) to hold (bx, by): by at least half its size on each side
 * exceeded, so a robot driving one way causes O(log) regrowths; an empty window (nx == 0) becomes the
 * 9 × 9 around it. The storage over the window is the caller's to lay out anew. */
inline void growWindowToHold(int& x0, int& y0, int& nx, int& ny, int bx, int by)
{
	if (nx == 0)
	{
		x0 = bx - 4;
		y0 = by - 4;
		nx = ny = 9;
		return;
	}
	int x1 = x0 + nx, y1 = y0 + ny;	 // [x0, x1)
	const int gx = std::max(4, nx / 2), gy = std::max(4, ny / 2);
	if (bx < x0) x0 = std::min(bx, x0 - gx);
	if (bx >= x1) x1 = std::max(bx + 1, x1 + gx);
	if (by < y0) y0 = std::min(by, y0 - gy);
	if (by >= y1) y1 = std::max(by + 1, y1 + gy);
	nx = x1 - x0;
	ny = y1 - y0;
}

/** Row-major storage over the window (x0, y0, nx, ny) moved into a new window that contains it. */
template <class T>
void moveToWindow(std::vector<T>& cells, int x0, int y0, int nx, int ny, int toX0, int toY0, int toNx, int toNy)
{
	std::vector<T> out(std::size_t(toNx) * toNy);
	for (int j = 0; j < ny; ++j)
		for (int i = 0; i < nx; ++i)
			out[std::size_t(j + y0 - toY0) * toNx + (i + x0 - toX0)] = std::move(cells[std::size_t(j) * nx + i]);
	cells.swap(out);
}

template <class Block>
class BlockDirectory
{
   public:
	static constexpr int kShift = 5;
	static constexpr int kSide = 1 << kShift;

	static int blockOf(int cell) { return cell >> kShift; }
	/** Index of cell (cx, cy) inside its block, row-major. */
	static int inBlock(int cx, int cy) { return ((cy & (kSide - 1)) << kShift) | (cx & (kSide - 1)); }

	/** The block (bx, by), or nullptr where none was allocated. */
	Block* find(int bx, int by) const
	{
		const unsigned i = unsigned(bx - m_x0), j = unsigned(by - m_y0);
		if (i >= unsigned(m_nx) || j >= unsigned(m_ny)) return nullptr;
		return m_dir[std::size_t(j) * m_nx + i].get();
	}

	/** The block (bx, by), made by make() (returning std::unique_ptr<Block>) if missing. */
	template <class Make>
	Block& obtain(int bx, int by, Make&& make)
	{
		if (unsigned(bx - m_x0) >= unsigned(m_nx) || unsigned(by - m_y0) >= unsigned(m_ny)) grow(bx, by);
		auto& slot = m_dir[std::size_t(by - m_y0) * m_nx + (bx - m_x0)];
		if (!slot)
		{
			slot = make();
			++m_count;
		}
		return *slot;
	}

	/** Calls f(bx, by, block) for every allocated block, row by row. */
	template <class F>
	void forEach(F&& f) const
	{
		for (int j = 0; j < m_ny; ++j)
			for (int i = 0; i < m_nx; ++i)
				if (const Block* b = m_dir[std::size_t(j) * m_nx + i].get()) f(i + m_x0, j + m_y0, *b);
	}
	template <class F>
	void forEach(F&& f)
	{
		for (int j = 0; j < m_ny; ++j)
			for (int i = 0; i < m_nx; ++i)
				if (Block* b = m_dir[std::size_t(j) * m_nx + i].get()) f(i + m_x0, j + m_y0, *b);
	}

	/** Inclusive block bounds of the allocated blocks; false when there are none. */
	bool bounds(int& bx0, int& by0, int& bx1, int& by1) const
	{
		CellBounds b;
		forEach([&b](int bx, int by, const Block&) { b.add(bx, by); });
		return b.get(bx0, by0, bx1, by1);
	}

	/** The same in cells: the inclusive cell bounds covered by the allocated blocks. */
	bool cellBounds(int& x0, int& y0, int& x1, int& y1) const
	{
		if (!bounds(x0, y0, x1, y1)) return false;
		x0 *= kSide;
		y0 *= kSide;
		x1 = (x1 + 1) * kSide - 1;
		y1 = (y1 + 1) * kSide - 1;
		return true;
	}

	/** Frees block (bx, by); false when none was allocated there. */
	bool release(int bx, int by)
	{
		const unsigned i = unsigned(bx - m_x0), j = unsigned(by - m_y0);
		if (i >= unsigned(m_nx) || j >= unsigned(m_ny)) return false;
		auto& slot = m_dir[std::size_t(j) * m_nx + i];
		if (!slot) return false;
		slot.reset();
		--m_count;
		return true;
	}

	std::size_t count() const { return m_count; }
	/** Bytes of the blocks and the directory. */
	std::size_t memoryBytes() const { return m_count * sizeof(Block) + m_dir.capacity() * sizeof(m_dir[0]); }
	void clear()
	{
		std::vector<std::unique_ptr<Block>>().swap(m_dir);  // gives the memory back
		m_x0 = m_y0 = m_nx = m_ny = 0;
		m_count = 0;
	}

   private:
	void grow(int bx, int by)
	{
		int x0 = m_x0, y0 = m_y0, nx = m_nx, ny = m_ny;
		growWindowToHold(x0, y0, nx, ny, bx, by);
		moveToWindow(m_dir, m_x0, m_y0, m_nx, m_ny, x0, y0, nx, ny);
		m_x0 = x0;
		m_y0 = y0;
		m_nx = nx;
		m_ny = ny;
	}

	std::vector<std::unique_ptr<Block>> m_dir;	// row-major over [m_x0, m_x0+m_nx) × [m_y0, m_y0+m_ny)
	int m_x0 = 0, m_y0 = 0, m_nx = 0, m_ny = 0;
	std::size_t m_count = 0;
};

}  // namespace pmslam
