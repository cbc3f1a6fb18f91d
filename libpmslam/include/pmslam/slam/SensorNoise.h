/* pmslam — the likelihood field's σ for each lidar, from the noise of its own scans (D52).
 *
 * The configured σ (0.055 m, D2) is the least: it models a SICK LMS's noise and the blur of a
 * 0.05 m grid. A lidar whose scans are noisier (RangeNoise) gets σ = 0.7 × its range noise: the
 * map's walls, drawn from the same returns, are a band of occupied cells that absorbs part of an
 * endpoint's deviation, and a wider σ costs precision (D52 has the sweep). Each sensor (by its
 * label) is measured apart, from the scans that go into the map (or, on a fixed map, every scan
 * matched). intel, aces and fr079 read at most 0.03 m, so σ is the configured one there.
 */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <pmslam/sensor/RangeNoise.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pmslam
{
class SensorNoise
{
   public:
	explicit SensorNoise(double configuredSigma) : m_configured(configuredSigma) {}

	/** A scan of `sensor` (its label), its returns in scan order, the lidar at `origin` (same frame). */
	void add(const std::string& sensor, const std::vector<mrpt::math::TPoint2Df>& hits,
			 const mrpt::math::TPoint2D& origin = {0, 0})
	{
		m_noise[sensor].add(hits, origin);
	}
	/** σ of the likelihood field for `sensor`'s scans (m). */
	double sigma(const std::string& sensor) const;
	/** The range noise measured for `sensor` (m); none before its first usable scan. */
	std::optional<double> noise(const std::string& sensor) const;
	/** Every sensor measured, by label. */
	const std::map<std::string, RangeNoise>& sensors() const { return m_noise; }
	double configuredSigma() const { return m_configured; }

   private:
	double m_configured;
	std::map<std::string, RangeNoise> m_noise;
};

}  // namespace pmslam
