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
	m_blocks.clear();
	for (auto& b : m_buckets) b.clear();
	m_minBucket = 0;
	m_queued = 0;
}

DynamicDistanceMap::Ref DynamicDistanceMap::ref(int cx, int cy) const
{
	return Ref{m_blocks.find(blockOf(cx), blockOf(cy)), inBlock(cx, cy)};
}

bool DynamicDistanceMap::isObstacle(int cx, int cy) const
{
	const Ref r = ref(cx, cy);
	return r && r.cell().obstacle();
}

DynamicDistanceMap::Ref DynamicDistanceMap::refAlloc(int cx, int cy)
{
	Block& b = m_blocks.obtain(blockOf(cx), blockOf(cy),
							   [this] { return std::make_unique<Block>(static_cast<float>(m_maxDistance)); });
	return Ref{&b, inBlock(cx, cy)};
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
	if (r.cell().obstacle()) return;
	assign(r, 0, 0, 0);	 // also ends a pending raise: the obstacle is back
	push(0, cx, cy);
}

void DynamicDistanceMap::removeObstacle(int cx, int cy)
{
	const Ref r = ref(cx, cy);
	if (!r || !r.cell().obstacle()) return;
	markRaise(r);
	push(0, cx, cy);
}


void DynamicDistanceMap::raise(int cx, int cy)
{
	for (const auto& d : kNeighbours)
	{
		const int nx = cx + d[0], ny = cy + d[1];
		const Ref n = ref(nx, ny);
		if (!n || n.cell().far()) continue;	// nothing to invalidate, or already raising
		const int key = n.cell().sqd();
		if (!isObstacle(nx + n.cell().ox, ny + n.cell().oy))
		{
			// n pointed at a vanished obstacle: invalidate it and carry the raise on.
			markRaise(n);
		}
		// Valid neighbours are re-queued so that their lower wave refills the raised area.
		push(key, nx, ny);
	}
	if (const Ref r = ref(cx, cy); r && r.cell().raising()) r.cell().oy = 0;	// far, raise done
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
		if (n.cell().raising() || sq >= n.cell().sqd()) continue;
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
		if (r.cell().raising())
			raise(cx, cy);
		else if (r.cell().sqd() != kFar && isObstacle(cx + r.cell().ox, cy + r.cell().oy))
		{
			const Cell copy = r.cell();	 // lower() may reallocate the directory, not the block
			lower(cx, cy, copy);
		}
		// Buckets only hold keys >= m_minBucket unless push() lowered it; push() keeps it exact.
	}
	m_minBucket = 0;
	// A map built in one go (a rebuild) queues most of its cells at once: give that memory back
	// rather than keep it for the few cells a scan flips.
	for (auto& b : m_buckets)
		if (b.capacity() > 4096) std::vector<std::pair<int, int>>().swap(b);
	return processed;
}

bool DynamicDistanceMap::releaseIfFar(int bx, int by)
{
	if (m_queued != 0) throw std::logic_error("DynamicDistanceMap::releaseIfFar: changes still queued");
	const Block* b = m_blocks.find(bx, by);
	if (!b) return false;
	for (const Cell& c : b->cells)
		if (!c.far()) return false;
	return m_blocks.release(bx, by);
}

int DynamicDistanceMap::squaredDistanceCells(int cx, int cy) const
{
	const Ref r = ref(cx, cy);
	if (!r || r.cell().sqd() == kFar) return -1;
	return r.cell().sqd();
}

float DynamicDistanceMap::cellDistance(int cx, int cy) const
{
	const Ref r = ref(cx, cy);
	return r ? r.block->dist[r.i] : static_cast<float>(m_maxDistance);
}

std::size_t DynamicDistanceMap::memoryBytes() const
{
	std::size_t bytes = m_blocks.memoryBytes() + sizeof(Block) + m_sqrtLut.capacity() * sizeof(float);
	for (const auto& b : m_buckets) bytes += b.capacity() * sizeof(b[0]) + sizeof(b);
	return bytes;
}

bool DynamicDistanceMap::touchedBounds(int& minX, int& minY, int& maxX, int& maxY) const
{
	return m_blocks.cellBounds(minX, minY, maxX, maxY);
}

}  // namespace pmslam
