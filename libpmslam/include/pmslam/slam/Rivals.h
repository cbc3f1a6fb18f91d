/* pmslam — look-alike poses kept until the scans decide between them.
 *
 * One scan cannot tell twin rooms or the bays of a repetitive corridor apart: whichever pose scores
 * best on it is as likely the look-alike as the right one. So the poses that explain it nearly
 * equally are kept as rivals, each moved with the robot's motion to the next scans and matched
 * there by Perfect Match. Only views from a new place count as evidence (the leader moved
 * viewLinear or turned viewAngular since the last one): a robot standing still shows the same scan
 * again, which tells nothing new. The mean goodness over those views ranks the rivals, and the
 * leader wins once its lead exceeds decideMargin / √views — about four times the scan-to-scan noise
 * of a goodness difference, a noise that shrinks as the square root of the views — or once it is
 * the only one left. In a truly symmetric place the lead stays at the noise and nothing is decided.
 * A rival whose matches stop explaining the scans is dropped.
 *
 * The robot's motion is evidence too (decisions.md D45): each rival is matched with the motion it was
 * moved by as a prior, so it does not slide where the scan leaves a direction open; a view counts
 * for less when the rival's own motion since its last view strays from the robot's (a look-alike the
 * map keeps pulling back to one spot while the robot drives on); and a caller's motion prior on
 * where a rival may be counts as one more view.
 *
 * Used by GlobalLocalizer (the start on a fixed map) and by PerfectMatchSlam (a lidar alone after a
 * gap). Poses are of the robot in the map frame (m, rad); `origin` is the caller's own (where the
 * rival puts some earlier scan), carried along unchanged.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace pmslam
{
struct RivalsOptions
{
	double decideMargin = 0.08;	 ///< the leader's lead in mean goodness, times √views, that decides
	/** A rival whose mean goodness falls below this, or its last match below it less 0.15, is dropped
	 * (good matches score 0.8-0.98). */
	double minGoodness = 0.55;
	double viewLinear = 0.2, viewAngular = 10 * M_PI / 180;	 ///< m, rad: a new view
	double distinctLinear = 0.3, distinctAngular = 5 * M_PI / 180;	///< closer rivals are one
	/** Views before anything is decided: 1 trusts a lone rival at once, which is right only when the
	 * search that proposed the rivals cannot have missed the true pose. */
	std::size_t minViews = 1;
	/** The leader's mean inlier goodness must reach this too (0: any): among rivals that are all wrong,
	 * the scans would otherwise pick the least wrong. Inlier goodness, because a right pose at the
	 * edge of the map has much of its scan on new ground. */
	double minLeaderGoodness = 0;
	/** How far a rival's own motion between two views may stray from the robot's before its view counts
	 * for less: σ = motionNoiseLinear + motionNoiseShare × the distance moved (m), and
	 * motionNoiseAngular + motionNoiseShare × the turn (rad); motionNoiseShare 0: not weighed. */
	double motionNoiseLinear = 0.05, motionNoiseAngular = 2 * M_PI / 180, motionNoiseShare = 0.2;
	/** m per rad: the linear σ grows with the turn too. A scan taken while the robot turns is skewed by
	 * the turn during its sweep, and a lidar ahead of the axle moves on an arc the odometry's timing
	 * misplaces: the matched translation of the right place jitters by 0.07-0.14 m over views of
	 * 12-15° while turning in place (aces, decisions.md D43), where a look-alike that fits the scan
	 * loosely just follows the odometry. Without it, such views counted the right place 0.09-0.77
	 * of its goodness and a look-alike 25 m away was decided. */
	double motionNoisePerTurn = 0.5;
};

class Rivals
{
   public:
	struct Rival
	{
		mrpt::math::TPose2D pose;  ///< at the latest scan
		mrpt::math::TPose2D origin;	 ///< the caller's, carried along
		mrpt::math::TPose2D lastView;  ///< where its last view counted
		PerfectMatchMatcher::MatchInfo info;  ///< of its latest match
		/** Its pose at each scan since it was added, with the caller's tag of that scan (so that the
		 * winner's path can replace what was reported while nothing was decided). */
		std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> path;
		double goodnessSum = 0, inlierGoodnessSum = 0;
		std::size_t views = 0;
		/** How plausible the motion model found it when it was added (1: no motion prior). */
		double prior = 1;
		double mean() const { return views ? goodnessSum / double(views) : 0; }
		/** The mean of the views' inlier goodness: how well the scans agree where they overlap the map. */
		double inlierMean() const { return views ? inlierGoodnessSum / double(views) : 0; }
		/** What ranks it: the mean goodness, less the motion prior's doubt counted as one view of
		 * the views + 1 (so the prior decides between poses the scans cannot yet tell apart, and the
		 * scans outweigh it as their views add up). */
		double score() const { return mean() - (1 - prior) / double(views + 1); }
	};

	explicit Rivals(const RivalsOptions& options = {}) : m_options(options) {}

	/** A rival matched at `pose` (its first view), unless one is there already; `prior`: how
	 * plausible the motion model finds it, in (0, 1]. */
	void add(const mrpt::math::TPose2D& pose, const mrpt::math::TPose2D& origin, const PerfectMatchMatcher::MatchInfo& info,
			 std::size_t tag = 0, double prior = 1);
	/** The next scan (`points`, robot frame): each rival moved by `motion` (robot frame) and matched on
	 * `map`, whose frame is the map frame less `shift`; then the weak ones dropped and ranked. */
	void follow(const PerfectMatchMatcher& matcher, const DynamicDistanceMap& map,
				const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPose2D& motion,
				const mrpt::math::TPoint2D& shift = {0, 0}, std::size_t tag = 0);
	/** Ranks them; true when the leader has won. */
	bool decide();

	bool empty() const { return m_rivals.empty(); }
	std::size_t size() const { return m_rivals.size(); }
	const Rival& leader() const { return m_rivals.front(); }
	double runnerUp() const { return m_rivals.size() > 1 ? m_rivals[1].mean() : 0; }
	std::size_t views() const { return m_rivals.empty() ? 0 : m_rivals.front().views; }
	void clear() { m_rivals.clear(); }

   private:
	bool distinct(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b) const;
	/** In (0, 1]: how well `r`'s motion since its last view agrees with the robot's (m_sinceView). */
	double motionAgreement(const Rival& r) const;
	RivalsOptions m_options;
	std::vector<Rival> m_rivals;  ///< leader first after decide()
	mrpt::poses::CPose2D m_sinceView;	///< the robot's motion since the last view (robot frame)
};

}  // namespace pmslam
