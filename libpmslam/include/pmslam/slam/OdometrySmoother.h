/* pmslam — the reported trajectory: matched poses fused with odometry increments.
 *
 * Each matched pose carries a small error of its own that changes from scan to
 * scan (in a corridor the scan barely fixes the pose along the track: aces,
 * about 1.5 cm per scan), while odometry increments over a few scans are
 * precise but drift over many. A Kalman filter on the position (x, y) with the
 * odometry increment as the motion model and the matched pose as the
 * measurement, followed by a fixed-lag Rauch-Tung-Striebel pass, keeps the
 * long-term position of the matches (so the map anchors it) and the short-term
 * shape of the odometry. The heading is the matched one.
 *
 * Both noise levels are learned online, separately along and across the
 * track, from how the discrepancy between matched and odometry increments
 * grows with the number of scans k it spans: var(k) = 2·R + k·Q, R the match
 * noise, Q the odometry noise per scan (k = 1 and k = varianceLag). Odometry
 * that drifts fast (fr079) thus gets a large Q and the output stays the
 * matched pose; precise odometry with noisy matches (aces) gets smoothed.
 * A match farther than `gate` standard deviations from the prediction (a
 * revisit snapping back, a glitch) restarts the filter at the match.
 *
 * Only the reported poses change: the map and the next prediction still use
 * the matched poses, so the odometry's drift never enters the map. A pose is
 * final `lag` scans after its own scan.
 */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace pmslam
{
struct OdometrySmootherOptions
{
	unsigned lag = 3;  ///< scans of look-ahead before a pose is final (0 = filter only)
	unsigned varianceLag = 8;  ///< k of the long-span discrepancy statistics (>= 2)
	double gate = 5.0;	///< restart at the match beyond this many standard deviations
	std::size_t warmup = 100;  ///< samples of each statistic before fusing (until then: the match)
};

class OdometrySmoother
{
   public:
	explicit OdometrySmoother(const OdometrySmootherOptions& o = {});

	/** Adds scan `index`'s matched pose (map frame) and the odometry at that scan (any frame;
	 * nullopt = none: the filter restarts there). */
	void add(std::size_t index, const mrpt::math::TPose2D& matched,
			 const std::optional<mrpt::math::TPose2D>& odometry);
	/** The poses that became final since the last call, oldest first: (index, pose). */
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> takeFinal();
	/** Finalises every pose still waiting (end of the log). */
	void finish();

	/** Learned standard deviations (along, across the track): of one match and of the odometry
	 * per scan. Zero until warmed up. */
	Eigen::Vector2d matchSigma() const;
	Eigen::Vector2d odometrySigma() const;
	bool warmedUp() const;

   private:
	struct Entry
	{
		std::size_t index;
		mrpt::math::TPose2D matched;
		std::optional<mrpt::math::TPose2D> odometry;
		Eigen::Vector2d x;	// filtered position
		Eigen::Matrix2d P;	// its covariance
		Eigen::Vector2d pred;  // prediction from the previous entry (unused after a restart)
		Eigen::Matrix2d Ppred;
		bool restart = true;
	};
	void updateStatistics();
	void emitOldest();
	Eigen::Vector2d smoothedPosition(std::size_t i) const;	// RTS over m_window[i..end]

	OdometrySmootherOptions m_opts;
	std::deque<Entry> m_window;	 // the last lag + 1 entries (+ the odometry history below)
	std::deque<std::pair<mrpt::math::TPose2D, mrpt::math::TPose2D>> m_history;	// (matched, odometry), last varianceLag + 1
	// Sums of squared discrepancy (along, across) and counts, for span 1 and span varianceLag.
	Eigen::Vector2d m_sum1 = Eigen::Vector2d::Zero(), m_sumK = Eigen::Vector2d::Zero();
	std::size_t m_n1 = 0, m_nK = 0;
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> m_final;
};

}  // namespace pmslam
