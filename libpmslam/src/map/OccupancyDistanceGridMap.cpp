/* pmslam — occupancy grid with a live distance layer (see OccupancyDistanceGridMap.h). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace pmslam
{
namespace
{
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

void OccupancyGridUpdateOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
																   const std::string& s)
{
	resolution = c.read_double(s, "resolution", resolution);
	maxDistance = c.read_double(s, "maxDistance", maxDistance);
	hitProbability = c.read_double(s, "hitProbability", hitProbability);
	missProbability = c.read_double(s, "missProbability", missProbability);
	clampProbability = c.read_double(s, "clampProbability", clampProbability);
	joinHitsCloserThan = c.read_double(s, "joinHitsCloserThan", joinHitsCloserThan);
	freeCarveLength = c.read_double(s, "freeCarveLength", freeCarveLength);
	freeCarveMarginBeforeHit = c.read_double(s, "freeCarveMarginBeforeHit", freeCarveMarginBeforeHit);
	scan.minRange = c.read_double(s, "minRange", scan.minRange);
	scan.maxHitRange = c.read_double(s, "maxHitRange", scan.maxHitRange);
	scan.noReturnCarveRange = c.read_double(s, "noReturnCarveRange", scan.noReturnCarveRange);
}

void OccupancyGridUpdateOptions::dumpToTextStream(std::ostream& out) const
{
	out << "resolution = " << resolution << "\nmaxDistance = " << maxDistance
		<< "\nhitProbability = " << hitProbability << "\nmissProbability = " << missProbability
		<< "\nclampProbability = " << clampProbability << "\njoinHitsCloserThan = " << joinHitsCloserThan
		<< "\nfreeCarveLength = " << freeCarveLength
		<< "\nfreeCarveMarginBeforeHit = " << freeCarveMarginBeforeHit
		<< "\nminRange = " << scan.minRange
		<< "\nmaxHitRange = " << scan.maxHitRange << "\nnoReturnCarveRange = " << scan.noReturnCarveRange << "\n";
}

OccupancyDistanceGridMap::OccupancyDistanceGridMap(const TUpdateOptions& opts)
	: COccupancyGridMap2D(-10.f, 10.f, -10.f, 10.f, static_cast<float>(opts.resolution)),
	  m_opts(opts),
	  m_distance(opts.resolution, opts.maxDistance)
{
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

void OccupancyDistanceGridMap::internal_clear()
{
	COccupancyGridMap2D::internal_clear();
	// Keep the grid origin on a multiple of the resolution so grid cells and
	// distance-map cells are the same cells.
	const double r = getResolution();
	setSize(static_cast<float>(std::round(-10.0 / r) * r), static_cast<float>(std::round(10.0 / r) * r),
			static_cast<float>(std::round(-10.0 / r) * r), static_cast<float>(std::round(10.0 / r) * r),
			static_cast<float>(r), 0.5f);
	m_offX = static_cast<int>(std::lround(getXMin() / r));
	m_offY = static_cast<int>(std::lround(getYMin() / r));
	m_distance.clear();
	m_stamp.assign(std::size_t(getSizeX()) * getSizeY(), 0);
	m_scanId = 0;
}

void OccupancyDistanceGridMap::ensureContains(double xmin, double ymin, double xmax, double ymax)
{
	if (xmin >= getXMin() && ymin >= getYMin() && xmax < getXMax() && ymax < getYMax()) return;
	const double r = getResolution(), margin = 5.0;
	auto down = [r](double v) { return static_cast<float>(std::floor(v / r) * r); };
	auto up = [r](double v) { return static_cast<float>(std::ceil(v / r) * r); };
	const float nx0 = std::min<float>(getXMin(), down(xmin - margin));
	const float ny0 = std::min<float>(getYMin(), down(ymin - margin));
	const float nx1 = std::max<float>(getXMax(), up(xmax + margin));
	const float ny1 = std::max<float>(getYMax(), up(ymax + margin));
	resizeGrid(nx0, nx1, ny0, ny1, 0.5f, false);
	const int offX = static_cast<int>(std::lround(getXMin() / r)), offY = static_cast<int>(std::lround(getYMin() / r));
	if (std::abs(getXMin() - offX * r) > 1e-3 * r || std::abs(getYMin() - offY * r) > 1e-3 * r)
		throw std::logic_error("OccupancyDistanceGridMap: grid origin left the resolution lattice after resizing");
	m_offX = offX;
	m_offY = offY;
	m_stamp.assign(std::size_t(getSizeX()) * getSizeY(), 0);
}

void OccupancyDistanceGridMap::applyUpdate(int ix, int iy, int delta)
{
	cellType& cell = m_map[std::size_t(iy) * m_size_x + ix];
	const bool wasOccupied = cell < 0;
	const int v = std::clamp(int(cell) + delta, -m_clamp, m_clamp);
	cell = static_cast<cellType>(v);
	const bool occupied = v < 0;
	if (occupied == wasOccupied) return;
	++m_flips;
	if (m_deferDistance) return;
	if (occupied)
		m_distance.addObstacle(ix + m_offX, iy + m_offY);
	else
		m_distance.removeObstacle(ix + m_offX, iy + m_offY);
}

std::size_t OccupancyDistanceGridMap::insertScan(const ScanPoints& scan, const mrpt::math::TPose2D& pose)
{
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	auto toWorld = [&](double x, double y) { return std::pair<double, double>(pose.x + c * x - s * y, pose.y + s * x + c * y); };
	const auto [ox, oy] = toWorld(scan.sensorOrigin.x, scan.sensorOrigin.y);

	double x0 = ox, y0 = oy, x1 = ox, y1 = oy;
	auto grow = [&](const mrpt::math::TPoint2Df& p) {
		const auto [wx, wy] = toWorld(p.x, p.y);
		x0 = std::min(x0, wx);
		x1 = std::max(x1, wx);
		y0 = std::min(y0, wy);
		y1 = std::max(y1, wy);
	};
	for (const auto& p : scan.hits) grow(p);
	for (const auto& p : scan.freeEnds) grow(p);
	if (!std::isfinite(x0 + x1 + y0 + y1)) throw std::invalid_argument("OccupancyDistanceGridMap::insertScan: non-finite pose or point");
	ensureContains(x0, y0, x1, y1);

	if (++m_scanId == 0)
	{
		std::fill(m_stamp.begin(), m_stamp.end(), 0);
		m_scanId = 1;
	}
	m_flips = 0;
	const int sx = x2idx(ox), sy = y2idx(oy);
	auto cellOf = [&](const mrpt::math::TPoint2Df& p) {
		const auto [wx, wy] = toWorld(p.x, p.y);
		return std::pair<int, int>(x2idx(wx), y2idx(wy));
	};
	// Each cell is updated at most once per scan: the stamp says it was done.
	auto touch = [&](int x, int y, int delta) {
		auto& st = m_stamp[std::size_t(y) * m_size_x + x];
		if (st == m_scanId) return;
		st = m_scanId;
		applyUpdate(x, y, delta);
	};
	// Visits the cells of the Bresenham line from (x, y) to (ex, ey), the end excluded.
	auto line = [&](int x, int y, int ex, int ey, int delta) {
		const int dx = std::abs(ex - x), dy = -std::abs(ey - y);
		const int stepX = x < ex ? 1 : -1, stepY = y < ey ? 1 : -1;
		int err = dx + dy;
		while (x != ex || y != ey)
		{
			touch(x, y, delta);
			const int e2 = 2 * err;
			if (e2 >= dy)
			{
				err += dy;
				x += stepX;
			}
			if (e2 <= dx)
			{
				err += dx;
				y += stepY;
			}
		}
	};
	// Hits first, so a cell that is both hit and crossed in this scan counts as hit.
	const double join2 = m_opts.joinHitsCloserThan * m_opts.joinHitsCloserThan;
	for (std::size_t i = 0; i < scan.hits.size(); ++i)
	{
		const auto [ix, iy] = cellOf(scan.hits[i]);
		touch(ix, iy, m_hitDelta);
		if (i > 0 && join2 > 0)
		{
			const auto& a = scan.hits[i - 1];
			const auto& b = scan.hits[i];
			if (double(a.x - b.x) * (a.x - b.x) + double(a.y - b.y) * (a.y - b.y) < join2)
			{
				const auto [jx, jy] = cellOf(a);
				line(jx, jy, ix, iy, m_hitDelta);
			}
		}
	}
	// Free space: every cell a beam crosses before its endpoint, or only the last
	// freeCarveLength metres of it (the cells near the robot are crossed by many beams;
	// a long beam adds little there but costs a cell visit per 5 cm).
	const double carve = m_opts.freeCarveLength, margin = m_opts.freeCarveMarginBeforeHit;
	// Carves from the sensor (or freeCarveLength before the end) to `stopShort` metres
	// before point p.
	auto carveTo = [&](const mrpt::math::TPoint2Df& p, double stopShort) {
		const double dx = double(p.x) - scan.sensorOrigin.x, dy = double(p.y) - scan.sensorOrigin.y;
		const double len = std::hypot(dx, dy);
		// The cell `back` metres before p on the beam.
		auto cellBefore = [&](double back) {
			const double t = 1.0 - back / len;
			const auto [wx, wy] = toWorld(scan.sensorOrigin.x + t * dx, scan.sensorOrigin.y + t * dy);
			return std::pair<int, int>(x2idx(wx), y2idx(wy));
		};
		if (stopShort > 0 && (len <= stopShort || (carve > 0 && carve <= stopShort))) return;  // nothing left
		const auto [ex, ey] = stopShort > 0 ? cellBefore(stopShort) : cellOf(p);
		const auto [fx, fy] = carve > 0 && len > carve ? cellBefore(carve) : std::pair<int, int>(sx, sy);
		line(fx, fy, ex, ey, m_missDelta);
	};
	// A beam that ends on a wall seen at a grazing angle crosses the cells just in front of
	// its endpoint that hold that same wall: stopping the carving short keeps such walls solid.
	for (const auto& p : scan.hits) carveTo(p, margin);
	for (const auto& p : scan.freeEnds) carveTo(p, 0.0);
	if (!m_deferDistance) m_distance.update();
	m_is_empty = false;
	return m_flips;
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
	const double r = getResolution();
	m_offX = static_cast<int>(std::lround(getXMin() / r));
	m_offY = static_cast<int>(std::lround(getYMin() / r));
	for (unsigned iy = 0; iy < getSizeY(); ++iy)
		for (unsigned ix = 0; ix < getSizeX(); ++ix)
			if (m_map[std::size_t(iy) * m_size_x + ix] < 0) m_distance.addObstacle(int(ix) + m_offX, int(iy) + m_offY);
	m_distance.update();
	m_stamp.assign(std::size_t(getSizeX()) * getSizeY(), 0);
}

std::size_t OccupancyDistanceGridMap::memoryBytes() const
{
	return m_map.capacity() * sizeof(cellType) + m_stamp.capacity() * sizeof(m_stamp[0]) + m_distance.memoryBytes();
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
		const cellType* cell = cellAt(wx, wy);
		if (!cell || *cell <= 0) continue;	// outside, unexplored or occupied
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

}  // namespace pmslam
