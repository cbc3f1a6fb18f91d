/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * DynamicDistanceMap: a truncated Euclidean distance map over an unbounded grid
 * of square cells, updated incrementally when cells become occupied or free.
 *
 * Algorithm: the dynamic brushfire of Lau, Sprunk and Burgard ("Efficient
 * grid-based spatial representations for robot navigation in dynamic
 * environments", RAS 2013). Each cell remembers which obstacle cell is nearest;
 * adding an obstacle sends a "lower" wave, removing one sends a "raise" wave that
 * invalidates the cells that pointed at it, and both stop where nothing changes
 * or where the truncation distance is reached. Only cells whose nearest obstacle
 * changes are touched.
 *
 * Frames and units: cell (i, j) covers [i·res, (i+1)·res) × [j·res, (j+1)·res)
 * in the map frame (metres); its distance sample sits at the cell centre.
 * Cell indices are global and may be negative: the map has no fixed extent.
 * Storage is allocated in square blocks only where a distance below the
 * truncation has been written, so memory grows with the area actually mapped.
 */
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace pmslam
{
class DynamicDistanceMap
{
   public:
	/** resolution: cell side in metres; maxDistance: truncation in metres
	 * (queries never answer more than this). */
	explicit DynamicDistanceMap(double resolution = 0.05, double maxDistance = 0.5);
	~DynamicDistanceMap();
	DynamicDistanceMap(DynamicDistanceMap&&) noexcept;
	DynamicDistanceMap& operator=(DynamicDistanceMap&&) noexcept;
	DynamicDistanceMap(const DynamicDistanceMap&) = delete;
	DynamicDistanceMap& operator=(const DynamicDistanceMap&) = delete;

	double resolution() const { return m_resolution; }
	double maxDistance() const { return m_maxDistance; }
	/** Truncation as a squared distance in cells: stored squared distances never exceed it. */
	int maxSquaredCells() const { return m_maxSq; }

	/** Queue a change; nothing is propagated until update(). Idempotent. */
	void addObstacle(int cx, int cy);
	void removeObstacle(int cx, int cy);
	/** Propagate all queued changes. Returns the number of cells processed. */
	std::size_t update();
	/** Forget everything (keeps resolution and truncation). */
	void clear();

	bool isObstacle(int cx, int cy) const;
	/** Squared distance in cells to the nearest obstacle, or -1 when it is beyond the truncation. */
	int squaredDistanceCells(int cx, int cy) const;
	/** Distance in metres from the centre of cell (cx, cy), truncated at maxDistance(). */
	float cellDistance(int cx, int cy) const;

	/** Distance (metres) at a world point by bilinear interpolation of the 4
	 * surrounding cell-centre samples, with its analytic gradient (dimensionless,
	 * d distance / d x and d y). Safe anywhere: unknown space answers maxDistance(). */
	float distanceAt(double x, double y, double* gradX = nullptr, double* gradY = nullptr) const;

	/** Cell index holding world coordinate v (metres). */
	int worldToCell(double v) const;

	/** Bytes of heap memory held by cells, directory and queue. */
	std::size_t memoryBytes() const;
	std::size_t allocatedBlocks() const { return m_blockCount; }
	/** Inclusive bounds of the cells that have storage (false if none). */
	bool touchedBounds(int& minX, int& minY, int& maxX, int& maxY) const;

	static constexpr int kBlockShift = 5;  // 32×32 cells per block
	static constexpr int kBlockSide = 1 << kBlockShift;

   private:
	struct Cell
	{
		int32_t sqd;  // squared distance in cells to (x+ox, y+oy); kFar when none within truncation
		int16_t ox, oy;	 // offset to the nearest obstacle cell
	};
	struct Block;
	static constexpr int32_t kFar = INT32_MAX;
	static constexpr uint8_t kOccupied = 1, kToRaise = 2;

	Cell* cellPtr(int cx, int cy, uint8_t** flags);	 // nullptr when not allocated
	const Cell* cellPtr(int cx, int cy, const uint8_t** flags) const;
	Cell* cellPtrAlloc(int cx, int cy, uint8_t** flags);
	void growDirectory(int bx, int by);
	void push(int key, int cx, int cy);
	void raise(int cx, int cy);
	void lower(int cx, int cy, const Cell& c);

	double m_resolution, m_maxDistance;
	double m_invResolution;	 // multiplications are cheaper than divisions in distanceAt()
	int m_maxSq;
	std::vector<float> m_sqrtLut;  // metres for squared distances 0..m_maxSq

	// Dense directory of block pointers over [m_bx0, m_bx0+m_nbx) × [m_by0, m_by0+m_nby).
	std::vector<std::unique_ptr<Block>> m_dir;
	int m_bx0 = 0, m_by0 = 0, m_nbx = 0, m_nby = 0;
	std::size_t m_blockCount = 0;

	// Bucket priority queue keyed by squared distance in cells.
	std::vector<std::vector<std::pair<int, int>>> m_buckets;
	int m_minBucket = 0;
	std::size_t m_queued = 0;
};

}  // namespace pmslam
