/* pmslam — pose hypotheses for a scan, and which one explains it best.
 *
 * The first hypothesis is the Perfect Match from the prediction. Where that match
 * explains the scan poorly (below wideSearchBelowGoodness: a fast spin, a wheel
 * slip), or the prediction is stale (a lidar alone after a gap), a correlative
 * search over a window around the prediction proposes other starting poses, each
 * refined by PM and scored by its goodness; a pose away from the prediction must
 * beat the match there by a margin.
 *
 * The window says how far the prediction may be off: the wide basin
 * (wideSearchLinear, wideSearchAngular) normally; growing with the time since the
 * last accepted match while lost (the odometry itself may be wrong: a robot
 * carried); with the odometry's distance and turn over a gap or a jump; with the
 * time of a stale prediction. A window wider than the wide basin is a
 * re-localisation, and holds look-alike places: when a clearly different pose
 * explains the scan nearly as well as the best (relocalizeAmbiguity), nothing is
 * decided and the next scans search again. A stale prediction's candidates go to
 * the scans instead (Rivals.h), each with its motion prior (prior()).
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>
#include <pmslam/slam/MotionModel.h>

#include <optional>
#include <utility>
#include <vector>

namespace pmslam
{
/** The MapBuilderOptions fields of the same names (see there for their defaults and why);
 * PerfectMatchSlam fills them. */
struct HypothesisSearchOptions
{
	double wideSearchBelowGoodness = 0;	 ///< 0 = never search
	double minGoodness = 0;	 ///< a match below explains too little of the scan to be taken on its own (D7)
	double wideSearchLinear = 0, wideSearchAngular = 0;	 ///< m, rad
	double relocalizeSpeed = 0, relocalizeTurnRate = 0;	 ///< m/s, rad/s
	double relocalizeOdometryError = 0;
	double relocalizeMaxLinear = 0;	 ///< m
	double relocalizeAmbiguity = 0;	 ///< 0 = off
};

/** Where the search looks: ±linear (m) in x and y and ±angular (rad) around the prediction. */
struct SearchWindow
{
	double linear = 0, angular = 0;
	/** The prediction is stale: search even when the match there looks good (it may be a look-alike
	 * a few metres back), and let the best explanation of the scan win. */
	bool alwaysSearch = false;
	/** After a logging gap (no scan for a while) the robot may have been carried or driven beyond the
	 * window: a poor answer is checked against the whole map (D53). */
	bool afterGap = false;
	/** Where the robot would be had it stopped: the motion prior is centred on the stretch from here
	 * to the prediction (the same pose unless the prediction was extrapolated without odometry). */
	mrpt::math::TPose2D stoppedAt;
	/** A second prediction (MotionPrediction::alternative): both are matched, the better one is the
	 * prediction the window is centred on. */
	std::optional<mrpt::math::TPose2D> alternative;
};

/** A refined candidate pose of a re-localisation, its match, and how plausible the motion model finds
 * it (HypothesisSearch::prior). */
struct Candidate
{
	mrpt::math::TPose2D pose;
	PerfectMatchMatcher::MatchInfo info;
	double prior = 1;
};

/** The pose chosen for a scan, and how it was found. */
struct Hypothesis
{
	mrpt::math::TPose2D pose;
	PerfectMatchMatcher::MatchInfo info;  ///< of the match at `pose`
	bool wideSearch = false;  ///< the window was searched
	bool relocalized = false;  ///< a pose from the search beat the match from the prediction
	bool undecided = false;	 ///< a stale prediction's search found look-alike poses: nothing decided
	bool fromAlternative = false;  ///< window.alternative was the better prediction
	/** A stale prediction's re-localisation: every refined candidate, the prediction's own match
	 * among them, that explains the scan nearly as well as the best, for the scans and the motion
	 * prior to decide between (Rivals.h); after a gap, the whole map's places that explain the scan
	 * clearly better than the window's answer (D53). */
	std::vector<Candidate> rivals;
};

class HypothesisSearch
{
   public:
	explicit HypothesisSearch(const HypothesisSearchOptions& options) : m_options(options) {}

	/** The window for a scan predicted by `motion`; `lost`: the last match was rejected, the first of
	 * those rejections `lostFor` s ago. */
	SearchWindow window(const MotionPrediction& motion, bool lost, double lostFor) const;

	/** PM of `hits` (robot frame) from `predicted`, and the search of `window` where that is not
	 * good enough (or always, with window.alwaysSearch). */
	Hypothesis search(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
					  const std::vector<mrpt::math::TPoint2Df>& hits, const mrpt::math::TPose2D& predicted,
					  const SearchWindow& window) const;

   private:
	HypothesisSearchOptions m_options;
	/** A match that does not explain the scan well enough to go without the wide search. */
	bool poor(const PerfectMatchMatcher::MatchInfo& info) const
	{
		return m_options.wideSearchBelowGoodness > 0 && info.goodness < m_options.wideSearchBelowGoodness;
	}
	/** The whole map's places that explain `hits` well (wideSearchBelowGoodness) and clearly better
	 * than `h`, each refined, as rivals with their motion prior. */
	std::vector<Candidate> clearlyBetterElsewhere(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
												  const std::vector<mrpt::math::TPoint2Df>& hits, const Hypothesis& h,
												  const mrpt::math::TPose2D& predicted, const SearchWindow& window) const;
	/** A refined candidate clearly away from `best` scores within relocalizeAmbiguity of `bestGoodness`. */
	bool lookAlike(const std::vector<std::pair<mrpt::math::TPose2D, double>>& refined, const mrpt::math::TPose2D& best,
				   double bestGoodness) const;
	/** The motion prior of `pose`: exp(-½ m²), m its distance from the stretch between
	 * window.stoppedAt and `predicted` in units of σ, the window being 2σ. */
	static double prior(const mrpt::math::TPose2D& pose, const mrpt::math::TPose2D& predicted, const SearchWindow& window);
};

}  // namespace pmslam
