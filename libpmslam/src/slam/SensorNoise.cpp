/* pmslam — the likelihood field's σ per lidar (see SensorNoise.h). */
#include <pmslam/slam/SensorNoise.h>

#include <algorithm>

namespace pmslam
{
namespace
{
// σ per metre of range noise (D52): the map's walls, drawn from the same noisy returns, are a band
// of occupied cells that absorbs part of an endpoint's deviation; 0.7 was the best of 0.5-1.4 in
// the sweep of decisions.md D52 (wide searches and error on simulated logs at 0.1-0.2 m of noise).
constexpr double kSigmaPerNoise = 0.7;
}  // namespace

double SensorNoise::sigma(const std::string& sensor) const
{
	const auto n = noise(sensor);
	return n ? std::max(m_configured, kSigmaPerNoise * *n) : m_configured;
}

std::optional<double> SensorNoise::noise(const std::string& sensor) const
{
	const auto it = m_noise.find(sensor);
	return it == m_noise.end() ? std::nullopt : it->second.noise();
}

}  // namespace pmslam
