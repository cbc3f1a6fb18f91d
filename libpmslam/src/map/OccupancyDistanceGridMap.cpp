/* pmslam — occupancy grid with a live distance layer (see OccupancyDistanceGridMap.h). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <pmslam/map/GridLine.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/map/WallCrossing.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace pmslam
{
namespace
{
constexpr double kMaxBeamLength = 1000.0;  // m; see insertScan

// MRPT stores 1/16 natural-log units of the log-odds of a cell being free.
int freeLogOddsUnits(double pFree)
{
	return static_cast<int>(std::lround(16.0 * std::log(pFree / (1.0 - pFree))));
}

void requireProbability(double p, const char* key)
{
	if (!(p > 0.0 && p < 1.0))
		throw std::invalid_argument(std::string("OccupancyDistanceGridMap: ") + key + " must be in (0,1), got " +
									std::to_string(p));
}
}  // namespace

OccupancyDistanceGridMap::OccupancyDistanceGridMap(const TUpdateOptions& opts)
	: COccupancyGridMap2D(0.f, static_cast<float>(opts.resolution), 0.f, static_cast<float>(opts.resolution),
						  static_cast<float>(opts.resolution)),
	  m_opts(opts),
	  m_distance(opts.resolution, opts.maxDistance)
{
	static_assert(sizeof(cellType) == sizeof(SparseOccupancyGrid::Cell), "MRPT built with 8-bit occupancy cells");
	requireProbability(opts.hitProbability, "hitProbability");
	requireProbability(opts.missProbability, "missProbability");
	requireProbability(opts.clampProbability, "clampProbability");
	if (opts.hitProbability <= 0.5 || opts.missProbability >= 0.5 || opts.clampProbability <= 0.5)
		throw std::invalid_argument(
			"OccupancyDistanceGridMap: need hitProbability > 0.5, missProbability < 0.5, clampProbability > 0.5");
	m_hitDelta = -std::max(1, -freeLogOddsUnits(1.0 - opts.hitProbability));  // occupancy evidence lowers the cell
	m_missDelta = std::max(1, freeLogOddsUnits(1.0 - opts.missProbability));
	m_clamp = std::min<int>(OCCGRID_CELLTYPE_MAX, std::max(1, freeLogOddsUnits(opts.clampProbability)));
	internal_clear();
}

void OccupancyDistanceGridMap::shrinkBase()
{
	// The dense view at its smallest: one cell at the origin.
	const float r = static_cast<float>(m_opts.resolution);
	setSize(0.f, r, 0.f, r, r, 0.5f);
	m_map.shrink_to_fit();
	m_viewCurrent = false;
}

void OccupancyDistanceGridMap::internal_clear()
{
	COccupancyGridMap2D::internal_clear();
	shrinkBase();
	m_cells.clear();
	m_distance.clear();
}

void OccupancyDistanceGridMap::releaseMaterialized() { shrinkBase(); }

namespace
{
// Sizes `grid` to the extent (edges on the lattice: grid cell (ix, iy) is lattice cell
// (x0 + ix, y0 + iy)) and copies the cells in.
void fillDense(const SparseOccupancyGrid& cells, double r, int x0, int y0, int x1, int y1,
			   mrpt::maps::COccupancyGridMap2D& grid)
{
	grid.setSize(static_cast<float>(x0 * r), static_cast<float>((x1 + 1) * r), static_cast<float>(y0 * r),
				 static_cast<float>((y1 + 1) * r), static_cast<float>(r), 0.5f);
	const int sx = int(grid.getSizeX()), sy = int(grid.getSizeY());
	if (sx != x1 - x0 + 1 || sy != y1 - y0 + 1)
		throw std::logic_error("OccupancyDistanceGridMap: MRPT sized the dense grid differently");
	for (int iy = 0; iy < sy; ++iy) cells.readRow(y0 + iy, x0, sx, grid.getRow(iy));
}
}  // namespace

void OccupancyDistanceGridMap::denseExtent(int& x0, int& y0, int& x1, int& y1) const
{
	if (!m_cells.allocatedBounds(x0, y0, x1, y1)) x0 = y0 = x1 = y1 = 0;
}

void OccupancyDistanceGridMap::materialize()
{
	// A builder's getCurrentlyBuiltMetricMap() may be called after every scan, and most scans are
	// not inserted: the view is refilled only when the cells changed.
	if (m_viewCurrent) return;
	int x0, y0, x1, y1;
	denseExtent(x0, y0, x1, y1);
	fillDense(m_cells, m_opts.resolution, x0, y0, x1, y1, *this);
	m_is_empty = m_cells.blockCount() == 0;
	m_viewCurrent = true;
}

mrpt::maps::COccupancyGridMap2D OccupancyDistanceGridMap::denseCopy() const
{
	mrpt::maps::COccupancyGridMap2D g;
	g.insertionOptions = insertionOptions;
	g.likelihoodOptions = likelihoodOptions;
	int x0, y0, x1, y1;
	denseExtent(x0, y0, x1, y1);
	fillDense(m_cells, m_opts.resolution, x0, y0, x1, y1, g);
	return g;
}

void OccupancyDistanceGridMap::assignCells(const mrpt::maps::COccupancyGridMap2D& grid, int offX, int offY)
{
	m_cells.clear();
	const auto& raw = grid.getRawMap();
	const unsigned sx = grid.getSizeX(), sy = grid.getSizeY();
	for (unsigned iy = 0; iy < sy; ++iy)
		for (unsigned ix = 0; ix < sx; ++ix)
			if (const auto c = raw[std::size_t(iy) * sx + ix]; c != 0) m_cells.at(int(ix) + offX, int(iy) + offY) = c;
	m_is_empty = false;
	m_viewCurrent = false;
	rebuildDistanceMap();
}

void OccupancyDistanceGridMap::applyUpdate(int cx, int cy, SparseOccupancyGrid::Cell& cell, int delta)
{
	const bool wasOccupied = cell < 0;
	const int v = std::clamp(int(cell) + delta, -m_clamp, m_clamp);
	cell = static_cast<cellType>(v);
	const bool occupied = v < 0;
	if (occupied == wasOccupied) return;
	++m_flips;
	if (m_deferDistance) return;
	if (occupied)
		m_distance.addObstacle(cx, cy);
	else
		m_distance.removeObstacle(cx, cy);
}

void OccupancyDistanceGridMap::checkScan(const ScanPoints& scan, const mrpt::math::TPose2D& pose) const
{
	// Every point checked before any cell changes: a bad scan leaves the map as it was.
	// Beyond ±10^7 cells (500 km at 5 cm) a coordinate is garbage, not a map.
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	const double limit = 1e7 * m_opts.resolution;
	auto valid = [&](double x, double y) {
		const double wx = pose.x + c * x - s * y, wy = pose.y + s * x + c * y;
		return std::abs(wx) < limit && std::abs(wy) < limit;
	};
	bool ok = valid(scan.sensorOrigin.x, scan.sensorOrigin.y);
	for (const auto* pts : {&scan.hits, &scan.freeEnds})
		for (const auto& p : *pts) ok = ok && valid(p.x, p.y);
	if (!ok) throw std::invalid_argument("OccupancyDistanceGridMap::insertScan: non-finite or absurd pose or point");
}

template <class Touch, class Line>
void OccupancyDistanceGridMap::rasterize(const ScanPoints& scan, const mrpt::math::TPose2D& pose, Touch&& touch,
										 Line&& line) const
{
	// The cell updates of one scan, in order: touch(cx, cy, delta) for a cell, line(x, y, ex, ey, delta)
	// for the cells of a Bresenham line (the end excluded). The callers visit each cell once per scan.
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	auto toWorld = [&](double x, double y) { return std::pair<double, double>(pose.x + c * x - s * y, pose.y + s * x + c * y); };
	auto cellIndex = [&](double wx, double wy) {
		return std::pair<int, int>(m_distance.worldToCell(wx), m_distance.worldToCell(wy));
	};
	const auto [ox, oy] = toWorld(scan.sensorOrigin.x, scan.sensorOrigin.y);
	const std::pair<int, int> sensorCell = cellIndex(ox, oy);
	const int sx = sensorCell.first, sy = sensorCell.second;  // plain ints: lambdas below capture them
	auto cellOf = [&](const mrpt::math::TPoint2Df& p) {
		const auto [wx, wy] = toWorld(p.x, p.y);
		return cellIndex(wx, wy);
	};
	// No planar lidar sees a kilometre: a longer beam is a damaged reading, and would cost a
	// cell visit and a block per 5 cm / 1.6 m of it.
	// (The squared length decides all but a hair's breadth around the limit, where std::hypot does as
	// before: hypot is dear, and this runs for every beam of every keyframe of every local map.)
	auto tooFar = [&](const mrpt::math::TPoint2Df& p) {
		const double dx = double(p.x) - scan.sensorOrigin.x, dy = double(p.y) - scan.sensorOrigin.y;
		const double d2 = dx * dx + dy * dy;
		constexpr double kBelow = kMaxBeamLength * kMaxBeamLength * (1 - 1e-9), kAbove = kMaxBeamLength * kMaxBeamLength * (1 + 1e-9);
		if (d2 < kBelow) return false;
		if (d2 > kAbove) return true;
		return std::hypot(dx, dy) > kMaxBeamLength;
	};
	// Hits first, so a cell that is both hit and crossed in this scan counts as hit.
	for (const auto& p : scan.hits)
		if (!tooFar(p))
		{
			const auto [ix, iy] = cellOf(p);
			touch(ix, iy, m_hitDelta);
		}
	// Free space: every cell a beam crosses from the sensor to `stopShort` metres before point p.
	const double margin = m_opts.freeCarveMarginBeforeHit;
	auto carveTo = [&](const mrpt::math::TPoint2Df& p, double stopShort) {
		const double dx = double(p.x) - scan.sensorOrigin.x, dy = double(p.y) - scan.sensorOrigin.y;
		const double len = std::hypot(dx, dy);
		// The cell `back` metres before p on the beam.
		auto cellBefore = [&](double back) {
			const double t = 1.0 - back / len;
			const auto [wx, wy] = toWorld(scan.sensorOrigin.x + t * dx, scan.sensorOrigin.y + t * dy);
			return cellIndex(wx, wy);
		};
		if (stopShort > 0 && len <= stopShort) return;	// nothing left
		const auto [ex, ey] = stopShort > 0 ? cellBefore(stopShort) : cellOf(p);
		line(sx, sy, ex, ey, m_missDelta);
	};
	// A beam that ends on a wall seen at a grazing angle crosses the cells just in front of
	// its endpoint that hold that same wall: stopping the carving short keeps such walls solid.
	for (const auto& p : scan.hits)
		if (!tooFar(p)) carveTo(p, margin);
	for (const auto& p : scan.freeEnds)
		if (!tooFar(p)) carveTo(p, 0.0);
}

template <class Keep>
std::size_t OccupancyDistanceGridMap::insertKept(const ScanPoints& scan, const mrpt::math::TPose2D& pose, Keep&& keep)
{
	checkScan(scan, pose);
	m_cells.beginPass();
	m_flips = 0;
	using Blocks = SparseOccupancyGrid::Blocks;
	// Each cell is updated at most once per scan.
	rasterize(
		scan, pose,
		[&](int x, int y, int delta) {
			if (!keep(Blocks::blockOf(x), Blocks::blockOf(y))) return;
			if (SparseOccupancyGrid::Cell* cell = m_cells.visitOnce(x, y)) applyUpdate(x, y, *cell, delta);
		},
		[&](int x, int y, int ex, int ey, int delta) {
			m_cells.visitLineOnceWithin(x, y, ex, ey, keep, [&](int cx, int cy, SparseOccupancyGrid::Cell& cell) {
				applyUpdate(cx, cy, cell, delta);
			});
		});
	if (!m_deferDistance) m_distance.update();
	m_is_empty = false;
	m_viewCurrent = false;
	return m_flips;
}

std::size_t OccupancyDistanceGridMap::insertScan(const ScanPoints& scan, const mrpt::math::TPose2D& pose)
{
	return insertKept(scan, pose, [](int, int) { return true; });
}

void OccupancyDistanceGridMap::insertScanWithin(const ScanPoints& scan, const mrpt::math::TPose2D& pose,
												const BlockMask& only)
{
	m_deferDistance = true;
	insertKept(scan, pose, [&only](int bx, int by) { return only.contains(bx, by); });
	m_deferDistance = false;
}

void OccupancyDistanceGridMap::addBlocksTouched(const ScanPoints& scan, const mrpt::math::TPose2D& pose,
												BlockMask& blocks) const
{
	checkScan(scan, pose);
	using Blocks = SparseOccupancyGrid::Blocks;
	// A beam stays in one block for up to 32 cells: only a change of block is worth adding (the mask
	// would skip the repeats too, at a call per cell).
	int lastX = std::numeric_limits<int>::min(), lastY = lastX;
	const auto add = [&](int cx, int cy) {
		const int bx = Blocks::blockOf(cx), by = Blocks::blockOf(cy);
		if (bx == lastX && by == lastY) return;
		lastX = bx, lastY = by;
		blocks.add(bx, by);
	};
	rasterize(
		scan, pose, [&](int x, int y, int) { add(x, y); },
		[&](int x, int y, int ex, int ey, int) {
			forEachCellOnLine(x, y, ex, ey, [&](int cx, int cy) {
				add(cx, cy);
				return true;
			});
		});
}

std::size_t OccupancyDistanceGridMap::replaceBlocks(const OccupancyDistanceGridMap& patch, const BlockMask& blocks)
{
	// Only the cells whose occupied state flips reach the distance layer, which re-propagates
	// around them alone (the dynamic brushfire), as after a scan.
	if (patch.m_opts.resolution != m_opts.resolution)
		throw std::invalid_argument("OccupancyDistanceGridMap::replaceBlocks: the patch has another resolution");
	using Blocks = SparseOccupancyGrid::Blocks;
	constexpr int S = Blocks::kSide;
	std::size_t flips = 0;
	int row = 0;
	bool first = true;
	blocks.forEach([&](int bx, int by) {
		// One row of blocks at a time: the brushfire's queue then holds a row's changes, not those
		// of a whole loop that moved.
		if (!first && by != row) m_distance.update();
		first = false;
		row = by;
		const SparseOccupancyGrid::Cell* from = patch.m_cells.blockCells(bx, by);
		const SparseOccupancyGrid::Cell* now = m_cells.blockCells(bx, by);
		if (!from && !now) return;
		SparseOccupancyGrid::Cell* to = m_cells.obtainBlockCells(bx, by);
		for (int i = 0; i < S * S; ++i)
		{
			const SparseOccupancyGrid::Cell v = from ? from[i] : SparseOccupancyGrid::Cell(0);
			if (v == to[i]) continue;
			const bool was = to[i] < 0, is = v < 0;
			to[i] = v;
			if (was == is) continue;
			++flips;
			const int cx = bx * S + (i & (S - 1)), cy = by * S + (i >> Blocks::kShift);
			if (is)
				m_distance.addObstacle(cx, cy);
			else
				m_distance.removeObstacle(cx, cy);
		}
		// No scan reaches this block any more (a moved scan's old place): it is unobserved again.
		if (!from) m_cells.releaseBlock(bx, by);
	});
	m_distance.update();
	// The distance layer's blocks there, and around them as far as the truncation reaches, that no
	// obstacle is near any more.
	const int reach = static_cast<int>(std::ceil(m_opts.maxDistance / m_opts.resolution / S)) + 1;
	BlockMask around;
	blocks.forEach([&](int bx, int by) {
		for (int dy = -reach; dy <= reach; ++dy)
			for (int dx = -reach; dx <= reach; ++dx) around.add(bx + dx, by + dy);
	});
	around.forEach([&](int bx, int by) { m_distance.releaseIfFar(bx, by); });
	m_viewCurrent = false;
	return flips;
}

void OccupancyDistanceGridMap::copyBlocks(const OccupancyDistanceGridMap& part, const BlockMask& blocks)
{
	if (part.m_opts.resolution != m_opts.resolution)
		throw std::invalid_argument("OccupancyDistanceGridMap::copyBlocks: the part has another resolution");
	constexpr int N = SparseOccupancyGrid::Blocks::kSide * SparseOccupancyGrid::Blocks::kSide;
	blocks.forEach([&](int bx, int by) {
		if (const SparseOccupancyGrid::Cell* from = part.m_cells.blockCells(bx, by))
			std::copy(from, from + N, m_cells.obtainBlockCells(bx, by));
		else
			m_cells.releaseBlock(bx, by);
	});
	m_is_empty = m_cells.blockCount() == 0;
	m_viewCurrent = false;
}

bool OccupancyDistanceGridMap::internal_insertObservation(const mrpt::obs::CObservation& obs,
														   const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
	const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs);
	if (!scan) return false;  // only planar range scans feed the distance layer
	mrpt::math::TPose2D pose(0, 0, 0);
	if (robotPose) pose = mrpt::poses::CPose2D(*robotPose).asTPose();
	insertScan(scanToPoints(*scan, m_opts.scan), pose);
	return true;
}

void OccupancyDistanceGridMap::insertScans(const std::vector<std::pair<mrpt::math::TPose2D, const ScanPoints*>>& scans)
{
	// The distance layer once at the end: propagating every flip of every scan would redo the
	// same cells many times over.
	m_deferDistance = true;
	for (const auto& [pose, scan] : scans) insertScan(*scan, pose);
	m_deferDistance = false;
	rebuildDistanceMap();
}

void OccupancyDistanceGridMap::rebuildDistanceMap()
{
	m_distance.clear();
	// One row of blocks at a time: the brushfire's queue then holds a row's cells, not the map's
	// (the layer is the same: adding obstacles to a propagated layer is what update() is for).
	int row = 0;
	bool first = true;
	m_cells.forEachObserved([&](int cx, int cy, SparseOccupancyGrid::Cell v) {
		const int r = cy >> SparseOccupancyGrid::Blocks::kShift;
		if (!first && r != row) m_distance.update();
		row = r;
		first = false;
		if (v < 0) m_distance.addObstacle(cx, cy);
	});
	m_distance.update();
}

std::size_t OccupancyDistanceGridMap::memoryBytes() const
{
	return m_map.capacity() * sizeof(cellType) + m_cells.memoryBytes() + m_distance.memoryBytes();
}

double OccupancyDistanceGridMap::inFreeSpaceFraction(const std::vector<mrpt::math::TPoint2Df>& points,
													  const mrpt::math::TPose2D& pose, double margin) const
{
	if (points.empty()) return 0.0;
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	std::size_t n = 0;
	for (const auto& p : points)
	{
		const double wx = pose.x + c * p.x - s * p.y, wy = pose.y + s * p.x + c * p.y;
		if (cellAt(wx, wy) <= 0) continue;	// unexplored or occupied
		if (m_distance.cellDistance(m_distance.worldToCell(wx), m_distance.worldToCell(wy)) > margin) ++n;
	}
	return double(n) / double(points.size());
}

std::vector<std::size_t> OccupancyDistanceGridMap::informativePoints(const std::vector<mrpt::math::TPoint2Df>& points,
																	 const mrpt::math::TPose2D& pose) const
{
	std::vector<std::size_t> out;
	out.reserve(points.size());
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	const float nearObstacle = static_cast<float>(2 * getResolution());
	for (std::size_t i = 0; i < points.size(); ++i)
	{
		const auto& p = points[i];
		const double wx = pose.x + c * p.x - s * p.y, wy = pose.y + s * p.x + c * p.y;
		if (!std::isfinite(wx) || !std::isfinite(wy)) continue;
		if (isUnexplored(wx, wy) &&
			m_distance.cellDistance(m_distance.worldToCell(wx), m_distance.worldToCell(wy)) > nearObstacle)
			continue;
		out.push_back(i);
	}
	return out;
}

double OccupancyDistanceGridMap::unexploredFraction(const std::vector<mrpt::math::TPoint2Df>& points,
													const mrpt::math::TPose2D& pose) const
{
	if (points.empty()) return 0.0;
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	std::size_t n = 0;
	for (const auto& p : points) n += isUnexplored(pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y);
	return double(n) / double(points.size());
}

double OccupancyDistanceGridMap::crossedWallFraction(const ScanPoints& scan, const mrpt::math::TPose2D& pose,
												   double margin) const
{
	return crossedObstacleFraction(m_distance, scan, pose, margin);
}

}  // namespace pmslam
