/* pmslam — finding the robot on a fixed map without being told where it starts.
 *
 * The first scan is searched over the whole map and every heading (BranchAndBoundSearch): its best
 * few distinct poses, each refined by Perfect Match, are the hypotheses. One that wins clearly is
 * the start; one that does not (a symmetric corridor, twin rooms) stays with its rivals until the
 * scans decide (Rivals.h). When every place has been dropped, the current scan is searched anew.
 * After `maxViews` views without a decision, or `maxSearches` searches without a place that kept
 * explaining the scans, it says so: undecided is an answer, a guess is not. Scans that may begin off
 * the map (searchAlong) are searched every metre or so until a place wins on more evidence.
 *
 * Poses are of the robot in the map's frame (metres, radians); best()->origin is the winner's pose at
 * the first scan given, whatever scan the winning search started from (carried back there by the
 * odometry), so that a tracker can start from the first scan.
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <pmslam/match/BranchAndBoundSearch.h>
#include <pmslam/match/LikelihoodPyramid.h>
#include <pmslam/match/PerfectMatchMatcher.h>
#include <pmslam/sensor/ScanPoints.h>
#include <pmslam/slam/Rivals.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

namespace pmslam
{
struct GlobalLocalizerOptions
{
	std::size_t candidates = 8;	 ///< distinct poses taken from a whole-map search
	/** Candidates scoring below this share of the search's best are not taken: "is anything else
	 * nearly as good?" (BranchAndBoundSearch::Options::minRelativeScore). */
	double candidateFloor = 0.7;
	std::size_t searchPoints = 120;	 ///< scan points the whole-map search scores (evenly taken)
	/** The two-stage search (a coarse lattice, its candidates refined at the map's resolution): tens
	 * of milliseconds instead of about a second, but its coarse stage can miss the true place, and
	 * then a look-alike wins: on the benchmark logs' maps 2-4 of 100 starts were decided wrongly
	 * (bench/global.sh), against none with the exact search of the map's lattice (false, the default). */
	bool coarseToFine = false;
	/** The coarse stage's candidates refined, the share of its best they must score, and its points:
	 * a coarse score ties easily, and the true place missed there cannot win later. */
	std::size_t coarseCandidates = 16;
	double coarseFloor = 0.7;
	std::size_t coarsePoints = 64;
	RivalsOptions rivals;  ///< how the scans decide between the places found
	std::size_t maxViews = 30;	///< undecided after this many views without a decision
	/** Not found after this many whole-map searches none of whose places kept explaining the scans. */
	std::size_t maxSearches = 8;
	/** The scans may begin off the map and come onto it later (a session continued from another
	 * wing, a second robot's session merged): never undecided; with no place in play, a new search
	 * once the odometry moved searchEveryLinear or turned searchEveryAngular since the last one;
	 * places left undecided after maxViews are let go; and a place is taken only after alongMinViews
	 * views with a mean goodness of at least alongLeaderGoodness (true places score 0.8-0.98): with a
	 * search every metre of a long log, a look-alike gets many more chances than at a start. */
	bool searchAlong = false;
	double searchEveryLinear = 1.0, searchEveryAngular = M_PI / 4;	///< m, rad
	std::size_t alongMinViews = 3;
	double alongLeaderGoodness = 0.75;
	/** searchAlong: the winner is taken only when the scans so far (the last 300), placed by the
	 * odometry relative to it, put at most this share of their returns that land on the map where the
	 * map observed free space, farther than 0.15 m from any obstacle (as a verified loop, decisions.md
	 * D27): a room shaped like a mapped one, its furniture elsewhere, fits the walls of the view at
	 * hand, but the robot's earlier views put that furniture where the map saw the floor. */
	double alongMaxInFreeSpace = 0.05;
};

