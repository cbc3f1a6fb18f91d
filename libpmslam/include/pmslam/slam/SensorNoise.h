/* pmslam — the likelihood field's σ for each lidar, from the noise of its own scans (D52).
 *
 * The configured σ (0.055 m, D2) is the least: it models a SICK LMS's noise and the blur of a
 * 0.05 m grid. A lidar whose scans are noisier (RangeNoise) gets σ = √2 × its range noise: an
 * endpoint and the wall it is compared with each carry that noise. Each sensor (by its label) is
 * measured apart, from the scans that go into the map (or, on a fixed map, every scan matched).
 * On intel, aces and fr079 √2 × the noise stays under 0.04 m, so σ is the configured one there.
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

	/** A scan of `sensor` (its label), its returns in scan order. */
	void add(const std::string& sensor, const std::vector<mrpt::math::TPoint2Df>& hits) { m_noise[sensor].add(hits); }
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
