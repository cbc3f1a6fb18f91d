/* pmslam — how noisy a lidar is, measured from its own scans (D52).
 *
 * The likelihood field's σ must cover the lidar's range noise and the map's blur that the noise
 * leaves; a SICK LMS's 0.055 m (D2) is too narrow for a noisier lidar: a true pose then scores
 * like a wrong one, matches are rejected, wide searches run on most scans, and a young map may
 * never grow. The noise is read from the scan itself, not from the match: where three consecutive
 * returns lie on one surface, the middle one's distance from the chord of its neighbours is noise
 * (a wall is straight over a few centimetres), whatever the pose. Match residuals would mix the
 * noise with the pose's error: a lost robot would learn a wide σ that then accepts wrong poses.
 *
 * A return moved by e along its beam is e·sin(a) off a surface seen at angle a to the beam; the chord
 * of its neighbours gives the surface's direction, so the deviation is divided by sin(a), and
 * surfaces seen at under 30° are left out (a small sine would amplify clutter). Per scan: the median
 * over its triples, so that corners, edges and clutter (whose chord distances are geometry, not
 * noise) do not count while they are under half the triples. A triple counts when its neighbours are
 * near (within kMaxSpan + 3 % of the range); far apart, they span surfaces. For independent Gaussian
 * range noise s, |e₀ − (e₋ + e₊)/2| has standard deviation s·√1.5, whose median is 0.6745·s·√1.5:
 * the estimate divides by that, so it reads s (test_sensor_noise: within 15 % up to 0.03 m). It
 * reads low once the noise nears the spacing of the returns, which errs towards the configured σ.
 *
 * Units: metres; points and the lidar's origin in one frame, points in scan order.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>

#include <cstddef>
#include <deque>
#include <optional>
#include <vector>

namespace pmslam
{
/** The range noise of one scan (m), or none when it has fewer than `minTriples` usable triples. */
std::optional<double> scanRangeNoise(const std::vector<mrpt::math::TPoint2Df>& points,
									const mrpt::math::TPoint2D& origin = {0, 0}, std::size_t minTriples = 20);

/** A lidar's range noise over its recent scans: the median of the last `window` scans' estimates,
 * so a scan of clutter or a crowd moves it little. */
class RangeNoise
{
   public:
	explicit RangeNoise(std::size_t window = 25) : m_window(window) {}
	void add(const std::vector<mrpt::math::TPoint2Df>& points, const mrpt::math::TPoint2D& origin = {0, 0});
	/** Median of the recent estimates (m); none before the first usable scan. */
	std::optional<double> noise() const { return m_median; }

   private:
	std::size_t m_window;
	std::deque<double> m_recent;
	std::optional<double> m_median;	 // of m_recent, kept by add(): the σ is asked for at every scan
};

}  // namespace pmslam
