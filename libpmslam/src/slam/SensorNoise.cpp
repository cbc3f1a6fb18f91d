/* pmslam — the likelihood field's σ per lidar (see SensorNoise.h). */
#include <pmslam/slam/SensorNoise.h>

#include <algorithm>
#include <cmath>

namespace pmslam
{
double SensorNoise::sigma(const std::string& sensor) const
{
	const auto n = noise(sensor);
	return n ? std::max(m_configured, std::sqrt(2.0) * *n) : m_configured;
}

std::optional<double> SensorNoise::noise(const std::string& sensor) const
{
	const auto it = m_noise.find(sensor);
	return it == m_noise.end() ? std::nullopt : it->second.noise();
}

}  // namespace pmslam
