/* pmslam — MRPT objects to LogEvent (see ObservationEvents.h). */
#include <mrpt/core/Clock.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/system/datetime.h>
#include <pmslam/io/ObservationEvents.h>
#include <pmslam/sensor/ScanSlice.h>

#include "CarmenGeometry.h"

#include <cmath>
#include <cstdio>
#include <utility>

namespace pmslam
{
namespace
{
double stampToDouble(const mrpt::system::TTimeStamp& t)
{
	return t == INVALID_TIMESTAMP ? 0.0 : mrpt::Clock::toDouble(t);
}

/** carmen2rawlog signature: label FLASER/RLASER and MRPT's aperture = N × 0.5°. */
bool hasCarmenImportGeometry(const mrpt::obs::CObservation2DRangeScan& s)
{
	const std::size_t n = s.getScanSize();
	if (n < 2 || (s.sensorLabel != "FLASER" && s.sensorLabel != "RLASER")) return false;
	const double mrptAperture = static_cast<double>(n) * 0.5 * M_PI / 180.0;
	return std::abs(static_cast<double>(s.aperture) - mrptAperture) < 1e-4;
}

/** Re-applies the Carmen FLASER/RLASER conventions (see CarmenLogReader.h). */
void applyCarmenGeometry(mrpt::obs::CObservation2DRangeScan& s, double noReturnRange)
{
	const std::size_t n = s.getScanSize();
	const double step = carmen::flaserBeamStep(n);
	const double aperture = step * static_cast<double>(n - 1);
	double laserYaw = s.sensorPose.yaw();
	if (s.sensorLabel == "RLASER" && std::abs(mrpt::math::wrapToPi(laserYaw)) < 0.5 * M_PI) laserYaw += M_PI;
	const double yaw = mrpt::math::wrapToPi(laserYaw - 0.5 * M_PI + 0.5 * aperture);
	const auto& p = s.sensorPose;
	s.sensorPose = mrpt::poses::CPose3D(p.x(), p.y(), p.z(), yaw, p.pitch(), p.roll());
	s.aperture = static_cast<float>(aperture);
	s.rightToLeft = true;
	s.maxRange = static_cast<float>(noReturnRange);
	for (std::size_t i = 0; i < n; ++i)
	{
		const float r = s.getScanRange(i);
		s.setScanRangeValidity(i, std::isfinite(r) && r > 0.0f && r < s.maxRange);
	}
}

/** Poses beyond these are damage, not a robot (as in CarmenLogReader.cpp). */
constexpr double kMaxCoordinate = 1e7;	// m
constexpr double kMaxHeading = 1e3;	 // rad
constexpr double kMaxSensorOffset = 100.0;	// m
/** No 2D laser measures farther (m): a longer "valid" reading is damage and made invalid. */
constexpr float kMaxReading = 1000.0f;

bool plausible(const mrpt::math::TPose2D& p)
{
	return std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate && std::abs(p.phi) <= kMaxHeading;
}

/** Empty if the scan's geometry is usable, else why not. */
std::string badGeometry(const mrpt::obs::CObservation2DRangeScan& s)
{
	const auto& p = s.sensorPose;
	for (double v : {p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll()})
		if (!std::isfinite(v)) return "non-finite sensor pose";
	if (std::hypot(p.x(), p.y()) > kMaxSensorOffset || std::abs(p.z()) > kMaxSensorOffset)
		return "sensor pose more than 100 m from the robot";
	if (!std::isfinite(s.aperture) || std::abs(s.aperture) > 100.0) return "implausible aperture";
	return {};
}

}  // namespace

ObservationEvents::ObservationEvents(const LogReaderOptions& opts, std::string source,
									 std::function<void(const std::string&)> warn, LogReadStats& stats)
	: m_opts(opts), m_source(std::move(source)), m_warn(std::move(warn)), m_stats(stats)
{
}

void ObservationEvents::skip(std::size_t index, const std::string& why)
{
	++m_stats.skipped;
	m_warn(m_source + ": object " + std::to_string(index) + ": " + why + ", skipped");
}

void ObservationEvents::push(LogEvent&& e, std::deque<LogEvent>& out)
{
	if (e.kind == LogEvent::Kind::Odometry) m_odomEmitted = true;
	m_lastTs = e.timestamp;
	out.push_back(std::move(e));
}

void ObservationEvents::flushHeld(double ts, std::deque<LogEvent>& out)
{
	if (!m_held) return;
	m_held->timestamp = ts;
	push(std::move(*m_held), out);
	m_held.reset();
}

/** A 2D scan as it is, or a 3D lidar's / RGB-D camera's horizontal slice; null (warned once per reason) if
 *  the slice holds no point, or if the observation is no range sensor at all. */
mrpt::obs::CObservation2DRangeScan::Ptr ObservationEvents::asScan(const mrpt::obs::CObservation::Ptr& o, std::size_t index)
{
	if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) return scan;
	if (!isSliceable(*o)) return nullptr;
	std::string why;
	auto scan = sliceObservation(*o, m_opts.slice, &why);
	if (scan) return scan;
	++m_stats.skipped;
	if (why.empty())
		why = "no point between " + std::to_string(m_opts.slice.minHeight) + " and " +
			  std::to_string(m_opts.slice.maxHeight) + " m of height";
	if (m_sliceWarned.insert(why).second)
		m_warn(m_source + ": object " + std::to_string(index) + " (" + o->GetRuntimeClass()->className + ", sensor " +
			   o->sensorLabel + "): " + why + ", skipped (and others like it)");
	return nullptr;
}

