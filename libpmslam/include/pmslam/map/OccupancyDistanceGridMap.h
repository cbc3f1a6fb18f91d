/* pmslam — an MRPT occupancy grid that keeps its distance map live.
 *
 * A mrpt::maps::COccupancyGridMap2D (so every MRPT tool can display, save and
 * load it) whose scan insertion also tracks which cells flip between "occupied"
 * and "not occupied" and forwards only those flips to a DynamicDistanceMap.
 * The Perfect Match aligner recognises this class and matches against the live
 * distance layer instead of rebuilding one.
 *
 * Occupancy model: log-odds per cell (MRPT stores the log-odds of being *free*,
 * 1/16 natural-log units); a hit adds occupancy evidence, a beam passing through
 * adds free evidence, each cell at most once per scan (hits win), and the
 * evidence is clamped so the map can still change when the world does. A cell
 * is an obstacle while its occupancy probability is above 0.5.
 *
 * Storage: the cells live in a SparseOccupancyGrid (blocks where scans touched),
 * on the distance layer's lattice: cell (i, j) covers [i·res, (i+1)·res) ×
 * [j·res, (j+1)·res). The dense COccupancyGridMap2D underneath is only a view,
 * filled by materialize() for MRPT code that reads it (getRawMap(), getCell(),
 * serialisation, CICP…) and then a snapshot until the next materialize(); it is
 * kept at one cell otherwise, so memory follows the area mapped. pmslam's own
 * writers read the sparse cells directly (io/MapExport).
 *
 * Serialising or cloning a materialised object through MRPT's RTTI yields a plain
 * COccupancyGridMap2D (the distance layer is derived data and is not saved).
 *
 * Frames and units: the map frame, metres; scans are inserted from a robot
 * pose (m, m, rad) in that frame with their points in the robot frame.
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/map/BlockMask.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/map/SparseOccupancyGrid.h>
#include <pmslam/sensor/ScanPoints.h>
#include <pmslam/util/ConfigKeys.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace pmslam
{
/** How scans update the grid; INI section [MappingApplication] keys of the same names. */
struct OccupancyGridUpdateOptions : public mrpt::config::CLoadableOptions
{
	double resolution = 0.05;  ///< cell side (m)
	double maxDistance = 0.5;  ///< distance-map truncation (m)
	double hitProbability = 0.7;  ///< inverse sensor model for a return
	double missProbability = 0.45;  ///< inverse sensor model for a beam passing through
	double clampProbability = 0.95;	 ///< evidence bound, both ways
	/** Free space stops this far (m) before each return (0 = up to the return's cell). A beam
	 * that ends on a wall seen at a grazing angle passes through the cells just in front of its
	 * end that hold the same wall; carving them makes walls flicker between scans. */
	double freeCarveMarginBeforeHit = 0.1;
	ScanPointsOptions scan;	 ///< min/max ranges and free-space carving of no-return beams

	/** Every INI key of this struct (ConfigKeys.h): loading, dumping and the documentation. */
	static const std::vector<config::Key<OccupancyGridUpdateOptions>>& keys();

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
	void dumpToTextStream(std::ostream& out) const override;
};

class OccupancyDistanceGridMap : public mrpt::maps::COccupancyGridMap2D
{
   public:
	using TUpdateOptions = OccupancyGridUpdateOptions;


	explicit OccupancyDistanceGridMap(const TUpdateOptions& opts = TUpdateOptions());

	const TUpdateOptions& updateOptions() const { return m_opts; }
	const DynamicDistanceMap& distanceMap() const { return m_distance; }
	/** The cells themselves (the truth; the COccupancyGridMap2D base is a view of them). */
	const SparseOccupancyGrid& cells() const { return m_cells; }

	/** Fills the COccupancyGridMap2D base with the cells (extent: the allocated blocks), for MRPT
	 * code that reads a dense grid. A snapshot: later insertions do not update it, the next call
	 * does (a call while the cells are unchanged since the last one does nothing). */
	void materialize();
	/** The lattice cells the dense view covers (inclusive): the allocated blocks, or the one cell at the
	 * origin of an empty map. materialize(), denseCopy() and the streamed map.gridmap.gz all use it. */
	void denseExtent(int& x0, int& y0, int& x1, int& y1) const;
	/** A plain MRPT grid holding the cells (the same extent as materialize()); this map is unchanged. */
	mrpt::maps::COccupancyGridMap2D denseCopy() const;
	/** Shrinks the base back to one cell (the memory of a materialize()). */
	void releaseMaterialized();
	/** Replaces the cells by those of a dense grid whose cell (0, 0) is lattice cell (offX, offY),
	 * and rebuilds the distance layer. */
	void assignCells(const mrpt::maps::COccupancyGridMap2D& grid, int offX, int offY);

	/** Inserts one scan (points in the robot frame) seen from robot pose `pose`
	 * (map frame). Returns how many cells flipped occupied/free. Points more than 1 km from the
	 * sensor are left out (a damaged reading: no planar lidar reaches that far); a non-finite
	 * pose or point throws std::invalid_argument before any cell changes. */
	std::size_t insertScan(const ScanPoints& scan, const mrpt::math::TPose2D& pose);

	/** Inserts many scans (a map rebuilt at corrected poses), in order: the same grid as one
	 * insertScan() each, with the distance layer computed once at the end. */
	void insertScans(const std::vector<std::pair<mrpt::math::TPose2D, const ScanPoints*>>& scans);