class GlobalLocalizer
{
   public:
	enum class State
	{
		Searching,	///< rivals still in play
		Found,
		Undecided
	};
	/** A place: `pose` at the latest scan, `origin` carried back to the first scan given. */
	using Hypothesis = Rivals::Rival;

	GlobalLocalizer(const mrpt::maps::COccupancyGridMap2D& map, const PerfectMatchMatcher::TConfigParams& matcher,
					const ScanPointsOptions& scanOptions, const GlobalLocalizerOptions& options = {});

	/** The next scan and the odometry at it (empty: none; then the robot is taken to stand still
	 * between scans). Returns the state after it. */
	State addScan(const mrpt::obs::CObservation2DRangeScan& scan, const std::optional<mrpt::math::TPose2D>& odometry);

	State state() const { return m_state; }
	/** The winner (Found), else the best so far; empty before any hypothesis. */
	std::optional<Hypothesis> best() const;
	/** The best rival's mean goodness (0 when none): how close the decision was. */
	double runnerUp() const { return m_rivals.runnerUp(); }
	std::size_t scansUsed() const { return m_scans; }
	std::size_t views() const { return m_rivals.views(); }
	std::size_t searches() const { return m_searches; }
	std::size_t hypotheses() const { return m_rivals.size(); }
	double searchSeconds() const { return m_searchSeconds; }

   private:
	/** Of `points` seen from `pose` (map frame): how many land where the map observed free space,
	 * farther than 0.15 m from any obstacle, and how many where it observed anything. */
	std::pair<std::size_t, std::size_t> inFreeSpace(const std::vector<mrpt::math::TPoint2Df>& points,
													const mrpt::math::TPose2D& pose) const;
	/** searchAlong: the scan's points (a share of them) kept with the odometry at it. */
	void remember(const std::vector<mrpt::math::TPoint2Df>& points, const std::optional<mrpt::math::TPose2D>& odometry);
	/** The share of the remembered scans' returns on the map that land in its free space (inFreeSpace),
	 * with the robot at `pose` at `odometry` now. */
	double historyInFreeSpace(const mrpt::math::TPose2D& pose, const std::optional<mrpt::math::TPose2D>& odometry) const;
	/** A new whole-map search is due at `odometry` (no place in play). */
	bool searchDue(const std::optional<mrpt::math::TPose2D>& odometry) const;
	void searchAnew(const std::vector<mrpt::math::TPoint2Df>& points);
	mrpt::math::TPose2D refine(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& start,
							   PerfectMatchMatcher::MatchInfo& info) const;

	GlobalLocalizerOptions m_opts;
	ScanPointsOptions m_scanOpts;
	PerfectMatchMatcher m_matcher;
	DynamicDistanceMap m_distance;
	mrpt::math::TPoint2D m_shift;  ///< map frame = distance layer's frame + m_shift
	std::unique_ptr<LikelihoodPyramid> m_pyramid, m_coarse;  // the map's, and its coarse one (coarseToFine)
	// searchAlong: what the map observed in each cell (row-major over its grid), and that grid's geometry.
	enum class Observed : uint8_t
	{
		Unknown,
		Free,
		Occupied
	};
	std::vector<Observed> m_observed;
	std::deque<std::pair<mrpt::math::TPose2D, std::vector<mrpt::math::TPoint2Df>>> m_history;  // (odometry, points)
	double m_freeX0 = 0, m_freeY0 = 0, m_freeRes = 1;
	int m_freeW = 0, m_freeH = 0;
	Rivals m_rivals;
	std::optional<mrpt::math::TPose2D> m_firstOdometry, m_lastOdometry;
	std::optional<mrpt::math::TPose2D> m_matchedOdometry;  ///< at the last scan the places were matched at
	std::optional<mrpt::math::TPose2D> m_searchedOdometry;	///< at the last whole-map search (searchAlong)
	State m_state = State::Searching;
	double m_searchSeconds = 0;
	std::size_t m_scans = 0, m_searches = 0;
};

}  // namespace pmslam
