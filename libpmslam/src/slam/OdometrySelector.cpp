/* pmslam — which odometry of a log predicts each scan (see OdometrySelector.h). */
#include <pmslam/slam/OdometrySelector.h>

#include <stdexcept>

namespace pmslam
{
bool OdometrySelector::takeReading(const LogEvent& ev)
{
	if (m_source == OdometrySource::Scan) return false;
	m_latestReading = ev.odometry;
	return true;
}

std::optional<mrpt::math::TPose2D> OdometrySelector::scanOdometry(const LogEvent& ev) const
{
	if (ev.scanHasOdometry && m_source != OdometrySource::Events) return ev.scanOdometry;
	return std::nullopt;
}

std::optional<mrpt::math::TPose2D> OdometrySelector::forScan(const LogEvent& ev) const
{
	if (auto own = scanOdometry(ev)) return own;
	return m_latestReading;	 // empty with OdometrySource::Scan: no reading was taken
}

OdometrySource odometrySourceFromName(const std::string& name)
{
	if (name == "auto") return OdometrySource::Auto;
	if (name == "scan") return OdometrySource::Scan;
	if (name == "events") return OdometrySource::Events;
	throw std::invalid_argument("'" + name + "': expected auto, scan or events");
}

}  // namespace pmslam
