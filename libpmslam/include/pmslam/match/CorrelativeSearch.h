/* pmslam — the wide basin: a correlative search over rotation and translation.
 *
 * Perfect Match converges from about ±0.2 m / ±5° (its field is truncated at the distance
 * map's reach). A prediction further off (a fast spin, an odometry slip, a time gap) lands in
 * the wrong basin. This search scores every pose of a lattice around the prediction (Olson,
 * "Real-time correlative scan matching", ICRA 2009, as Cartographer's real-time matcher does)
 * and returns the best few local maxima, which the PM refinement then polishes.
 *
 * Score of a pose: the mean over a subset of the points of σc²/(σc²+Δ²), Δ the truncated
 * distance at the point's cell, σc a few lattice steps wide so that neighbouring lattice poses
 * see a smooth field. The lattice: translation steps of `linearStep`; rotation steps small
 * enough that the farthest points (95th percentile of range) move at most one linear step.
 *
 * Units and frames: metres and radians; points in the robot frame, poses of the robot in the
 * map frame.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <pmslam/map/DynamicDistanceMap.h>

#include <cstddef>
#include <vector>

namespace pmslam
{
class CorrelativeSearch
{
   public:
	struct Options
	{
		double linearStep = 0.1;  ///< lattice step in x and y (m)
		double minAngularStep = 0.25 * M_PI / 180, maxAngularStep = 1.0 * M_PI / 180;	///< rad
		double fieldSigma = 0.15;  ///< σc of the search's likelihood field (m)
		std::size_t maxPoints = 160;  ///< points scored (evenly taken from the scan)
		std::size_t candidates = 4;	 ///< local maxima returned, best first
	};
	struct Candidate
	{
		mrpt::math::TPose2D pose;
		double score = 0;  ///< mean likelihood in [0, 1]
	};

	CorrelativeSearch() = default;
	explicit CorrelativeSearch(const Options& o) : options(o) {}
	Options options;

	/** Poses within ±linearWindow (m, in x and y) and ±angularWindow (rad) of `centre`, best
	 * first; distinct candidates differ by at least two lattice steps or two rotation steps. */
	std::vector<Candidate> search(const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& points,
								  const mrpt::math::TPose2D& centre, double linearWindow, double angularWindow) const;

	/** Starting poses for a refinement over a window of any size: a coarse lattice over the whole
	 * window (steps of max(0.1 m, linearWindow / 8), so at most ~17 per axis), then a fine one
	 * (0.1 m) around each coarse peak; best coarse peak first. The cost stays bounded however
	 * wide the window (a re-localisation, a loop closure's uncertainty). */
	static std::vector<Candidate> coarseToFine(const DynamicDistanceMap& map,
											   const std::vector<mrpt::math::TPoint2Df>& points,
											   const mrpt::math::TPose2D& centre, double linearWindow,
											   double angularWindow, std::size_t candidates = 4);
};

}  // namespace pmslam
