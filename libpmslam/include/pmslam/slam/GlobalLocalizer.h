/* pmslam — finding the robot on a fixed map without being told where it starts.
 *
 * The first scan is searched over the whole map and every heading (BranchAndBoundSearch): its best
 * few distinct poses, each refined by Perfect Match, are the hypotheses. One that wins clearly
 * (its match explains the scan better than the runner-up's by `decideMargin`) is the start. One
 * that does not (a symmetric corridor, twin rooms) stays with its rivals: each is moved by the
 * odometry to the next scans and matched there, and the scans decide. Only views from a new place
 * count as evidence (the leader moved 0.2 m or turned 10° since the last one): a robot standing
 * still shows the same scan again, which tells nothing new. The mean goodness over those views ranks
 * the hypotheses, and the leader wins once its lead exceeds decideMargin / √views — a lead that
 * holds over more independent views needs to be smaller to be sure, as the noise of a mean shrinks;
 * in a truly symmetric place the lead stays at the noise and nothing is decided. A hypothesis that
 * stops explaining the scans is dropped; when every one is, the current scan is searched anew.
 * After `maxViews` views without a decision it says so: undecided is an answer, a guess is not.
 *
 * Poses are of the robot in the map's frame (metres, radians); firstPose() is the winner's pose at
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

#include <cstddef>
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
	/** The leader wins when its mean goodness exceeds every rival's by this / √views (about four
	 * times the scan-to-scan noise of a goodness difference, 0.02). */
	double decideMargin = 0.08;
	double viewLinear = 0.2, viewAngular = 10 * M_PI / 180;	 ///< m, rad: a new view
	/** A hypothesis whose last match, or mean, falls below this is dropped (good matches score 0.8-0.98). */
	double minGoodness = 0.55;
	std::size_t maxViews = 30;	///< undecided after this many views without a decision
	/** Not found after this many whole-map searches none of whose places kept explaining the scans. */
	std::size_t maxSearches = 8;
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
	struct Hypothesis
	{
		mrpt::math::TPose2D pose;  ///< at the latest scan (map frame)
		mrpt::math::TPose2D first;	///< carried back to the first scan given
		mrpt::math::TPose2D lastView;  ///< where its last view counted
		double goodnessSum = 0;
		std::size_t scans = 0;	///< views counted
		double lastGoodness = 0;
		double mean() const { return scans ? goodnessSum / double(scans) : 0; }
	};

	GlobalLocalizer(const mrpt::maps::COccupancyGridMap2D& map, const PerfectMatchMatcher::TConfigParams& matcher,
					const ScanPointsOptions& scanOptions, const GlobalLocalizerOptions& options = {});

	/** The next scan and the odometry at it (empty: none; then the robot is taken to stand still
	 * between scans). Returns the state after it. */
	State addScan(const mrpt::obs::CObservation2DRangeScan& scan, const std::optional<mrpt::math::TPose2D>& odometry);

	State state() const { return m_state; }
	/** The winner (Found), else the best so far; empty before any hypothesis. */
	std::optional<Hypothesis> best() const;
	/** The best rival's mean goodness (0 when none): how close the decision was. */
	double runnerUp() const { return m_runnerUp; }
	std::size_t scansUsed() const { return m_scans; }
	std::size_t views() const { return m_hyps.empty() ? 0 : m_hyps.front().scans; }
	std::size_t searches() const { return m_searches; }
	std::size_t hypotheses() const { return m_hyps.size(); }
	double searchSeconds() const { return m_searchSeconds; }

   private:
	void searchAnew(const std::vector<mrpt::math::TPoint2Df>& points);
	void follow(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& motion);
	void decide();
	mrpt::math::TPose2D refine(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& start,
							   PerfectMatchMatcher::MatchInfo& info) const;

	GlobalLocalizerOptions m_opts;
	ScanPointsOptions m_scanOpts;
	PerfectMatchMatcher m_matcher;
	DynamicDistanceMap m_distance;
	mrpt::math::TPoint2D m_shift;  ///< map frame = distance layer's frame + m_shift
	std::unique_ptr<LikelihoodPyramid> m_pyramid;
	std::vector<Hypothesis> m_hyps;
	std::optional<mrpt::math::TPose2D> m_firstOdometry, m_lastOdometry;
	State m_state = State::Searching;
	double m_runnerUp = 0, m_searchSeconds = 0;
	std::size_t m_scans = 0, m_searches = 0;
};

}  // namespace pmslam
