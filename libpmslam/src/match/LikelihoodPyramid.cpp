/* pmslam — max-pooled likelihood pyramid (see LikelihoodPyramid.h). */
#include <pmslam/match/LikelihoodPyramid.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <cmath>
#include <stdexcept>

namespace pmslam
{
namespace
{
LikelihoodPyramid::CellWindow wholeExtent(const DynamicDistanceMap& map)
{
	LikelihoodPyramid::CellWindow w;
	if (!map.touchedBounds(w.minX, w.minY, w.maxX, w.maxY)) w = {0, 0, 0, 0};
	return w;
}
}  // namespace

LikelihoodPyramid::LikelihoodPyramid(const DynamicDistanceMap& map, const Options& options)
	: LikelihoodPyramid(map, wholeExtent(map), options)
{
}

LikelihoodPyramid::LikelihoodPyramid(const DynamicDistanceMap& map, const CellWindow& window, const Options& options)
	: m_options(options), m_resolution(map.resolution()), m_maxDistance(map.maxDistance()), m_window(window)
{
	if (window.width() < 1 || window.height() < 1) throw std::invalid_argument("LikelihoodPyramid: empty window");
	if (options.levels < 1 || options.levels > 16)
		throw std::invalid_argument("LikelihoodPyramid: levels must be in [1, 16]");
	if (!(options.sigma > 0)) throw std::invalid_argument("LikelihoodPyramid: sigma must be positive");
	m_levels.resize(std::size_t(options.levels));
	buildLevel0(map);
	for (int h = 1; h < options.levels; ++h) buildLevel(h);
}

LikelihoodPyramid LikelihoodPyramid::fromGrid(const mrpt::maps::COccupancyGridMap2D& grid, double maxDistance,
											  double occupiedThreshold, const Options& options)
{
	// The same distance layer (and the same cell lattice) as PerfectMatchAligner::distanceLayerFor.
	const DynamicDistanceMap dm = PerfectMatchMatcher::distanceMapFromGrid(grid, maxDistance, occupiedThreshold);
	const double r = grid.getResolution();
	CellWindow w;
	w.minX = int(std::lround(grid.getXMin() / r));
	w.minY = int(std::lround(grid.getYMin() / r));
	w.maxX = w.minX + int(grid.getSizeX()) - 1;
	w.maxY = w.minY + int(grid.getSizeY()) - 1;
	LikelihoodPyramid p(dm, w, options);
	p.m_offset = {grid.getXMin() - w.minX * r, grid.getYMin() - w.minY * r};
	return p;
}

LikelihoodPyramid LikelihoodPyramid::coarsened(int factor, int dilation, int levels) const
{
	if (factor < 1 || dilation < 0) throw std::invalid_argument("LikelihoodPyramid::coarsened: bad factor or dilation");
	if (levels < 1 || levels > 16) throw std::invalid_argument("LikelihoodPyramid: levels must be in [1, 16]");
	LikelihoodPyramid c;
	c.m_options = m_options;
	c.m_options.levels = levels;
	c.m_resolution = m_resolution * factor;
	c.m_maxDistance = m_maxDistance;
	c.m_offset = m_offset;
	auto down = [&](int v) { return int(std::floor(double(v) / factor)); };
	c.m_window = {down(m_window.minX), down(m_window.minY), down(m_window.maxX), down(m_window.maxY)};
	c.m_levels.resize(std::size_t(levels));
	Level& l = c.m_levels[0];
	l.x0 = c.m_window.minX - 1;
	l.y0 = c.m_window.minY - 1;
	l.width = c.m_window.width() + 2;
	l.height = c.m_window.height() + 2;
	l.cells.assign(std::size_t(l.width) * std::size_t(l.height), 0);
	// Separable: first the max along x over each coarse column's span of every fine row, then
	// along y. The padding border stays 0, as every level's must (a clamped look-up far outside
	// the map lands on it).
	const Level& f = m_levels[0];
	const int span = factor + 2 * dilation;
	std::vector<uint8_t> rows(std::size_t(l.width) * std::size_t(f.height), 0);
	for (int y = 0; y < f.height; ++y)
	{
		const uint8_t* in = &f.cells[std::size_t(y) * std::size_t(f.width)];
		uint8_t* out = &rows[std::size_t(y) * std::size_t(l.width)];
		for (int x = 1; x + 1 < l.width; ++x)
		{
			const int start = (l.x0 + x) * factor - dilation - f.x0;
			uint8_t m = 0;
			for (int k = std::max(0, start); k < std::min(f.width, start + span); ++k) m = std::max(m, in[k]);
			out[x] = m;
		}
	}
	for (int y = 1; y + 1 < l.height; ++y)
	{
		const int start = (l.y0 + y) * factor - dilation - f.y0;
		uint8_t* out = &l.cells[std::size_t(y) * std::size_t(l.width)];
		for (int k = std::max(0, start); k < std::min(f.height, start + span); ++k)
		{
			const uint8_t* in = &rows[std::size_t(k) * std::size_t(l.width)];
			for (int x = 0; x < l.width; ++x) out[x] = std::max(out[x], in[x]);
		}
	}
	for (int h = 1; h < levels; ++h) c.buildLevel(h);
	return c;
}

int LikelihoodPyramid::quantise(double d) const
{
	// Rescaled so that the truncation scores 0: a point in unknown or empty space adds nothing,
	// and all 256 levels are spent on the part of the curve that tells poses apart.
	const double s2 = m_options.sigma * m_options.sigma;
	const double far = s2 / (s2 + m_maxDistance * m_maxDistance);
	const double l = s2 / (s2 + d * d);
	return std::clamp(int(std::lround(kMaxValue * (l - far) / (1 - far))), 0, kMaxValue);
}

void LikelihoodPyramid::buildLevel0(const DynamicDistanceMap& map)
{
	// One zero cell of padding on each side, so that a clamped look-up outside answers 0.
	Level& l = m_levels[0];
	l.x0 = m_window.minX - 1;
	l.y0 = m_window.minY - 1;
	l.width = m_window.width() + 2;
	l.height = m_window.height() + 2;
	l.cells.assign(std::size_t(l.width) * std::size_t(l.height), 0);
	// Squared distances in cells are small integers: tabulate the likelihood once.
	std::vector<uint8_t> lut(std::size_t(map.maxSquaredCells()) + 1);
	for (std::size_t sq = 0; sq < lut.size(); ++sq) lut[sq] = uint8_t(quantise(std::sqrt(double(sq)) * m_resolution));
	for (int cy = m_window.minY; cy <= m_window.maxY; ++cy)
	{
		uint8_t* row = &l.cells[std::size_t(cy - l.y0) * std::size_t(l.width)];
		for (int cx = m_window.minX; cx <= m_window.maxX; ++cx)
		{
			const int sq = map.squaredDistanceCells(cx, cy);
			row[cx - l.x0] = sq < 0 ? 0 : lut[std::size_t(sq)];
		}
	}
}

void LikelihoodPyramid::buildLevel(int h)
{
	// Level h from level h-1: a 2^h window is four 2^(h-1) windows, s = 2^(h-1) apart. Level h
	// starts 2^h cells before the window (a window starting there still reaches the map's first
	// cell) and ends one cell after it (all zero from there on).
	const Level& prev = m_levels[std::size_t(h - 1)];
	Level& l = m_levels[std::size_t(h)];
	const int s = 1 << (h - 1);
	l.x0 = m_window.minX - (1 << h);
	l.y0 = m_window.minY - (1 << h);
	l.width = m_window.width() + (1 << h) + 1;
	l.height = m_window.height() + (1 << h) + 1;
	l.cells.resize(std::size_t(l.width) * std::size_t(l.height));
	// Column indices into prev's rows, clamped: prev's first and last columns are zero, like
	// everything beyond them.
	std::vector<int> ia(std::size_t(l.width)), ib(std::size_t(l.width));
	for (int x = 0; x < l.width; ++x)
	{
		ia[std::size_t(x)] = std::clamp(l.x0 + x - prev.x0, 0, prev.width - 1);
		ib[std::size_t(x)] = std::clamp(l.x0 + x + s - prev.x0, 0, prev.width - 1);
	}
	auto rowOf = [&](int cy) {
		return &prev.cells[std::size_t(std::clamp(cy - prev.y0, 0, prev.height - 1)) * std::size_t(prev.width)];
	};
	for (int y = 0; y < l.height; ++y)
	{
		const uint8_t* ra = rowOf(l.y0 + y);
		const uint8_t* rb = rowOf(l.y0 + y + s);
		uint8_t* out = &l.cells[std::size_t(y) * std::size_t(l.width)];
		for (int x = 0; x < l.width; ++x)
		{
			const std::size_t a = std::size_t(ia[std::size_t(x)]), b = std::size_t(ib[std::size_t(x)]);
			out[x] = std::max(std::max(ra[a], ra[b]), std::max(rb[a], rb[b]));
		}
	}
}

std::size_t LikelihoodPyramid::memoryBytes() const
{
	std::size_t bytes = 0;
	for (const Level& l : m_levels) bytes += l.cells.capacity();
	return bytes;
}

}  // namespace pmslam
