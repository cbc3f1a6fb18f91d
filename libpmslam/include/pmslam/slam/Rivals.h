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
 * Used by GlobalLocalizer (the start on a fixed map) and by PerfectMatchSlam (a lidar alone after a
 * gap). Poses are of the robot in the map frame (m, rad); `origin` is the caller's own (where the
 * rival puts some earlier scan), carried along unchanged.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
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
	/** The leader's mean goodness must reach this too (0: any): among rivals that are all wrong, the
	 * scans would otherwise pick the least wrong. */
	double minLeaderGoodness = 0;
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
		double goodnessSum = 0;
		std::size_t views = 0;
		double mean() const { return views ? goodnessSum / double(views) : 0; }
	};

	explicit Rivals(const RivalsOptions& options = {}) : m_options(options) {}

	/** A rival matched at `pose` (its first view), unless one is there already. */
	void add(const mrpt::math::TPose2D& pose, const mrpt::math::TPose2D& origin, const PerfectMatchMatcher::MatchInfo& info,
			 std::size_t tag = 0);
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
	RivalsOptions m_options;
	std::vector<Rival> m_rivals;  ///< leader first after decide()
};

}  // namespace pmslam
