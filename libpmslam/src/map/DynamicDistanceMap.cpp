/* pmslam — incremental brushfire distance map (see DynamicDistanceMap.h). */
#include <pmslam/map/DynamicDistanceMap.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pmslam
{
namespace
{
constexpr int kNeighbours[8][2] = {{-1, -1}, {0, -1}, {1, -1}, {-1, 0},
								   {1, 0},	 {-1, 1}, {0, 1},  {1, 1}};
}  // namespace

DynamicDistanceMap::DynamicDistanceMap(double resolution, double maxDistance)
	: m_resolution(resolution), m_maxDistance(maxDistance), m_invResolution(1.0 / resolution)
{
	if (!(resolution > 0) || !std::isfinite(resolution))
		throw std::invalid_argument("DynamicDistanceMap: resolution must be > 0, got " + std::to_string(resolution));
	if (!(maxDistance > 0) || maxDistance / resolution > 4096)
		throw std::invalid_argument(
			"DynamicDistanceMap: maxDistance must be in (0, 4096 cells], got " + std::to_string(maxDistance) + " m");
	const double r = maxDistance / resolution;
	// Relative slack: a float resolution (0.05f) must not turn 10 cells into 9.99999.
	m_maxSq = static_cast<int>(std::floor(r * r * (1.0 + 1e-6)));
	m_sqrtLut.resize(m_maxSq + 1);
	for (int i = 0; i <= m_maxSq; ++i)
		m_sqrtLut[i] = static_cast<float>(std::min(std::sqrt(double(i)) * resolution, maxDistance));
	m_buckets.resize(m_maxSq + 1);
	m_farBlock = std::make_unique<Block>(static_cast<float>(maxDistance));
}

DynamicDistanceMap::~DynamicDistanceMap() = default;
DynamicDistanceMap::DynamicDistanceMap(DynamicDistanceMap&&) noexcept = default;
DynamicDistanceMap& DynamicDistanceMap::operator=(DynamicDistanceMap&&) noexcept = default;

void DynamicDistanceMap::clear()
{
	m_dir.clear();
	m_bx0 = m_by0 = m_nbx = m_nby = 0;
	m_blockCount = 0;
	for (auto& b : m_buckets) b.clear();
	m_minBucket = 0;
	m_queued = 0;
}

int DynamicDistanceMap::worldToCell(double v) const
{
	return static_cast<int>(std::floor(v / m_resolution));
}

DynamicDistanceMap::Ref DynamicDistanceMap::ref(int cx, int cy) const
{
	const int bx = blockOf(cx) - m_bx0, by = blockOf(cy) - m_by0;
	if (bx < 0 || by < 0 || bx >= m_nbx || by >= m_nby) return {};
	return Ref{m_dir[std::size_t(by) * m_nbx + bx].get(), inBlock(cx, cy)};
}

bool DynamicDistanceMap::isObstacle(int cx, int cy) const
{
	const Ref r = ref(cx, cy);
	return r && (r.flags() & kOccupied);
}

void DynamicDistanceMap::growDirectory(int bx, int by)
{
	if (m_nbx == 0)
	{
		// First block: start with a small window around it.
		m_bx0 = bx - 4;
		m_by0 = by - 4;
		m_nbx = m_nby = 9;
		m_dir.resize(std::size_t(m_nbx) * m_nby);
		return;
	}
	int x0 = m_bx0, y0 = m_by0, x1 = m_bx0 + m_nbx, y1 = m_by0 + m_nby;	 // [x0,x1)
	// Grow by at least half the current size on the side that is exceeded,
	// so a robot driving in one direction causes O(log) reallocations.
	if (bx < x0) x0 = std::min(bx, x0 - std::max(4, m_nbx / 2));
	if (bx >= x1) x1 = std::max(bx + 1, x1 + std::max(4, m_nbx / 2));
	if (by < y0) y0 = std::min(by, y0 - std::max(4, m_nby / 2));
	if (by >= y1) y1 = std::max(by + 1, y1 + std::max(4, m_nby / 2));
	const int nbx = x1 - x0, nby = y1 - y0;
	std::vector<std::unique_ptr<Block>> dir(std::size_t(nbx) * nby);
	for (int j = 0; j < m_nby; ++j)
		for (int i = 0; i < m_nbx; ++i)
			dir[std::size_t(j + m_by0 - y0) * nbx + (i + m_bx0 - x0)] = std::move(m_dir[std::size_t(j) * m_nbx + i]);
	m_dir.swap(dir);
	m_bx0 = x0;
	m_by0 = y0;
	m_nbx = nbx;
	m_nby = nby;
}

DynamicDistanceMap::Ref DynamicDistanceMap::refAlloc(int cx, int cy)
{
	int bx = blockOf(cx) - m_bx0, by = blockOf(cy) - m_by0;
	if (bx < 0 || by < 0 || bx >= m_nbx || by >= m_nby)
	{
		growDirectory(blockOf(cx), blockOf(cy));
		bx = blockOf(cx) - m_bx0;
		by = blockOf(cy) - m_by0;
	}
	auto& slot = m_dir[std::size_t(by) * m_nbx + bx];
	if (!slot)
	{
		slot = std::make_unique<Block>(static_cast<float>(m_maxDistance));
		++m_blockCount;
	}
	return Ref{slot.get(), inBlock(cx, cy)};
}

void DynamicDistanceMap::push(int key, int cx, int cy)
{
	key = std::clamp(key, 0, m_maxSq);
	m_buckets[key].emplace_back(cx, cy);
	if (m_queued == 0 || key < m_minBucket) m_minBucket = key;
	++m_queued;
}

void DynamicDistanceMap::addObstacle(int cx, int cy)
{
	const Ref r = refAlloc(cx, cy);
	if (r.flags() & kOccupied) return;
	r.flags() |= kOccupied;
	assign(r, 0, 0, 0);
	push(0, cx, cy);
}

void DynamicDistanceMap::removeObstacle(int cx, int cy)
{
	const Ref r = ref(cx, cy);
	if (!r || !(r.flags() & kOccupied)) return;
	r.flags() = static_cast<uint8_t>((r.flags() & ~kOccupied) | kToRaise);
	assign(r, kFar, 0, 0);
	push(0, cx, cy);
}


void DynamicDistanceMap::raise(int cx, int cy)
{
	for (const auto& d : kNeighbours)
	{
		const int nx = cx + d[0], ny = cy + d[1];
		const Ref n = ref(nx, ny);
		if (!n || n.cell().sqd == kFar || (n.flags() & kToRaise)) continue;
		const int key = n.cell().sqd;
		if (!isObstacle(nx + n.cell().ox, ny + n.cell().oy))
		{
			// n pointed at a vanished obstacle: invalidate it and carry the raise on.
			assign(n, kFar, 0, 0);
			n.flags() |= kToRaise;
		}
		// Valid neighbours are re-queued so that their lower wave refills the raised area.
		push(key, nx, ny);
	}
	if (const Ref r = ref(cx, cy)) r.flags() &= static_cast<uint8_t>(~kToRaise);
}

void DynamicDistanceMap::lower(int cx, int cy, const Cell& c)
{
	const int obx = cx + c.ox, oby = cy + c.oy;
	for (const auto& d : kNeighbours)
	{
		const int nx = cx + d[0], ny = cy + d[1];
		const int dx = obx - nx, dy = oby - ny;
		const int sq = dx * dx + dy * dy;
		if (sq > m_maxSq) continue;
		const Ref n = refAlloc(nx, ny);
		if ((n.flags() & kToRaise) || sq >= n.cell().sqd) continue;
		assign(n, sq, dx, dy);
		push(sq, nx, ny);
	}
}

std::size_t DynamicDistanceMap::update()
{
	std::size_t processed = 0;
	while (m_queued > 0)
	{
		while (m_buckets[m_minBucket].empty()) ++m_minBucket;
		auto& bucket = m_buckets[m_minBucket];
		const auto [cx, cy] = bucket.back();
		bucket.pop_back();
		--m_queued;
		++processed;

		const Ref r = ref(cx, cy);
		if (!r) continue;
		if (r.flags() & kToRaise)
			raise(cx, cy);
		else if (r.cell().sqd != kFar && isObstacle(cx + r.cell().ox, cy + r.cell().oy))
		{
			const Cell copy = r.cell();	 // lower() may reallocate the directory, not the block
			lower(cx, cy, copy);
		}
		// Buckets only hold keys >= m_minBucket unless push() lowered it; push() keeps it exact.
	}
	m_minBucket = 0;
	return processed;
}

int DynamicDistanceMap::squaredDistanceCells(int cx, int cy) const
{
	const Ref r = ref(cx, cy);
	if (!r || r.cell().sqd == kFar) return -1;
	return r.cell().sqd;
}

float DynamicDistanceMap::cellDistance(int cx, int cy) const
{
	const Ref r = ref(cx, cy);
	return r ? r.block->dist[r.i] : static_cast<float>(m_maxDistance);
}

std::size_t DynamicDistanceMap::memoryBytes() const
{
	std::size_t bytes = (m_blockCount + 1) * sizeof(Block) + m_dir.capacity() * sizeof(m_dir[0]) +
						m_sqrtLut.capacity() * sizeof(float);
	for (const auto& b : m_buckets) bytes += b.capacity() * sizeof(b[0]) + sizeof(b);
	return bytes;
}

bool DynamicDistanceMap::touchedBounds(int& minX, int& minY, int& maxX, int& maxY) const
{
	bool any = false;
	for (int j = 0; j < m_nby; ++j)
		for (int i = 0; i < m_nbx; ++i)
		{
			if (!m_dir[std::size_t(j) * m_nbx + i]) continue;
			const int x0 = (i + m_bx0) * kBlockSide, y0 = (j + m_by0) * kBlockSide;
			if (!any)
			{
				minX = x0;
				minY = y0;
				maxX = x0 + kBlockSide - 1;
				maxY = y0 + kBlockSide - 1;
				any = true;
			}
			minX = std::min(minX, x0);
			minY = std::min(minY, y0);
			maxX = std::max(maxX, x0 + kBlockSide - 1);
			maxY = std::max(maxY, y0 + kBlockSide - 1);
		}
	return any;
}

}  // namespace pmslam