/** Repairs what can be repaired (the Carmen importer's geometry, damaged readings made invalid); false (skipped,
 *  said) if nothing usable is left. */
bool ObservationEvents::usableScan(mrpt::obs::CObservation2DRangeScan& scan, std::size_t index)
{
	if (scan.getScanSize() < 2)
	{
		skip(index, "scan with " + std::to_string(scan.getScanSize()) + " beams");
		return false;
	}
	if (hasCarmenImportGeometry(scan))
	{
		if (!m_fixWarned)
		{
			m_fixWarned = true;
			char b[64];
			std::snprintf(b, sizeof(b), "%.2f", m_opts.noReturnRange);
			m_warn(m_source + ": scans labelled " + scan.sensorLabel +
				   " carry the geometry of MRPT's Carmen importer (aperture = N x 0.5 deg); re-applied the "
				   "Carmen 180-degree fan from -90 deg and no-return range " +
				   b + " m");
		}
		applyCarmenGeometry(scan, m_opts.noReturnRange);
	}
	if (const std::string why = badGeometry(scan); !why.empty())
	{
		skip(index, "scan with " + why);
		return false;
	}
	bool anyValid = false;
	for (std::size_t i = 0; i < scan.getScanSize(); ++i)
	{
		const float r = scan.getScanRange(i);
		if (!scan.getScanRangeValidity(i)) continue;
		if (std::isfinite(r) && r > 0.0f && r <= kMaxReading)
			anyValid = true;
		else
			scan.setScanRangeValidity(i, false);
	}
	if (!anyValid) skip(index, "scan has no valid beam");  // as for Carmen lines: nothing to match or map
	return anyValid;
}

void ObservationEvents::addObservation(const mrpt::obs::CObservation::Ptr& o, std::size_t index, std::deque<LogEvent>& out)
{
	if (auto scan = asScan(o, index))
	{
		if (!usableScan(*scan, index)) return;
		LogEvent e;
		e.kind = LogEvent::Kind::Scan;
		e.timestamp = stampToDouble(scan->timestamp);
		e.scan = scan;
		e.sourceIndex = index;
		push(std::move(e), out);
	}
	else if (auto od = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
	{
		if (!plausible(od->odometry.asTPose()))  // NaN fails too
		{
			skip(index, "implausible odometry pose");
			return;
		}
		LogEvent e;
		e.kind = LogEvent::Kind::Odometry;
		e.timestamp = stampToDouble(od->timestamp);
		e.odometry = od->odometry.asTPose();
		e.sourceIndex = index;
		push(std::move(e), out);
	}
}

void ObservationEvents::add(const mrpt::serialization::CSerializable::Ptr& obj, std::size_t index, std::deque<LogEvent>& out)
{
	if (!obj) return;
	if (auto ac = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
	{
		flushHeld(m_lastTs, out);
		const auto mv = ac->getBestMovementEstimation();
		const bool usable = mv && mv->poseChange && plausible(mv->poseChange->getMeanVal().asTPose()) &&
							plausible((m_odom + mv->poseChange->getMeanVal()).asTPose());
		if (mv && mv->poseChange && !usable)
		{
			skip(index, "implausible odometry increment");
		}
		if (usable)
		{
			m_odom = m_odom + mv->poseChange->getMeanVal();
			LogEvent e;
			e.kind = LogEvent::Kind::Odometry;
			e.odometry = m_odom.asTPose();
			e.sourceIndex = index;
			if (mv->timestamp != INVALID_TIMESTAMP)
			{
				e.timestamp = mrpt::Clock::toDouble(mv->timestamp);
				push(std::move(e), out);
			}
			else
				m_held = std::move(e);
		}
	}
	else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
	{
		bool haveTs = false, hasScan = false;
		double sfTs = m_lastTs;
		for (const auto& o : *sf)
		{
			if (!o) continue;
			if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o) || isSliceable(*o)) hasScan = true;
			if (o->timestamp != INVALID_TIMESTAMP)
			{
				const double t = mrpt::Clock::toDouble(o->timestamp);
				if (!haveTs || t < sfTs) sfTs = t;
				haveTs = true;
			}
		}
		flushHeld(sfTs, out);
		if (hasScan && !m_odomEmitted)
		{
			LogEvent e;  // the accumulated odometry before any action: the origin
			e.kind = LogEvent::Kind::Odometry;
			e.timestamp = sfTs;
			e.odometry = m_odom.asTPose();
			e.sourceIndex = index;
			push(std::move(e), out);
		}
		for (const auto& o : *sf)
			if (o) addObservation(o, index, out);
	}
	else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
	{
		flushHeld(m_lastTs, out);
		addObservation(o, index, out);
	}
}

}  // namespace pmslam