	/** The part of a map re-inserted after some of its scans moved (the loop closure):
	 * - addBlocksTouched(): the blocks (BlockMask coordinates) insertScan(scan, pose) would update;
	 * - insertScanWithin(): insertScan() restricted to the blocks of `only` (frozen), which are
	 *   the only ones allocated; builds a patch, whose distance layer is not kept;
	 * - replaceBlocks(): this map's cells of `blocks` become the patch's, and the distance layer
	 *   re-propagates around the cells that flipped, and only those. Returns how many flipped.
	 * A patch built from every scan that touches `blocks`, in their insertion order, replaces
	 * exactly the cells a map rebuilt from all its scans would have there. */
	void addBlocksTouched(const ScanPoints& scan, const mrpt::math::TPose2D& pose, BlockMask& blocks) const;
	void insertScanWithin(const ScanPoints& scan, const mrpt::math::TPose2D& pose, const BlockMask& only);
	std::size_t replaceBlocks(const OccupancyDistanceGridMap& patch, const BlockMask& blocks);
	/** The cells of `blocks` become those of `part` (a patch of other blocks of the same map, built
	 * beside this one); the distance layer is not touched (a patch keeps none). */
	void copyBlocks(const OccupancyDistanceGridMap& part, const BlockMask& blocks);

	/** True when cell (global index) is an obstacle in the binarised grid. */
	bool isOccupiedCell(int gx, int gy) const { return m_distance.isObstacle(gx, gy); }
	/** Global cell index of world coordinate v. */
	int worldToGlobalCell(double v) const { return m_distance.worldToCell(v); }

	/** True where no scan has said anything yet (a cell at the prior). */
	bool isUnexplored(double x, double y) const { return cellAt(x, y) == 0; }
	/** True where the scans say occupied more than free (the cells the distance layer has as obstacles). */
	bool isOccupied(double x, double y) const { return cellAt(x, y) < 0; }
	/** The fraction of `points` (robot frame) that land in unexplored cells seen from `pose`. */
	double unexploredFraction(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& pose) const;
	/** The fraction of `points` (robot frame, seen from `pose`) that land in cells observed free, farther
	 * than `margin` (m) from any obstacle: returns where the map saw nothing (a person, or a wrong pose). */
	double inFreeSpaceFraction(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& pose,
							   double margin) const;
	/** The fraction of the beams of `scan` seen from `pose` that pass through an obstacle cell before
	 * they end (each beam cut `margin` m short of its endpoint, so that the wall it hit does not
	 * count): a pose whose beams cross the map's walls cannot be where the scan was taken, however
	 * well its endpoints fit. Beams shorter than the margin are not counted; 0 without any. */
	double crossedWallFraction(const ScanPoints& scan, const mrpt::math::TPose2D& pose, double margin) const;
	/** The points (robot frame) that say something about a pose near `pose`: all but those that
	 * land in unexplored space more than two cells from any obstacle. Beyond the end of a mapped
	 * wall the distance map still pulls a point back towards the wall's end; along a corridor
	 * that pull is the only "information" the scan has, and it slides the robot backwards. */
	std::vector<std::size_t> informativePoints(const std::vector<mrpt::math::TPoint2Df>& points,
											   const mrpt::math::TPose2D& pose) const;  // indices into points

	/** Bytes held by the cells, the distance layer, the scratch buffers and any materialised view. */
	std::size_t memoryBytes() const;

	/** Rebuilds the distance layer from the grid contents (after loading a grid). */
	void rebuildDistanceMap();

   protected:
	bool internal_insertObservation(const mrpt::obs::CObservation& obs,
									const std::optional<const mrpt::poses::CPose3D>& robotPose) override;
	void internal_clear() override;

   private:
	/** The raw cell (log-odds of free) at world (x, y); 0 where never observed. */
	cellType cellAt(double x, double y) const
	{
		return m_cells.get(m_distance.worldToCell(x), m_distance.worldToCell(y));
	}
	// Applies one update to a cell (global index); forwards a flip to the distance map.
	void applyUpdate(int cx, int cy, SparseOccupancyGrid::Cell& cell, int delta);
	// Throws std::invalid_argument for a non-finite or absurd pose or point (before any cell changes).
	void checkScan(const ScanPoints& scan, const mrpt::math::TPose2D& pose) const;
	// The cell updates of one scan's insertion, in order (see the .cpp).
	template <class Touch, class Line>
	void rasterize(const ScanPoints& scan, const mrpt::math::TPose2D& pose, Touch&& touch, Line&& line) const;
	// insertScan() for the cells of the blocks keep(bx, by) accepts.
	template <class Keep>
	std::size_t insertKept(const ScanPoints& scan, const mrpt::math::TPose2D& pose, Keep&& keep);
	void shrinkBase();

	TUpdateOptions m_opts;
	SparseOccupancyGrid m_cells;
	DynamicDistanceMap m_distance;
	int m_hitDelta, m_missDelta, m_clamp;  // in MRPT log-odds units (free-positive)
	std::size_t m_flips = 0;
	bool m_deferDistance = false;  // insertScans(), insertScanWithin(): no distance updates per scan
	bool m_viewCurrent = false;  // the base holds the cells as they are (materialize() done since the last change)
};

}  // namespace pmslam
