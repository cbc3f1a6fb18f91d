/* pmslam — branch-and-bound correlative search (see BranchAndBoundSearch.h). */
#include <mrpt/math/wrap2pi.h>
#include <pmslam/match/BranchAndBoundSearch.h>

#include <algorithm>
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

struct Node
{
	int64_t bound;
	int a, i, j;
};

bool byBound(const Node& l, const Node& r) { return l.bound > r.bound; }

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

	void descend(int h, int a, int i, int j);
	void leaf(int a, int i, int j, int64_t score);
	bool dominated(const Pose& p) const;
	Pose bestNextDoor(const Pose& p);
	bool insideLowerBasin(int h, const Node& n) const;
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
	stats.angles = std::size_t(m_nA);
	stats.translations = std::size_t(lattice.nx) * std::size_t(lattice.ny);
	stats.points = std::size_t(m_n);
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
	// Every root is scored and the roots are taken best first across all rotations: a good
	// candidate found early prunes most of the others.
	const int w = 1 << m_top;
	std::vector<Node> roots;
	for (int a = 0; a < m_nA; ++a)
		for (int j = 0; j < m_lat.ny; j += w)
			for (int i = 0; i < m_lat.nx; i += w) roots.push_back({bound(m_top, a, i, j), a, i, j});
	m_stats.roots = roots.size();
	m_stats.nodes += roots.size();
	std::sort(roots.begin(), roots.end(), byBound);
	for (const Node& r : roots)
	{
		if (r.bound < threshold()) break;
		if (m_top == 0)
			leaf(r.a, r.i, r.j, r.bound);
		else if (!insideLowerBasin(m_top, r))
			descend(m_top, r.a, r.i, r.j);
	}
	// Candidates confirmed before the best was known may fall below its relative floor.
	if (!m_peaks.empty())
	{
		const int64_t floor = std::max(m_minRaw, relativeFloor(m_peaks.front().key.score));
		while (m_peaks.back().key.score < floor) m_peaks.pop_back();
	}
	return m_peaks;
}

void Searcher::descend(int h, int a, int i, int j)
{
	const int s = 1 << (h - 1);
	int64_t b[4];
	childBounds(h - 1, a, i, j, threshold(), b);
	Node kids[4];
	int m = 0;
	for (int dy = 0; dy < 2; ++dy)
		for (int dx = 0; dx < 2; ++dx)
		{
			const int ci = i + dx * s, cj = j + dy * s;
			if (ci < m_lat.nx && cj < m_lat.ny) kids[m++] = {b[dy * 2 + dx], a, ci, cj};
		}
	m_stats.nodes += std::size_t(m);
	sortChildren(kids, m);
	for (int c = 0; c < m; ++c)
	{
		// The threshold may have risen while the previous child was explored.
		if (kids[c].bound < threshold()) break;
		if (h == 1)
			leaf(a, kids[c].i, kids[c].j, kids[c].bound);
		else if (!insideLowerBasin(h - 1, kids[c]))
			descend(h - 1, a, kids[c].i, kids[c].j);
	}
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

bool Searcher::insideLowerBasin(int h, const Node& n) const
{
	// A node lying wholly in a candidate's neighbourhood, every pose of it below the candidate,
	// holds no candidate: the slopes of a peak already found need no exploring.
	const int w = (1 << h) - 1;
	for (const Pose& c : m_peaks)
	{
		if (!(n.bound < c.key.score) || angularDistance(c.a, n.a) > m_lat.angularRadius) continue;
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
