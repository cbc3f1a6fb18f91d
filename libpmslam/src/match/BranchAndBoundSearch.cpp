/* pmslam — branch-and-bound correlative search (see BranchAndBoundSearch.h). */
#include <mrpt/math/wrap2pi.h>
#include <pmslam/match/BranchAndBoundSearch.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <unordered_set>

namespace pmslam
{
namespace
{
using Lattice = BranchAndBoundSearch::Lattice;

// The cell of a point at rotation (c, s), translation index 0: the one formula of the score.
inline int cellOf(double origin, double rotated, double res) { return int(std::floor((origin + rotated) / res)); }

// The total order of lattice poses: score, then the smaller index (so that every pose has a
// unique rank and plateaus yield one candidate, the same one a brute-force pass picks).
struct Key
{
	int64_t score = -1;
	int64_t index = 0;
	bool operator>(const Key& o) const { return score != o.score ? score > o.score : index < o.index; }
	bool operator==(const Key& o) const { return score == o.score && index == o.index; }
};

struct Pose
{
	int a, i, j;
	Key key;
};

// A node: rotations [a·2^g, (a+1)·2^g) of the lattice (a is the index among level g's rotation
// intervals), translations [i, i+2^h) × [j, j+2^h). g = 0 is one rotation.
struct Node
{
	int64_t bound;
	int a, i, j;
	int g = 0, h = 0;
};

// ⌈log2 v⌉ for v ≥ 1: the pyramid level whose window of 2^L cells spans v cells.
inline int ceilLog2(unsigned v) { return v <= 1 ? 0 : 32 - __builtin_clz(v - 1); }

bool byBound(const Node& l, const Node& r) { return l.bound > r.bound; }

// Rotations are searched by branch and bound too, not one by one: a node spans 2^g rotations,
// and each point's bound is read at the level whose window holds every cell the point takes over
// those rotations and the node's translations. A rotation interval is halved before the
// translations once a point at the median range spans more than the node's side over it: the
// points beyond it then read coarser levels (looser bounds), while a node of one rotation shares
// nothing with its neighbours. Measured on bench_global_search (K = 8, floor 0.7, 120 points):
// the median range and a share of 1 against the 90th percentile and shares of 0.25 and 0.5:
// within the spread or faster on 20, 50 and 100 m buildings.
const double kReachShare = 1.0;
const double kReachQuantile = 0.5;
// Above this level the open nodes are taken best first (a priority queue: the candidates' scores
// and so the threshold rise as early as they can); at and below it, depth first, children best
// first (the nodes of one subtree read neighbouring cells: far fewer cache misses). Best first
// down to the poses needs the fewest bounds, but on a 100 m map its queue holds a million nodes
// and it takes three times longer; depth first from the roots evaluates 1.3-3 times more nodes.
const int kDepthFirstBelow = 5;

// At most four children: an insertion sort, best bound first (std::sort's machinery is wasted on
// four elements).
void sortChildren(Node* kids, int m)
{
	for (int c = 1; c < m; ++c)
		for (int d = c; d > 0 && kids[d].bound > kids[d - 1].bound; --d) std::swap(kids[d], kids[d - 1]);
}

/** One search over one lattice: the rotated points, the pruning state and the peaks found. */
class Searcher
{
   public:
	Searcher(const LikelihoodPyramid& pyramid, const Lattice& lattice, const BranchAndBoundSearch::Options& options,
			 BranchAndBoundSearch::Stats& stats);
	std::vector<Pose> run();

   private:
	int64_t bound(int h, int a, int i, int j) const { return boundBelow(h, a, i, j, 0); }
	int64_t boundBelow(int h, int a, int i, int j, int64_t limit) const;
	int64_t jointBound(int g, int a, int h, int i, int j, int64_t limit) const;
	void jointChildBounds(int g, int a, int h, int i, int j, int64_t limit, int64_t out[4]) const;
	void buildRotationIntervals(const std::vector<double>& ranges, double res);
	bool splitsRotations(int g, int h) const { return g > 0 && (h == 0 || m_reach[std::size_t(g)] > kReachShare * (1 << h)); }
	int intervals(int g) const { return int(m_span[std::size_t(g)].size()) / std::max(1, m_n); }
	void childBounds(int h, int a, int i, int j, int64_t limit, int64_t out[4]) const;
	Key keyOf(int64_t score, int a, int i, int j) const
	{
		return {score, (int64_t(a) * m_lat.ny + j) * m_lat.nx + i};
	}
	int angularDistance(int a, int b) const
	{
		const int d = std::abs(a - b);
		return m_lat.wrapsAround ? std::min(d, m_nA - d) : d;
	}
	bool neighbours(const Pose& p, int a, int i, int j) const
	{
		const double di = i - p.i, dj = j - p.j;
		return angularDistance(p.a, a) <= m_lat.angularRadius && di * di + dj * dj <= m_r2;
	}
	int64_t threshold() const
	{
		// Nothing below minScore, nor below minRelativeScore times the best found so far (the
		// final best is at least that good, so this never drops a pose that would be reported).
		const int64_t floor = m_peaks.empty() ? m_minRaw : std::max(m_minRaw, relativeFloor(m_peaks.front().key.score));
		return m_peaks.size() >= m_k ? std::max(floor, m_peaks.back().key.score) : floor;
	}
	int64_t relativeFloor(int64_t best) const { return int64_t(std::ceil(m_relative * double(best) - 1e-9)); }

