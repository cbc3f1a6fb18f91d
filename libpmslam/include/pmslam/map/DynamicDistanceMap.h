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

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <pmslam/map/BlockDirectory.h>
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
	/** Frees block (bx, by) (DynamicDistanceMap block coordinates) if every cell of it is beyond the
	 * truncation: where obstacles were removed, the blocks they had filled. Only after update(). */
	bool releaseIfFar(int bx, int by);

	bool isObstacle(int cx, int cy) const;
	/** Squared distance in cells to the nearest obstacle, or -1 when it is beyond the truncation. */
	int squaredDistanceCells(int cx, int cy) const;
	/** Distance in metres from the centre of cell (cx, cy), truncated at maxDistance(). */
	float cellDistance(int cx, int cy) const;
	/** f(i, cellDistance(cx0 + i·step, cy)) for i = 0 .. count-1 (step ≥ 1), in order: a row of a
	 * correlative search's lattice (millions of cells per search), inline, the block looked up once
	 * per block rather than once per cell. */
	template <class F>
	void forRowSamples(int cx0, int cy, int step, int count, F&& f) const
	{
		const int rowOffset = (cy & (kBlockSide - 1)) << kBlockShift;
		int i = 0, cx = cx0;
		while (i < count)
		{
			const int bx = blockOf(cx);
			const float* d = blockAt(cx, cy)->dist + rowOffset;
			// The cells of this row that fall in block bx.
			for (; i < count && blockOf(cx) == bx; ++i, cx += step) f(i, d[cx & (kBlockSide - 1)]);
		}
	}

	/** Distance (metres) at a world point by bilinear interpolation of the 4
	 * surrounding cell-centre samples, with its analytic gradient (dimensionless,
	 * d distance / d x and d y). Safe anywhere: unknown space answers maxDistance(). */
	float distanceAt(double x, double y, double* gradX = nullptr, double* gradY = nullptr) const;

	/** The same bilinear sample in cell units, for callers that do their own (float)
	 * coordinate arithmetic: the point at fraction (ax, ay) ∈ [0,1)² between the samples of
	 * cells (i0, j0) and (i0+1, j0+1). Returns the distance (m); dU, dV receive its derivatives
	 * per cell along x and y. */
	float sampleBilinear(int i0, int j0, float ax, float ay, float& dU, float& dV) const
	{
		float d00, d10, d01, d11;
		fetch4(i0, j0, d00, d10, d01, d11);
		const float top = d00 + ax * (d10 - d00), bottom = d01 + ax * (d11 - d01);
		dU = (d10 - d00) * (1 - ay) + (d11 - d01) * ay;
		dV = bottom - top;
		return top + ay * (bottom - top);
	}

	/** Cell index holding world coordinate v (metres). */
	int worldToCell(double v) const { return static_cast<int>(std::floor(v / m_resolution)); }

	/** Bytes of heap memory held by cells, directory and queue. */
	std::size_t memoryBytes() const;
	std::size_t allocatedBlocks() const { return m_blocks.count(); }
	/** Inclusive bounds of the cells that have storage (false if none). */
	bool touchedBounds(int& minX, int& minY, int& maxX, int& maxY) const;

	static constexpr int kBlockShift = 5;  // 32×32 cells per block
	static constexpr int kBlockSide = 1 << kBlockShift;

	static int blockOf(int c) { return c >> kBlockShift; }	// floor division, also for negatives
	static int inBlock(int cx, int cy) { return ((cy & (kBlockSide - 1)) << kBlockShift) | (cx & (kBlockSide - 1)); }
	static_assert(kBlockShift == BlockDirectory<int>::kShift, "one block lattice for every map layer");

   private:
	// The nearest obstacle cell as an offset (the squared distance is ox² + oy²: 4 bytes a cell,
	// which is most of the map's memory). An obstacle points at itself, (0, 0); ox == kNone when no
	// obstacle lies within the truncation, with oy == 1 while the cell waits for a raise wave.
	struct Cell
	{
		int16_t ox, oy;
		int32_t sqd() const { return ox == kNone ? kFar : int32_t(ox) * ox + int32_t(oy) * oy; }
		bool far() const { return ox == kNone; }
		bool raising() const { return ox == kNone && oy == 1; }
		bool obstacle() const { return ox == 0 && oy == 0; }
	};
	static constexpr int16_t kNone = INT16_MIN;
	static constexpr int32_t kFar = INT32_MAX;
	struct Block
	{
		static constexpr int N = kBlockSide * kBlockSide;
		Cell cells[N];
		// The truncated distance (m) of each cell, kept in step with cells[].sqd(): the matcher reads
		// 4 of these per point, and a float load beats computing it (a 16-bit copy, measured: 10-15 %
		// slower per scan on fr079, and the rounding moved intel's runs between their modes).
		float dist[N];
		explicit Block(float far)
		{
			for (auto& c : cells) c = Cell{kNone, 0};
			for (auto& d : dist) d = far;
		}
	};
	// Where the matcher looks: the block holding (cx, cy), or a shared all-far block where
	// nothing was ever written, so the hot path has no null checks.
	const Block* blockAt(int cx, int cy) const
	{
		const Block* b = m_blocks.find(blockOf(cx), blockOf(cy));
		return b ? b : m_farBlock.get();
	}
	/** A cell's storage: its block and index there (block null when not allocated). */
	struct Ref
	{
		Block* block = nullptr;
		int i = 0;
		explicit operator bool() const { return block != nullptr; }
		Cell& cell() const { return block->cells[i]; }
	};
	Ref ref(int cx, int cy) const;	// no allocation
	Ref refAlloc(int cx, int cy);
	// No obstacle within reach any more, and the cells that relied on this one must be told.
	void markRaise(const Ref& r)
	{
		assign(r, kFar, 0, 0);
		r.block->cells[r.i].oy = 1;
	}
	void assign(const Ref& r, int32_t sqd, int ox, int oy)
	{
		r.block->cells[r.i] = sqd == kFar ? Cell{kNone, 0} : Cell{static_cast<int16_t>(ox), static_cast<int16_t>(oy)};
		r.block->dist[r.i] = sqd == kFar ? static_cast<float>(m_maxDistance) : m_sqrtLut[sqd];
	}
	// The samples of cells (i0, j0), (i0+1, j0), (i0, j0+1), (i0+1, j0+1).
	void fetch4(int i0, int j0, float& d00, float& d10, float& d01, float& d11) const
	{
		if (blockOf(i0) == blockOf(i0 + 1) && blockOf(j0) == blockOf(j0 + 1))
		{
			// Common case: all four samples in one block, one directory look-up.
			const float* d = blockAt(i0, j0)->dist + inBlock(i0, j0);
			d00 = d[0];
			d10 = d[1];
			d01 = d[kBlockSide];
			d11 = d[kBlockSide + 1];
		}
		else
		{
			d00 = blockAt(i0, j0)->dist[inBlock(i0, j0)];
			d10 = blockAt(i0 + 1, j0)->dist[inBlock(i0 + 1, j0)];
			d01 = blockAt(i0, j0 + 1)->dist[inBlock(i0, j0 + 1)];
			d11 = blockAt(i0 + 1, j0 + 1)->dist[inBlock(i0 + 1, j0 + 1)];
		}
	}

	void push(int key, int cx, int cy);
	void raise(int cx, int cy);
	void lower(int cx, int cy, const Cell& c);

	double m_resolution, m_maxDistance;
	double m_invResolution;	 // multiplications are cheaper than divisions in distanceAt()
	int m_maxSq;
	std::vector<float> m_sqrtLut;  // metres for squared distances 0..m_maxSq

	BlockDirectory<Block> m_blocks;
	std::unique_ptr<Block> m_farBlock;	// read-only stand-in for blocks never allocated

	// Bucket priority queue keyed by squared distance in cells.
	std::vector<std::vector<std::pair<int, int>>> m_buckets;
	int m_minBucket = 0;
	std::size_t m_queued = 0;
};

// Inline: it is the innermost call of every matcher iteration.
inline float DynamicDistanceMap::distanceAt(double x, double y, double* gradX, double* gradY) const
{
	const double u = x * m_invResolution - 0.5, v = y * m_invResolution - 0.5;
	// Far outside anything representable (or NaN): answer the truncation.
	if (!(std::abs(u) < 1e9 && std::abs(v) < 1e9))
	{
		if (gradX) *gradX = 0;
		if (gradY) *gradY = 0;
		return static_cast<float>(m_maxDistance);
	}
	// floor() without a libm call: truncate, then step down for negative fractions.
	int i0 = static_cast<int>(u), j0 = static_cast<int>(v);
	i0 -= u < i0;
	j0 -= v < j0;
	const double ax = u - i0, ay = v - j0;
	float d00, d10, d01, d11;
	fetch4(i0, j0, d00, d10, d01, d11);
	const double top = d00 + ax * (d10 - d00), bottom = d01 + ax * (d11 - d01);
	if (gradX) *gradX = ((d10 - d00) * (1 - ay) + (d11 - d01) * ay) * m_invResolution;
	if (gradY) *gradY = (bottom - top) * m_invResolution;
	return static_cast<float>(top + ay * (bottom - top));
}

}  // namespace pmslam
