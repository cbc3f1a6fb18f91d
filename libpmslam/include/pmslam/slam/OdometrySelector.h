/* pmslam — which odometry of a log predicts each scan ([Log] odometrySource).
 *
 * A log can carry odometry twice: written on the laser line itself (Carmen FLASER/RLASER/ROBOTLASER1:
 * LogEvent::scanOdometry) and as separate readings (ODOM lines, CObservationOdometry, rawlog actions:
 * LogEvent::Kind::Odometry). OdometrySource says which of them a run uses; every program that feeds a
 * log's events to a SLAM front-end (pm-slam-app, pm-icp-slam) applies it through this one class, so
 * that "auto" means the same everywhere:
 *   auto    the scan's own odometry when it has one, else the latest reading
 *   scan    only the scan's own odometry (readings are ignored)
 *   events  only the readings (the odometry on the laser line is ignored)
 */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/slam/SlamConfig.h>

#include <optional>
#include <string>

namespace pmslam
{
class OdometrySelector
{
   public:
	explicit OdometrySelector(OdometrySource source = OdometrySource::Auto) : m_source(source) {}

	/** An odometry reading of the log (LogEvent::Kind::Odometry): true when the source uses readings
	 * (it is then the latest one), false when it is to be ignored. */
	bool takeReading(const LogEvent& ev);
	/** The odometry written with the scan, when there is one and the source uses it. It takes
	 * precedence over the readings (PerfectMatchSlam::processScan's `odometryAtScan`). */
	std::optional<mrpt::math::TPose2D> scanOdometry(const LogEvent& ev) const;
	/** The odometry predicting the scan: its own (scanOdometry()), else the latest reading taken
	 * (for a front-end that keeps no readings itself); empty when there is none. */
	std::optional<mrpt::math::TPose2D> forScan(const LogEvent& ev) const;

	OdometrySource source() const { return m_source; }

   private:
	OdometrySource m_source;
	std::optional<mrpt::math::TPose2D> m_latestReading;
};

/** "auto", "scan" or "events" (OdometrySource's names in the [Log] section); throws
 * std::invalid_argument naming the three otherwise. */
OdometrySource odometrySourceFromName(const std::string& name);

}  // namespace pmslam
