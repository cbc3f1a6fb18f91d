/* pmslam — incremental brushfire distance map (see DynamicDistanceMap.h). */
#include <pmslam/DynamicDistanceMap.h>

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

DynamicDistanceMap::Cell* DynamicDistanceMap::cellPtr(int cx, int cy, uint8_t** flags)
{
	const int bx = blockOf(cx) - m_bx0, by = blockOf(cy) - m_by0;
	if (bx < 0 || by < 0 || bx >= m_nbx || by >= m_nby) return nullptr;
	Block* b = m_dir[std::size_t(by) * m_nbx + bx].get();
	if (!b) return nullptr;
	const int i = inBlock(cx, cy);
	if (flags) *flags = &b->flags[i];
	return &b->cells[i];
}

const DynamicDistanceMap::Cell* DynamicDistanceMap::cellPtr(int cx, int cy, const uint8_t** flags) const
{
	const int bx = blockOf(cx) - m_bx0, by = blockOf(cy) - m_by0;
	if (bx < 0 || by < 0 || bx >= m_nbx || by >= m_nby) return nullptr;
	const Block* b = m_dir[std::size_t(by) * m_nbx + bx].get();
	if (!b) return nullptr;
	const int i = inBlock(cx, cy);
	if (flags) *flags = &b->flags[i];
	return &b->cells[i];
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

DynamicDistanceMap::Cell* DynamicDistanceMap::cellPtrAlloc(int cx, int cy, uint8_t** flags)
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
		slot = std::make_unique<Block>();
		++m_blockCount;
	}
	const int i = inBlock(cx, cy);
	if (flags) *flags = &slot->flags[i];
	return &slot->cells[i];
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
	uint8_t* f = nullptr;
	Cell* c = cellPtrAlloc(cx, cy, &f);
	if (*f & kOccupied) return;
	*f |= kOccupied;
	c->sqd = 0;
	c->ox = c->oy = 0;
	push(0, cx, cy);
}

void DynamicDistanceMap::removeObstacle(int cx, int cy)
{
	uint8_t* f = nullptr;
	Cell* c = cellPtr(cx, cy, &f);
	if (!c || !(*f & kOccupied)) return;
	*f = static_cast<uint8_t>((*f & ~kOccupied) | kToRaise);
	c->sqd = kFar;
	c->ox = c->oy = 0;
	push(0, cx, cy);
}

bool DynamicDistanceMap::isObstacle(int cx, int cy) const
{
	const uint8_t* f = nullptr;
	const Cell* c = cellPtr(cx, cy, &f);
	return c && (*f & kOccupied);
}

void DynamicDistanceMap::raise(int cx, int cy)
{
	for (const auto& d : kNeighbours)
	{
		const int nx = cx + d[0], ny = cy + d[1];
		uint8_t* nf = nullptr;
		Cell* n = cellPtr(nx, ny, &nf);
		if (!n || n->sqd == kFar || (*nf & kToRaise)) continue;
		const int key = n->sqd;
		if (!isObstacle(nx + n->ox, ny + n->oy))
		{
			// n pointed at a vanished obstacle: invalidate it and carry the raise on.
			n->sqd = kFar;
			n->ox = n->oy = 0;
			*nf |= kToRaise;
		}
		// Valid neighbours are re-queued so that their lower wave refills the raised area.
		push(key, nx, ny);
	}
	uint8_t* f = nullptr;
	if (cellPtr(cx, cy, &f)) *f &= static_cast<uint8_t>(~kToRaise);
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
		uint8_t* nf = nullptr;
		Cell* n = cellPtrAlloc(nx, ny, &nf);
		if ((*nf & kToRaise) || sq >= n->sqd) continue;
		n->sqd = sq;
		n->ox = static_cast<int16_t>(dx);
		n->oy = static_cast<int16_t>(dy);
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

		uint8_t* f = nullptr;
		Cell* c = cellPtr(cx, cy, &f);
		if (!c) continue;
		if (*f & kToRaise)
			raise(cx, cy);
		else if (c->sqd != kFar && isObstacle(cx + c->ox, cy + c->oy))
		{
			const Cell copy = *c;  // lower() may reallocate the directory, not the block
			lower(cx, cy, copy);
		}
		// Buckets only hold keys >= m_minBucket unless push() lowered it; push() keeps it exact.
	}
	m_minBucket = 0;
	return processed;
}

int DynamicDistanceMap::squaredDistanceCells(int cx, int cy) const
{
	const Cell* c = cellPtr(cx, cy, nullptr);
	if (!c || c->sqd == kFar) return -1;
	return c->sqd;
}

float DynamicDistanceMap::cellDistance(int cx, int cy) const
{
	const Cell* c = cellPtr(cx, cy, nullptr);
	if (!c || c->sqd == kFar) return static_cast<float>(m_maxDistance);
	return m_sqrtLut[c->sqd];
}

std::size_t DynamicDistanceMap::memoryBytes() const
{
	std::size_t bytes = m_blockCount * sizeof(Block) + m_dir.capacity() * sizeof(m_dir[0]) +
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