	int children(const Node& n, Node kids[4]);
	void explore(const Node& n);
	void leaf(int a, int i, int j, int64_t score);
	bool dominated(const Pose& p) const;
	Pose bestNextDoor(const Pose& p);
	bool insideLowerBasin(const Node& n) const;
	void climb(Pose p);
	Pose bestInNeighbourhood(const Pose& p);
	void localDescend(int h, const Node& n, const Pose& centre, Pose& best);
	bool reaches(int h, int i, int j, const Pose& centre) const;
	void insertPeak(const Pose& p);

	const LikelihoodPyramid& m_pyr;
	const Lattice& m_lat;
	BranchAndBoundSearch::Stats& m_stats;
	std::size_t m_k;
	int m_n, m_nA, m_top;
	int64_t m_minRaw;
	double m_relative, m_r2;
	std::vector<int> m_cx, m_cy;  // cell of point k at rotation a, translation 0: [a·n + k]
	// Rotation intervals of 2^g rotations (g ≥ 1): over the interval a, point k's cells span
	// [minX, minX + span] × [minY, minY + span]: [a·n + k] at m_minX[g] etc. (g = 0: m_cx, m_cy, 0).
	std::vector<std::vector<int>> m_minX, m_minY;
	std::vector<std::vector<uint16_t>> m_span;
	std::vector<double> m_reach;  // [g]: the span (cells) of a point at the reach range, over 2^g rotations
	int m_rootG = 0;  // rotation level of the roots
	// Every pyramid level has the same extent (LikelihoodPyramid::shape): its origin, last cell and
	// row length; each level's cells, up to any level a point may ask for (at most ⌈log2(2^h +
	// 65535)⌉).
	int m_x0 = 0, m_y0 = 0, m_wx = 0, m_wy = 0;
	std::size_t m_stride = 0;
	std::array<const uint8_t*, 32> m_cells{};
	std::array<std::size_t, 32> m_mask{};
	std::vector<Pose> m_peaks;	// confirmed candidates, best first, at most K
	std::unordered_set<int64_t> m_settled;	// indices of poses climbed through
};

Searcher::Searcher(const LikelihoodPyramid& pyramid, const Lattice& lattice,
				   const BranchAndBoundSearch::Options& options, BranchAndBoundSearch::Stats& stats)
	: m_pyr(pyramid), m_lat(lattice), m_stats(stats), m_k(std::max<std::size_t>(1, options.candidates))
{
	m_n = int(lattice.points.size());
	m_nA = int(lattice.angles.size());
	m_minRaw = int64_t(std::ceil(options.minScore * LikelihoodPyramid::kMaxValue * m_n - 1e-9));
	m_relative = std::clamp(options.minRelativeScore, 0.0, 1.0);
	m_r2 = lattice.linearRadius * lattice.linearRadius;
	// The coarsest level worth using: one node spanning the lattice's larger side.
	m_top = 0;
	while (m_top + 1 < pyramid.levels() && (1 << m_top) < std::max(lattice.nx, lattice.ny)) ++m_top;
	const double res = pyramid.resolution();
	m_cx.resize(std::size_t(m_nA) * std::size_t(m_n));
	m_cy.resize(m_cx.size());
	for (int a = 0; a < m_nA; ++a)
	{
		const double c = std::cos(lattice.angles[std::size_t(a)]), s = std::sin(lattice.angles[std::size_t(a)]);
		for (int k = 0; k < m_n; ++k)
		{
			const auto& p = lattice.points[std::size_t(k)];
			m_cx[std::size_t(a) * m_n + k] = cellOf(lattice.originX, c * p.x - s * p.y, res);
			m_cy[std::size_t(a) * m_n + k] = cellOf(lattice.originY, s * p.x + c * p.y, res);
		}
	}
	std::vector<double> ranges;
	for (const auto& p : lattice.points) ranges.push_back(std::hypot(double(p.x), double(p.y)));
	buildRotationIntervals(ranges, res);
	stats.angles = std::size_t(m_nA);
	stats.translations = std::size_t(lattice.nx) * std::size_t(lattice.ny);
	stats.points = std::size_t(m_n);
}

void Searcher::buildRotationIntervals(const std::vector<double>& ranges, double res)
{
	// Level g from level g-1: interval a is intervals 2a and 2a+1 (the last may be missing).
	const int G = ceilLog2(unsigned(std::max(1, m_nA)));
	const std::size_t n = std::size_t(m_n);
	m_minX.assign(std::size_t(G) + 1, {});
	m_minY.assign(std::size_t(G) + 1, {});
	m_span.assign(std::size_t(G) + 1, {});
	m_minX[0] = m_cx;
	m_minY[0] = m_cy;
	m_span[0].assign(m_cx.size(), 0);
	std::vector<int> maxX = m_cx, maxY = m_cy, nextX, nextY;
	for (int g = 1; g <= G; ++g)
	{
		const std::size_t below = m_span[std::size_t(g - 1)].size() / n, count = (below + 1) / 2;
		const auto& bx = m_minX[std::size_t(g - 1)];
		const auto& by = m_minY[std::size_t(g - 1)];
		auto& mx = m_minX[std::size_t(g)];
		auto& my = m_minY[std::size_t(g)];
		auto& sp = m_span[std::size_t(g)];
		mx.resize(count * n);
		my.resize(count * n);
		sp.resize(count * n);
		nextX.resize(count * n);
		nextY.resize(count * n);
		for (std::size_t a = 0; a < count; ++a)
		{
			const std::size_t c0 = 2 * a * n, c1 = (2 * a + 1 < below ? 2 * a + 1 : 2 * a) * n;
			for (std::size_t k = 0; k < n; ++k)
			{
				const std::size_t o = a * n + k;
				mx[o] = std::min(bx[c0 + k], bx[c1 + k]);
				my[o] = std::min(by[c0 + k], by[c1 + k]);
				nextX[o] = std::max(maxX[c0 + k], maxX[c1 + k]);
				nextY[o] = std::max(maxY[c0 + k], maxY[c1 + k]);
				sp[o] = uint16_t(std::min(65535, std::max(nextX[o] - mx[o], nextY[o] - my[o])));
			}
		}
		std::swap(maxX, nextX);
		std::swap(maxY, nextY);
	}
	// The split rule's reach: how far a point at the reach range moves over 2^g rotations.
	std::vector<double> r = ranges;
	double reachRange = 0;
	if (!r.empty())
	{
		const auto at = r.begin() + std::ptrdiff_t(std::lround(kReachQuantile * double(r.size() - 1)));
		std::nth_element(r.begin(), at, r.end());
		reachRange = *at;
	}
	m_reach.assign(std::size_t(G) + 1, 0);
	for (int g = 1; g <= G; ++g) m_reach[std::size_t(g)] = reachRange * m_lat.angularStep * double(1 << g) / res;
	m_rootG = 0;
	while (m_rootG < G && !splitsRotations(m_rootG + 1, m_top)) ++m_rootG;
	// Levels beyond the coarsest read a single cell holding the maximum.
	static const uint8_t kMaxCell[1] = {uint8_t(LikelihoodPyramid::kMaxValue)};
	const LikelihoodPyramid::Level& l0 = m_pyr.level(0);
	m_x0 = l0.x0;
	m_y0 = l0.y0;
	m_wx = l0.width - 1;
	m_wy = l0.height - 1;
	m_stride = std::size_t(l0.width);
	for (int L = 0; L < int(m_cells.size()); ++L)
	{
		const bool real = L < m_pyr.levels();
		m_cells[std::size_t(L)] = real ? m_pyr.level(L).cells.data() : kMaxCell;
		m_mask[std::size_t(L)] = real ? ~std::size_t(0) : 0;
	}
}

int64_t Searcher::jointBound(int g, int a, int h, int i, int j, int64_t limit) const
{
	// As boundBelow, each point at the level whose window spans its cells over the node's
	// rotations (span) and translations (2^h): [minX + i, minX + span + i + 2^h) fits in a window
	// of 2^L cells starting at minX + i. Beyond the pyramid's coarsest level the point counts the
	// maximum. Every level has the same extent, so the cell index is the same at any level.
	if (g == 0) return boundBelow(h, a, i, j, limit);
	const std::size_t base = std::size_t(a) * std::size_t(m_n);
	const int* mx = &m_minX[std::size_t(g)][base];
	const int* my = &m_minY[std::size_t(g)][base];
	const uint16_t* sp = &m_span[std::size_t(g)][base];
	const unsigned w = 1u << h;
	const int ox = i - m_x0, oy = j - m_y0;
	int64_t sum = 0;
	for (int k0 = 0; k0 < m_n; k0 += 16)
	{
		const int k1 = std::min(m_n, k0 + 16);
		int part = 0;
		for (int k = k0; k < k1; ++k)
		{
			const int L = ceilLog2(w + sp[k]);
			const std::size_t x = std::size_t(std::clamp(mx[k] + ox, 0, m_wx)), y = std::size_t(std::clamp(my[k] + oy, 0, m_wy));
			part += m_cells[L][(y * m_stride + x) & m_mask[L]];
		}
		sum += part;
		if (sum + int64_t(m_n - k1) * LikelihoodPyramid::kMaxValue < limit) return sum;
	}
	return sum;
}

void Searcher::jointChildBounds(int g, int a, int h, int i, int j, int64_t limit, int64_t out[4]) const
{
	// The four translation children of a node of rotation level g at once (see childBounds).
	const std::size_t base = std::size_t(a) * std::size_t(m_n);
	const int* mx = &m_minX[std::size_t(g)][base];
	const int* my = &m_minY[std::size_t(g)][base];
	const uint16_t* sp = &m_span[std::size_t(g)][base];
	const unsigned w = 1u << h;
	const int s = int(w), ox = i - m_x0, oy = j - m_y0;
	int64_t sum[4] = {0, 0, 0, 0};
	for (int k0 = 0; k0 < m_n; k0 += 16)
	{
		const int k1 = std::min(m_n, k0 + 16);
		int p0 = 0, p1 = 0, p2 = 0, p3 = 0;
		for (int k = k0; k < k1; ++k)
		{
			const int L = ceilLog2(w + sp[k]);
			const uint8_t* cells = m_cells[L];
			const std::size_t mask = m_mask[L];
			const int x = mx[k] + ox, y = my[k] + oy;
			const std::size_t xa = std::size_t(std::clamp(x, 0, m_wx)), xb = std::size_t(std::clamp(x + s, 0, m_wx));
			const std::size_t ya = std::size_t(std::clamp(y, 0, m_wy)) * m_stride,
							  yb = std::size_t(std::clamp(y + s, 0, m_wy)) * m_stride;
			p0 += cells[(ya + xa) & mask];
			p1 += cells[(ya + xb) & mask];
			p2 += cells[(yb + xa) & mask];
			p3 += cells[(yb + xb) & mask];
		}
		sum[0] += p0;
		sum[1] += p1;
		sum[2] += p2;
		sum[3] += p3;
		const int64_t best = std::max(std::max(sum[0], sum[1]), std::max(sum[2], sum[3]));
		if (best + int64_t(m_n - k1) * LikelihoodPyramid::kMaxValue < limit) break;
	}
	for (int c = 0; c < 4; ++c) out[c] = sum[c];
}

int64_t Searcher::boundBelow(int h, int a, int i, int j, int64_t limit) const
{
	// The hot loop: one clamped byte load per point (clamping keeps points that leave the
	// padded level on its zero border, which is exactly their value). Every 16 points, a sum
	// that cannot reach `limit` even if every remaining point scored the maximum stops early:
	// the node is pruned all the same, and the partial sum returned is below `limit` too.
	const LikelihoodPyramid::Level& l = m_pyr.level(h);
	const int* cx = &m_cx[std::size_t(a) * m_n];
	const int* cy = &m_cy[std::size_t(a) * m_n];
	const int ox = i - l.x0, oy = j - l.y0, wx = l.width - 1, wy = l.height - 1;
	const uint8_t* cells = l.cells.data();
	const std::size_t stride = std::size_t(l.width);
	int64_t sum = 0;
	for (int k0 = 0; k0 < m_n; k0 += 16)
	{
		const int k1 = std::min(m_n, k0 + 16);
		int part = 0;
		for (int k = k0; k < k1; ++k)
		{
			const int x = std::clamp(cx[k] + ox, 0, wx), y = std::clamp(cy[k] + oy, 0, wy);
			part += cells[std::size_t(y) * stride + std::size_t(x)];
		}
		sum += part;
		if (sum + int64_t(m_n - k1) * LikelihoodPyramid::kMaxValue < limit) return sum;
	}
	return sum;
}

void Searcher::childBounds(int h, int a, int i, int j, int64_t limit, int64_t out[4]) const
{
	// The four children of a node of level h+1 at once, at level h: [i, i+s) and [i+s, i+2s) in
	// x, alike in y (s = 2^h). One pass over the points, four loads each from two nearby rows:
	// the rotated cells and the clamping are shared, and the loads are independent. Early exit as
	// in boundBelow, once no child can reach `limit`.
	const LikelihoodPyramid::Level& l = m_pyr.level(h);
	const int* cx = &m_cx[std::size_t(a) * m_n];
	const int* cy = &m_cy[std::size_t(a) * m_n];
	const int s = 1 << h;
	const int ox = i - l.x0, oy = j - l.y0, wx = l.width - 1, wy = l.height - 1;
	const uint8_t* cells = l.cells.data();
	const std::size_t stride = std::size_t(l.width);
	int64_t sum[4] = {0, 0, 0, 0};
	for (int k0 = 0; k0 < m_n; k0 += 16)
	{
		const int k1 = std::min(m_n, k0 + 16);
		int p0 = 0, p1 = 0, p2 = 0, p3 = 0;
		for (int k = k0; k < k1; ++k)
		{
			const int x = cx[k] + ox, y = cy[k] + oy;
			const std::size_t xa = std::size_t(std::clamp(x, 0, wx)), xb = std::size_t(std::clamp(x + s, 0, wx));
			const uint8_t* ra = cells + std::size_t(std::clamp(y, 0, wy)) * stride;
			const uint8_t* rb = cells + std::size_t(std::clamp(y + s, 0, wy)) * stride;
			p0 += ra[xa];
			p1 += ra[xb];
			p2 += rb[xa];
			p3 += rb[xb];
		}
		sum[0] += p0;
		sum[1] += p1;
		sum[2] += p2;
		sum[3] += p3;
		const int64_t best = std::max(std::max(sum[0], sum[1]), std::max(sum[2], sum[3]));
		if (best + int64_t(m_n - k1) * LikelihoodPyramid::kMaxValue < limit) break;
	}
	for (int c = 0; c < 4; ++c) out[c] = sum[c];
}

std::vector<Pose> Searcher::run()
{
	// Best first: the open node of the highest bound is expanded next (ties: the finer node, so
	// that poses come out before the coarse nodes they tie with). Poses then come out in
	// descending score, the threshold reaches the K-th candidate's score as early as it can, and
	// every node expanded has a bound at or above the answer: no order does less.
	const int w = 1 << m_top;
	auto worse = [](const Node& l, const Node& r) {
		return l.bound != r.bound ? l.bound < r.bound : l.g + l.h > r.g + r.h;
	};
	std::vector<Node> heap;
	for (int a = 0; a < intervals(m_rootG); ++a)
		for (int j = 0; j < m_lat.ny; j += w)
			for (int i = 0; i < m_lat.nx; i += w)
				heap.push_back({jointBound(m_rootG, a, m_top, i, j, 0), a, i, j, m_rootG, m_top});
	m_stats.roots = heap.size();
	m_stats.nodes += heap.size();
	std::make_heap(heap.begin(), heap.end(), worse);
	Node kids[4];
	while (!heap.empty() && heap.front().bound >= threshold())
	{
		std::pop_heap(heap.begin(), heap.end(), worse);
		const Node n = heap.back();
		heap.pop_back();
		if (n.h <= kDepthFirstBelow)
			explore(n);
		else if (!insideLowerBasin(n))
		{
			const int m = children(n, kids);
			for (int c = 0; c < m; ++c)
				if (kids[c].bound >= threshold())
				{
					heap.push_back(kids[c]);
					std::push_heap(heap.begin(), heap.end(), worse);
				}
			m_stats.open = std::max(m_stats.open, heap.size());
		}
	}
	// Candidates confirmed before the best was known may fall below its relative floor.
	if (!m_peaks.empty())
	{
		const int64_t floor = std::max(m_minRaw, relativeFloor(m_peaks.front().key.score));
		while (m_peaks.back().key.score < floor) m_peaks.pop_back();
	}
	return m_peaks;
}

void Searcher::explore(const Node& n)
{
	if (n.g == 0 && n.h == 0)
	{
		leaf(n.a, n.i, n.j, n.bound);
		return;
	}
	if (insideLowerBasin(n)) return;
	Node kids[4];
	const int m = children(n, kids);
	sortChildren(kids, m);
	for (int c = 0; c < m; ++c)
	{
		// The threshold may have risen while the previous child was explored.
		if (kids[c].bound < threshold()) break;
		explore(kids[c]);
	}
}

int Searcher::children(const Node& n, Node kids[4])
{
	int m = 0;
	if (splitsRotations(n.g, n.h))
	{
		// Two halves of the rotation interval, the same translations.
		for (int c = 2 * n.a; c <= 2 * n.a + 1 && c < intervals(n.g - 1); ++c)
			kids[m++] = {jointBound(n.g - 1, c, n.h, n.i, n.j, threshold()), c, n.i, n.j, n.g - 1, n.h};
	}
	else
	{
		// Four quarters of the translations, the same rotations.
		const int h = n.h - 1, s = 1 << h;
		int64_t b[4] = {0, 0, 0, 0};
		if (n.g == 0)
			childBounds(h, n.a, n.i, n.j, threshold(), b);
		else
			jointChildBounds(n.g, n.a, h, n.i, n.j, threshold(), b);
		for (int dy = 0; dy < 2; ++dy)
			for (int dx = 0; dx < 2; ++dx)
			{
				const int ci = n.i + dx * s, cj = n.j + dy * s;
				if (ci >= m_lat.nx || cj >= m_lat.ny) continue;
				kids[m++] = {b[dy * 2 + dx], n.a, ci, cj, n.g, h};
			}
	}
	m_stats.nodes += std::size_t(m);
	return m;
}

void Searcher::leaf(int a, int i, int j, int64_t score)
{
	++m_stats.leaves;
	const Pose p{a, i, j, keyOf(score, a, i, j)};
	if (score < threshold()) return;
	if (m_peaks.size() >= m_k && !(p.key > m_peaks.back().key)) return;
	if (!dominated(p)) climb(p);
}

bool Searcher::dominated(const Pose& p) const
{
	// A pose near a confirmed candidate that beats it is no candidate itself.
	for (const Pose& c : m_peaks)
		if (c.key > p.key && neighbours(c, p.a, p.i, p.j)) return true;
	return false;
}

bool Searcher::insideLowerBasin(const Node& n) const
{
	// A node lying wholly in a candidate's neighbourhood, every pose of it below the candidate,
	// holds no candidate: the slopes of a peak already found need no exploring.
	const int w = (1 << n.h) - 1;
	const int lo = n.a << n.g, hi = std::min(m_nA, (n.a + 1) << n.g) - 1;
	for (const Pose& c : m_peaks)
	{
		if (!(n.bound < c.key.score)) continue;
		// Every rotation of [lo, hi] within the angular radius of c's.
		int d = lo - c.a;
		if (m_lat.wrapsAround) d = ((d % m_nA) + m_nA + m_nA / 2) % m_nA - m_nA / 2;
		if (d < -m_lat.angularRadius || d + (hi - lo) > m_lat.angularRadius) continue;
		const double dx = std::max(std::abs(n.i - c.i), std::abs(n.i + w - c.i));
		const double dy = std::max(std::abs(n.j - c.j), std::abs(n.j + w - c.j));
		if (dx * dx + dy * dy <= m_r2) return true;
	}
	return false;
}

Pose Searcher::bestNextDoor(const Pose& p)
{
	// The best of the (up to) 26 poses one step away: on a smooth score most poses have a better
	// one there, which is far cheaper to find than the best of the whole neighbourhood.
	Pose best = p;
	for (int da = -1; da <= 1; ++da)
	{
		int a = p.a + da;
		if (m_lat.wrapsAround)
			a = (a + m_nA) % m_nA;
		else if (a < 0 || a >= m_nA)
			continue;
		for (int dj = -1; dj <= 1; ++dj)
			for (int di = -1; di <= 1; ++di)
			{
				const int i = p.i + di, j = p.j + dj;
				if ((!da && !di && !dj) || i < 0 || j < 0 || i >= m_lat.nx || j >= m_lat.ny || !neighbours(p, a, i, j))
					continue;
				++m_stats.climbNodes;
				const Key k = keyOf(bound(0, a, i, j), a, i, j);
				if (k > best.key) best = {a, i, j, k};
			}
	}
	return best;
}

void Searcher::climb(Pose p)
{
	// Hill-climb until the pose beats its whole neighbourhood: that is a candidate. Confirming
	// candidates early raises the pruning threshold once K of them are known. A pose climbed
	// through once is settled (no candidate, or confirmed), so later climbs stop there.
	for (;;)
	{
		if (!m_settled.insert(p.key.index).second || dominated(p)) return;
		const Pose q = bestNextDoor(p);
		if (q.key > p.key)
		{
			p = q;
			continue;
		}
		++m_stats.climbs;
		const Pose b = bestInNeighbourhood(p);
		if (b.key == p.key)
		{
			insertPeak(p);
			return;
		}
		p = b;
	}
}

bool Searcher::reaches(int h, int i, int j, const Pose& centre) const
{
	// Does node [i, i+2^h) × [j, j+2^h) hold a lattice pose of centre's disc?
	const int w = (1 << h) - 1;
	const int x0 = std::max(i, 0), y0 = std::max(j, 0), x1 = std::min(i + w, m_lat.nx - 1),
			  y1 = std::min(j + w, m_lat.ny - 1);
	if (x0 > x1 || y0 > y1) return false;
	const double dx = std::max({x0 - centre.i, 0, centre.i - x1}), dy = std::max({y0 - centre.j, 0, centre.j - y1});
	return dx * dx + dy * dy <= m_r2;
}

Pose Searcher::bestInNeighbourhood(const Pose& p)
{
	// The same branch and bound over p's neighbourhood: one small square of translations per
	// rotation, threshold p's own score.
	const int r = int(std::floor(m_lat.linearRadius + 1e-9));
	int h = 0;
	while ((1 << h) < 2 * r + 1 && h < m_top) ++h;
	const int w = 1 << h;
	std::vector<Node> roots;
	// Rotations of the neighbourhood, each once (a radius of half the circle or more is all of it).
	const bool all = m_lat.wrapsAround && 2 * m_lat.angularRadius + 1 >= m_nA;
	const int from = all ? 0 : p.a - m_lat.angularRadius, to = all ? m_nA - 1 : p.a + m_lat.angularRadius;
	for (int da = from; da <= to; ++da)
	{
		int a = da;
		if (m_lat.wrapsAround)
			a = (a % m_nA + m_nA) % m_nA;
		else if (a < 0 || a >= m_nA)
			continue;
		for (int j = p.j - r; j <= p.j + r; j += w)
			for (int i = p.i - r; i <= p.i + r; i += w)
				if (reaches(h, i, j, p)) roots.push_back({bound(h, a, i, j), a, i, j});
	}
	m_stats.climbNodes += roots.size();
	std::sort(roots.begin(), roots.end(), byBound);
	Pose best = p;
	for (const Node& n : roots)
	{
		if (n.bound < best.key.score) break;
		localDescend(h, n, p, best);
	}
	return best;
}

void Searcher::localDescend(int h, const Node& n, const Pose& centre, Pose& best)
{
	if (h == 0)
	{
		const Key k = keyOf(n.bound, n.a, n.i, n.j);
		if (k > best.key) best = {n.a, n.i, n.j, k};
		return;
	}
	const int s = 1 << (h - 1);
	Node kids[4];
	int m = 0;
	for (int dy = 0; dy < 2; ++dy)
		for (int dx = 0; dx < 2; ++dx)
		{
			const int ci = n.i + dx * s, cj = n.j + dy * s;
			if (reaches(h - 1, ci, cj, centre)) kids[m++] = {boundBelow(h - 1, n.a, ci, cj, best.key.score), n.a, ci, cj};
		}
	m_stats.climbNodes += std::size_t(m);
	sortChildren(kids, m);
	for (int c = 0; c < m && kids[c].bound >= best.key.score; ++c) localDescend(h - 1, kids[c], centre, best);
}

void Searcher::insertPeak(const Pose& p)
{
	auto at = std::find_if(m_peaks.begin(), m_peaks.end(), [&](const Pose& c) { return p.key > c.key; });
	m_peaks.insert(at, p);
	if (m_peaks.size() > m_k) m_peaks.pop_back();
}
}  // namespace

struct BranchAndBoundSearch::CoarseCache
{
	std::once_flag once;
	std::unique_ptr<LikelihoodPyramid> pyramid;
};

BranchAndBoundSearch::BranchAndBoundSearch(const LikelihoodPyramid& pyramid, const Options& options)
	: m_pyramid(pyramid), m_options(options), m_coarse(std::make_shared<CoarseCache>())
{
}

BranchAndBoundSearch::Result BranchAndBoundSearch::searchGlobalCoarseToFine(
	const std::vector<mrpt::math::TPoint2Df>& points) const
{
	std::call_once(m_coarse->once, [&] { m_coarse->pyramid = std::make_unique<LikelihoodPyramid>(coarsePyramid()); });
	return searchGlobalCoarseToFine(points, *m_coarse->pyramid);
}

namespace
{
bool near(const BranchAndBoundSearch::Candidate& a, const BranchAndBoundSearch::Candidate& b, double linear,
		  double angular)
{
	return std::hypot(a.pose.x - b.pose.x, a.pose.y - b.pose.y) <= linear &&
		   std::abs(mrpt::math::wrapToPi(a.pose.phi - b.pose.phi)) <= angular;
}

void addWork(BranchAndBoundSearch::Stats& total, const BranchAndBoundSearch::Stats& s)
{
	total.nodes += s.nodes;
	total.leaves += s.leaves;
	total.climbs += s.climbs;
	total.climbNodes += s.climbNodes;
}
}  // namespace

BranchAndBoundSearch::Result BranchAndBoundSearch::searchGlobalCoarseToFine(
	const std::vector<mrpt::math::TPoint2Df>& points, const LikelihoodPyramid& coarse) const
{
	const auto t0 = std::chrono::steady_clock::now();
	const Options::CoarseToFine& c = m_options.coarse;
	// Stage 1: the exact optimum of the coarse score on the coarse global lattice.
	Options co = m_options;
	co.maxPoints = c.maxPoints;
	co.rangeQuantile = c.rangeQuantile;
	co.angularStep = 0;	 // a given step is the fine lattice's: the coarse one follows the coarse cells
	co.candidates = std::max(c.candidates, m_options.candidates);
	co.minRelativeScore = c.minRelativeScore;
	const BranchAndBoundSearch first(coarse, co);
	const Lattice lattice = first.globalLattice(points);
	const Result rough = first.search(lattice);
	Result out;
	out.stats = rough.stats;
	out.stats.coarseSeconds = rough.stats.seconds;
	out.stats.refined = rough.candidates.size();
	// Stage 2: each coarse candidate refined on this pyramid, by the fine score.
	Options fo = m_options;
	fo.candidates = 1;
	fo.minRelativeScore = 0;
	const BranchAndBoundSearch fine(m_pyramid, fo);
	const double lin = c.linearWindow > 0 ? c.linearWindow : coarse.resolution();
	std::vector<Candidate> refined;
	for (const Candidate& k : rough.candidates)
	{
		// Centred on the fine cell centre nearest the coarse pose, so that the refined
		// translations are those of the fine global lattice (a coarse cell's centre lies on a
		// fine cell's corner when the factor is even).
		const double res = m_pyramid.resolution(), ox = m_pyramid.frameOffset().x, oy = m_pyramid.frameOffset().y;
		const mrpt::math::TPose2D centre((std::floor((k.pose.x - ox) / res) + 0.5) * res + ox,
										 (std::floor((k.pose.y - oy) / res) + 0.5) * res + oy, k.pose.phi);
		const Result r = fine.searchWindow(points, centre, lin, c.angularSteps * lattice.angularStep);
		addWork(out.stats, r.stats);
		if (!r.candidates.empty()) refined.push_back(r.candidates[0]);
	}
	// Best fine score first (ties: the better coarse rank, kept by the stable sort); each kept
	// when no better one lies in its neighbourhood.
	std::stable_sort(refined.begin(), refined.end(),
					 [](const Candidate& l, const Candidate& r) { return l.rawScore > r.rawScore; });
	for (const Candidate& k : refined)
	{
		if (out.candidates.size() >= std::max<std::size_t>(1, m_options.candidates)) break;
		if (!out.candidates.empty() && k.score < m_options.minRelativeScore * out.candidates.front().score - 1e-12)
			break;
		const bool shadowed = std::any_of(out.candidates.begin(), out.candidates.end(), [&](const Candidate& b) {
			return near(k, b, m_options.distinctLinear, m_options.distinctAngular);
		});
		if (!shadowed) out.candidates.push_back(k);
	}
	out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return out;
}

BranchAndBoundSearch::Lattice BranchAndBoundSearch::makeLattice(const std::vector<mrpt::math::TPoint2Df>& points) const
{
	Lattice l;
	const std::size_t maxPts = m_options.maxPoints ? m_options.maxPoints : points.size();
	const std::size_t stride = std::max<std::size_t>(1, (points.size() + maxPts - 1) / std::max<std::size_t>(1, maxPts));
	std::vector<double> ranges;
	for (std::size_t k = 0; k < points.size(); k += stride)
		if (std::isfinite(points[k].x) && std::isfinite(points[k].y))
		{
			l.points.push_back(points[k]);
			ranges.push_back(std::hypot(points[k].x, points[k].y));
		}
	double far = 0;
	if (!ranges.empty())
	{
		const double q = std::clamp(m_options.rangeQuantile, 0.0, 1.0);
		const auto at = ranges.begin() + std::ptrdiff_t(std::lround(q * double(ranges.size() - 1)));
		std::nth_element(ranges.begin(), at, ranges.end());
		far = *at;
	}
	const double res = m_pyramid.resolution();
	// The farthest point (or the quantile's) moves by range · step: one cell at most. (A point closer than two cells
	// would ask for absurdly many rotations.)
	l.angularStep = m_options.angularStep > 0 ? m_options.angularStep : res / std::max(far, 2 * res);
	l.linearRadius = m_options.distinctLinear / res;
	return l;
}

BranchAndBoundSearch::Lattice BranchAndBoundSearch::windowLattice(const std::vector<mrpt::math::TPoint2Df>& points,
																   const mrpt::math::TPose2D& centre,
																   double linearWindow, double angularWindow) const
{
	Lattice l = makeLattice(points);
	const double res = m_pyramid.resolution();
	const int nT = std::max(0, int(std::ceil(linearWindow / res - 1e-9)));
	l.originX = centre.x - m_pyramid.frameOffset().x - nT * res;
	l.originY = centre.y - m_pyramid.frameOffset().y - nT * res;
	l.nx = l.ny = 2 * nT + 1;
	const int nA = std::max(0, int(std::ceil(angularWindow / l.angularStep - 1e-9)));
	if ((2 * nA + 1) * l.angularStep >= 2 * M_PI)
	{
		// The window covers every heading: the whole circle, evenly, starting at the centre's.
		const int n = int(std::ceil(2 * M_PI / l.angularStep));
		l.angularStep = 2 * M_PI / n;
		for (int a = 0; a < n; ++a) l.angles.push_back(centre.phi + a * l.angularStep);
		l.wrapsAround = true;
	}
	else
		for (int a = -nA; a <= nA; ++a) l.angles.push_back(centre.phi + a * l.angularStep);
	l.angularRadius = int(std::floor(m_options.distinctAngular / l.angularStep + 1e-9));
	return l;
}

BranchAndBoundSearch::Lattice BranchAndBoundSearch::globalLattice(const std::vector<mrpt::math::TPoint2Df>& points) const
{
	Lattice l = makeLattice(points);
	const double res = m_pyramid.resolution();
	const auto& w = m_pyramid.window();
	// Cell centres: the pose sits in the middle of the cell it stands on.
	l.originX = (w.minX + 0.5) * res;
	l.originY = (w.minY + 0.5) * res;
	l.nx = w.width();
	l.ny = w.height();
	const int n = int(std::ceil(2 * M_PI / l.angularStep - 1e-9));
	l.angularStep = 2 * M_PI / n;
	for (int a = 0; a < n; ++a) l.angles.push_back(a * l.angularStep);
	l.wrapsAround = true;
	l.angularRadius = int(std::floor(m_options.distinctAngular / l.angularStep + 1e-9));
	return l;
}

BranchAndBoundSearch::Result BranchAndBoundSearch::search(const Lattice& lattice) const
{
	const auto t0 = std::chrono::steady_clock::now();
	Result out;
	if (lattice.points.empty() || lattice.angles.empty() || lattice.nx < 1 || lattice.ny < 1) return out;
	Searcher searcher(m_pyramid, lattice, m_options, out.stats);
	const double scale = 1.0 / (double(LikelihoodPyramid::kMaxValue) * lattice.points.size());
	for (const Pose& p : searcher.run())
		out.candidates.push_back({poseOf(lattice, p.a, p.i, p.j), p.key.score * scale, p.key.score, p.a, p.i, p.j});
	out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return out;
}

std::vector<std::pair<int, int>> BranchAndBoundSearch::pointCells(const Lattice& lattice, int a) const
{
	const double c = std::cos(lattice.angles.at(std::size_t(a))), s = std::sin(lattice.angles.at(std::size_t(a)));
	const double res = m_pyramid.resolution();
	std::vector<std::pair<int, int>> out;
	for (const auto& p : lattice.points)
		out.emplace_back(cellOf(lattice.originX, c * p.x - s * p.y, res), cellOf(lattice.originY, s * p.x + c * p.y, res));
	return out;
}

int64_t BranchAndBoundSearch::nodeBound(const Lattice& lattice, int h, int a, int i, int j) const
{
	int64_t sum = 0;
	for (const auto& [cx, cy] : pointCells(lattice, a)) sum += m_pyramid.value(h, cx + i, cy + j);
	return sum;
}

mrpt::math::TPose2D BranchAndBoundSearch::poseOf(const Lattice& lattice, int a, int i, int j) const
{
	const double res = m_pyramid.resolution();
	return {lattice.originX + i * res + m_pyramid.frameOffset().x, lattice.originY + j * res + m_pyramid.frameOffset().y,
			mrpt::math::wrapToPi(lattice.angles.at(std::size_t(a)))};
}

}  // namespace pmslam
