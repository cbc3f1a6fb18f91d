/* pmslam — global search: exhaustive correlative matching by branch and bound.
 *
 * CorrelativeSearch scores every pose of a small lattice around a prediction. A robot that does not
 * know where it is needs the whole map and every heading: millions of translations times
 * thousands of rotations, far too many to score one by one. Olson's multi-resolution correlative
 * matching (ICRA 2009), in the form of Hess et al. (Cartographer, ICRA 2016), finds the same
 * optimum while looking at a tiny part of them: for one rotation, a node is a square of 2^h × 2^h
 * translations; LikelihoodPyramid's level h bounds every score in it from above; the search goes
 * depth-first, children best bound first, and drops a node whose bound cannot beat what it
 * already has.
 *
 * The lattice (Lattice): rotations θ_a (a step such that the farthest point moves at most one
 * cell), translations origin + (i, j)·res (the map resolution). The score of lattice pose
 * (a, i, j) is the sum over the points k of level 0 of the pyramid at cell
 *     (cx_k(a) + i, cy_k(a) + j),  cx_k(a) = ⌊(originX + cos θ_a·x_k − sin θ_a·y_k) / res⌋
 * (cy_k alike): a translation by whole cells shifts every point by whole cells. The result is the
 * EXACT optimum of this integer score over the lattice, not an approximation of it; reported
 * scores are that sum / (255 · points), in [0, 1].
 *
 * Distinct candidates, so that ambiguity can be measured: lattice poses are totally ordered by
 * (score, then the smaller index (a·ny + j)·nx + i). A candidate is a pose greater than every
 * other pose of its neighbourhood (Euclidean translation within `distinctLinear` and rotation
 * within `distinctAngular`); the search returns the K greatest candidates, which a brute-force
 * pass computes identically. Two candidates are therefore further apart than the thresholds, and
 * a second candidate scoring close to the first means the scan fits two places.
 *
 * Cost: every rotation's root nodes are scored (rotations × (side / 2^top)² bounds), then the
 * nodes whose bound reaches the best score so far. In a building, a coarse node's window holds a
 * wall for nearly every point, so bounds only fall below a good match's score a few levels above
 * the cells: the node count, not the leaves or the candidate checks, dominates, and it grows
 * faster than the map's area (bench/bench_global_search.cpp): on a 100 m × 100 m building at
 * 0.05 m, ~10 s of CPU per whole-map search with 181 points.
 *
 * searchGlobalCoarseToFine() is the whole-map search for a robot switched on in a big map: the
 * same exact search on a lattice 4 times coarser (a dilated max of level 0 as its score, 64
 * points, the rotation step from the median range: about 16 × 25 × 3 times fewer poses × points
 * than the fine lattice, and a pyramid that fits in cache), then a window search on this
 * pyramid around each of its best candidates. Each stage is exact on its own lattice; the two
 * together are not the fine lattice's optimum, but on bench_global_search they find the true
 * pose nearly whenever the fine optimum would (answers worse than the truth's own fine score:
 * 0-5 % of the queries, with noise and 10 % clutter or without) in 65-130 ms of CPU on
 * 100 m × 100 m (1-1.3 M bounds of 64 points; the spread is the load of the shared machine
 * measured on, and 360-point scans cost more to refine than 181-point ones).
 *
 * Units and frames: metres and radians; points in the robot frame; poses of the robot in the
 * caller's map frame (the pyramid's frame plus its frameOffset()).
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/match/LikelihoodPyramid.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace pmslam
{
class BranchAndBoundSearch
{
   public:
	struct Options
	{
		/** Points scored, evenly taken from the scan (0: all). The score and its optimum are those
		 * of the points kept. */
		std::size_t maxPoints = 0;
		/** Rotation step (rad); 0: resolution / farthest point's range, so that the farthest point
		 * moves at most about one cell between neighbouring rotations. */
		double angularStep = 0;
		/** With angularStep 0, the range that sets the step is this quantile of the kept points'
		 * ranges (1: the farthest). A few far points need not multiply the rotations: below 1, the
		 * points beyond that range may move more than a cell between rotations. */
		double rangeQuantile = 1;
		/** Mean score in [0, 1] below which nothing is reported; also a pruning threshold from the
		 * start, so a sensible value (an expected fraction of matched points) speeds the search. */
		double minScore = 0;
		/** Nothing scoring below this fraction of the best is reported (0: no such floor). Asking
		 * for K candidates with a floor of, say, 0.8 answers "is anything else nearly as good?"
		 * at little more cost than K = 1; without it the search must rank the K-th best place,
		 * however poor, which on a small window or a featureless map means most of the lattice. */
		double minRelativeScore = 0;
		std::size_t candidates = 1;	 ///< K: distinct candidates returned, best first
		double distinctLinear = 0.3;  ///< m, neighbourhood of a candidate in translation
		double distinctAngular = 5.0 * M_PI / 180;	///< rad, neighbourhood of a candidate in rotation

		/** searchGlobalCoarseToFine: the coarse lattice and how its candidates are refined. */
		struct CoarseToFine
		{
			int factor = 4;	 ///< coarse resolution = factor × the pyramid's
			/** Fine cells by which each coarse cell's max is widened (LikelihoodPyramid::coarsened):
			 * half a coarse cell, so that the nearest coarse pose's points still fall in cells
			 * holding their true wall cells (up to what the rotation step moves them). Measured on
			 * bench_global_search: 3 (covering half a rotation step at the median range too) blurs
			 * the score into more near-ties than it saves; 5 loses most searches. */
			int dilation = 2;
			int levels = 8;	 ///< levels of the coarse pyramid
			std::size_t maxPoints = 64;	 ///< points scored by the coarse search
			/** Sets the coarse rotation step (see rangeQuantile): the median range, so that most
			 * points move at most about a coarse cell between rotations; far points are few. */
			double rangeQuantile = 0.5;
			/** Coarse candidates refined (at least `candidates`): the dilated score of a few points
			 * ties more easily than the fine score of all of them, so the coarse winner is not
			 * always the true place; refining is cheap (a small window each), the coarse ranking
			 * of more candidates is not much dearer. */
			std::size_t candidates = 16;
			double minRelativeScore = 0.7;	///< coarse candidates within this fraction of the best
			double linearWindow = 0;  ///< refinement ±(m) around a coarse candidate; 0: one coarse cell
			double angularSteps = 1;  ///< refinement ±(coarse rotation steps)
		};
		CoarseToFine coarse;

		/** One scan searched over the whole map, as the front-end after a gap (D53) and the back-end
		 * after lost tracking (D46) ask it: 120 points, the rotation step set by their 90th-percentile
		 * range (a few far returns need not multiply the rotations), the `candidates` best distinct
		 * places within `floor` of the best. */
		static Options wholeMap(std::size_t candidates, double floor)
		{
			Options o;
			o.candidates = candidates;
			o.minRelativeScore = floor;
			o.maxPoints = 120;
			o.rangeQuantile = 0.9;
			return o;
		}
	};

	/** The lattice searched. Built by windowLattice() or globalLattice(); public so that a
	 * reference (a test, a benchmark) can score the very same poses. */
	struct Lattice
	{
		std::vector<mrpt::math::TPoint2Df> points;	///< the points scored (robot frame)
		std::vector<double> angles;	 ///< θ_a (rad, pyramid frame = map frame)
		double originX = 0, originY = 0;  ///< translation of (i, j) = (0, 0), pyramid frame (m)
		int nx = 0, ny = 0;	 ///< translations i ∈ [0, nx), j ∈ [0, ny)
		double angularStep = 0;	 ///< rad
		bool wrapsAround = false;  ///< angles cover the whole circle (neighbourhoods wrap)
		int angularRadius = 0;	///< neighbourhood: |Δa| ≤ this (in steps, wrapped when wrapsAround)
		double linearRadius = 0;  ///< neighbourhood: Δi² + Δj² ≤ this² (cells)
	};

	struct Candidate
	{
		mrpt::math::TPose2D pose;  ///< in the caller's map frame
		double score = 0;  ///< mean rescaled likelihood in [0, 1]
		int64_t rawScore = 0;  ///< the integer sum the search maximises
		int a = 0, i = 0, j = 0;  ///< lattice indices
	};
	struct Stats
	{
		std::size_t angles = 0, translations = 0;  ///< lattice size: angles × translations poses
		std::size_t points = 0;	 ///< points scored
		std::size_t roots = 0;	///< nodes at the coarsest level (all scored)
		std::size_t nodes = 0;	///< bounds evaluated in the main search (roots included)
		std::size_t leaves = 0;	 ///< poses scored in the main search
		std::size_t climbs = 0, climbNodes = 0;	 ///< neighbourhood searches and the bounds they evaluated
		double seconds = 0;	 ///< wall time of search() (rotating the points included)
		double coarseSeconds = 0;  ///< searchGlobalCoarseToFine: wall time of its coarse stage
		std::size_t refined = 0;  ///< searchGlobalCoarseToFine: coarse candidates refined
	};
	struct Result
	{
		std::vector<Candidate> candidates;	///< best first
		Stats stats;
	};

	/** The pyramid must outlive the search. */
	BranchAndBoundSearch(const LikelihoodPyramid& pyramid, const Options& options);
	explicit BranchAndBoundSearch(const LikelihoodPyramid& pyramid) : BranchAndBoundSearch(pyramid, Options()) {}

	/** Poses within ±linearWindow (m, in x and y) and ±angularWindow (rad) of `centre` (map frame). */
	Lattice windowLattice(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& centre,
						  double linearWindow, double angularWindow) const;
	/** Every cell centre of the pyramid's window, every heading. */
	Lattice globalLattice(const std::vector<mrpt::math::TPoint2Df>& points) const;

	/** The K best distinct candidates of `lattice` (see the file comment). */
	Result search(const Lattice& lattice) const;
	Result searchWindow(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& centre,
						double linearWindow, double angularWindow) const
	{
		return search(windowLattice(points, centre, linearWindow, angularWindow));
	}
	Result searchGlobal(const std::vector<mrpt::math::TPoint2Df>& points) const
	{
		return search(globalLattice(points));
	}

	/** Two-stage global search, for a robot switched on in a big map (see Options::CoarseToFine).
	 * Stage 1 is search() on the global lattice of `coarse` (every coarse cell centre, every
	 * heading at the coarse step): the EXACT optimum of the coarse score, the sum over
	 * Options::coarse.maxPoints points of the dilated max of level 0 (coarsened()). Its
	 * Options::coarse.candidates best distinct candidates within coarse.minRelativeScore of the
	 * best are each refined by a window search on this pyramid (±coarse.linearWindow,
	 * ±coarse.angularSteps coarse steps, all the points this search's options keep): the exact
	 * optimum of the fine score in that window. The refined poses are re-ranked by fine score,
	 * made distinct (distinctLinear/distinctAngular) and cut to `candidates` and minRelativeScore.
	 * Their a, i, j index the window lattice they were refined on. minScore applies to both
	 * stages (the dilated coarse score of the truth's cell is normally above its fine score);
	 * angularStep, if given, to the refinement only. Stats: the coarse
	 * lattice's size, nodes and leaves of both stages, the total time. */
	Result searchGlobalCoarseToFine(const std::vector<mrpt::math::TPoint2Df>& points,
									const LikelihoodPyramid& coarse) const;
	/** The same on coarsePyramid(), built on the first call and kept (shared by copies). */
	Result searchGlobalCoarseToFine(const std::vector<mrpt::math::TPoint2Df>& points) const;
	/** The coarse pyramid Options::coarse describes. */
	LikelihoodPyramid coarsePyramid() const
	{
		return m_pyramid.coarsened(m_options.coarse.factor, m_options.coarse.dilation, m_options.coarse.levels);
	}

	/** The cells (cx_k(a), cy_k(a)) of every point at rotation a, translation (0, 0). */
	std::vector<std::pair<int, int>> pointCells(const Lattice& lattice, int a) const;
	/** Upper bound of the node of level h at rotation a, translations [i, i+2^h) × [j, j+2^h): the
	 * sum of level h over the points. At h = 0, the score of pose (a, i, j). */
	int64_t nodeBound(const Lattice& lattice, int h, int a, int i, int j) const;
	/** Lattice pose (a, i, j) in the caller's map frame. */
	mrpt::math::TPose2D poseOf(const Lattice& lattice, int a, int i, int j) const;

	const Options& options() const { return m_options; }
	const LikelihoodPyramid& pyramid() const { return m_pyramid; }

   private:
	struct CoarseCache;
	const LikelihoodPyramid& m_pyramid;
	Options m_options;
	std::shared_ptr<CoarseCache> m_coarse;
	Lattice makeLattice(const std::vector<mrpt::math::TPoint2Df>& points) const;
};

}  // namespace pmslam
