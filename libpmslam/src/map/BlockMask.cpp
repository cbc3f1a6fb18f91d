/* pmslam — a set of map blocks (see BlockMask.h). */
#include <pmslam/map/BlockDirectory.h>
#include <pmslam/map/BlockMask.h>

#include <algorithm>
#include <stdexcept>

namespace pmslam
{
void BlockMask::add(int bx, int by)
{
	if (m_frozen) throw std::logic_error("BlockMask::add: after freeze()");
	if (unsigned(bx - m_x0) >= unsigned(m_nx) || unsigned(by - m_y0) >= unsigned(m_ny))
	{
		// A moved scan adds a block per 1.6 m of every beam: the bitmap, not a list of them, bounds the memory.
		int x0 = m_x0, y0 = m_y0, nx = m_nx, ny = m_ny;
		growWindowToHold(x0, y0, nx, ny, bx, by);
		moveToWindow(m_bits, m_x0, m_y0, m_nx, m_ny, x0, y0, nx, ny);
		m_x0 = x0, m_y0 = y0, m_nx = nx, m_ny = ny;
	}
	std::uint8_t& b = m_bits[std::size_t(by - m_y0) * m_nx + (bx - m_x0)];
	m_count += b == 0;
	b = 1;
}

void BlockMask::freeze()
{
	if (m_frozen) throw std::logic_error("BlockMask::freeze: called twice");
	m_frozen = true;
	m_sum.assign(std::size_t(m_nx + 1) * (m_ny + 1), 0);
	for (int j = 0; j < m_ny; ++j)
		for (int i = 0; i < m_nx; ++i)
			m_sum[std::size_t(j + 1) * (m_nx + 1) + (i + 1)] = m_bits[std::size_t(j) * m_nx + i] +
																m_sum[std::size_t(j) * (m_nx + 1) + (i + 1)] +
																m_sum[std::size_t(j + 1) * (m_nx + 1) + i] -
																m_sum[std::size_t(j) * (m_nx + 1) + i];
}

bool BlockMask::meets(int bx0, int by0, int bx1, int by1) const
{
	// The box clipped to the set's bounding box, then the summed-area table's four corners.
	const int i0 = std::max(bx0 - m_x0, 0), j0 = std::max(by0 - m_y0, 0);
	const int i1 = std::min(bx1 - m_x0, m_nx - 1), j1 = std::min(by1 - m_y0, m_ny - 1);
	if (!m_frozen) throw std::logic_error("BlockMask::meets: before freeze()");
	if (m_count == 0 || i0 > i1 || j0 > j1) return false;
	const auto s = [&](int i, int j) { return m_sum[std::size_t(j) * (m_nx + 1) + i]; };
	return s(i1 + 1, j1 + 1) - s(i0, j1 + 1) - s(i1 + 1, j0) + s(i0, j0) > 0;
}

}  // namespace pmslam
