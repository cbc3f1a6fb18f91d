/* pmslam — a set of map blocks: the part of a map that is being re-inserted.
 *
 * When the loop closure moves some keyframes, only the blocks (32×32 cells, the maps' storage
 * unit) that those keyframes' scans touched, where they were and where they go, change. This is
 * that set: a dense bitmap over its bounding box (a byte per 1024 cells), and once frozen a
 * summed-area table too, so "is this block in it" and "does this box of blocks meet it" (is a
 * scan whose reach is that box worth re-inserting) are O(1).
 *
 * Block coordinates: cell index >> BlockDirectory's kShift (floor division, also for negatives).
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pmslam
{
class BlockMask
{
   public:
	/** Adds block (bx, by); only before freeze(). */
	void add(int bx, int by);
	/** Builds the lookup tables; call once, after the last add(). */
	void freeze();

	bool empty() const { return m_count == 0; }
	/** Distinct blocks in the set. */
	std::size_t count() const { return m_count; }
	bool contains(int bx, int by) const
	{
		const unsigned i = unsigned(bx - m_x0), j = unsigned(by - m_y0);
		return i < unsigned(m_nx) && j < unsigned(m_ny) && m_bits[std::size_t(j) * m_nx + i];
	}
	/** True when a block of the inclusive box [bx0, bx1] × [by0, by1] is in the set. */
	bool meets(int bx0, int by0, int bx1, int by1) const;
	/** Calls f(bx, by) for every block of the set, row by row. */
	template <class F>
	void forEach(F&& f) const
	{
		for (int j = 0; j < m_ny; ++j)
			for (int i = 0; i < m_nx; ++i)
				if (m_bits[std::size_t(j) * m_nx + i]) f(m_x0 + i, m_y0 + j);
	}
	std::size_t memoryBytes() const { return m_bits.capacity() + m_sum.capacity() * sizeof(m_sum[0]); }

   private:
	bool m_frozen = false;
	std::vector<std::uint8_t> m_bits;	 // row-major over [m_x0, m_x0+m_nx) × [m_y0, m_y0+m_ny)
	std::vector<std::uint32_t> m_sum;  // summed-area table, (m_nx+1) × (m_ny+1)
	int m_x0 = 0, m_y0 = 0, m_nx = 0, m_ny = 0;
	std::size_t m_count = 0;
};

}  // namespace pmslam
