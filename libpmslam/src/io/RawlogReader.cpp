/* pmslam — MRPT rawlog reader (see RawlogReader.h). */
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <pmslam/sensor/ScanSlice.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <pmslam/io/RawlogReader.h>

#include "CarmenGeometry.h"
#include "RawlogProbe.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

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

/** Uncompressed size of the file: its size, or the gzip ISIZE trailer. */
std::uint64_t contentSize(const std::string& path)
{
	std::error_code ec;
	const std::uint64_t size = std::filesystem::file_size(path, ec);
	if (ec) return 0;
	std::ifstream f(path, std::ios::binary);
	unsigned char magic[2] = {0, 0};
	if (!f.read(reinterpret_cast<char*>(magic), 2) || magic[0] != 0x1f || magic[1] != 0x8b || size < 18) return size;
	unsigned char t[4];
	f.seekg(static_cast<std::streamoff>(size - 4));
	if (!f.read(reinterpret_cast<char*>(t), 4)) return size;
	const std::uint64_t isize = std::uint64_t(t[0]) | (std::uint64_t(t[1]) << 8) | (std::uint64_t(t[2]) << 16) |
								(std::uint64_t(t[3]) << 24);
	// Smaller than the file: > 4 GiB wrapped; implausibly large: not a trailer (damaged copy).
	return (isize >= size && isize <= 50 * size) ? isize : size;
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

struct RawlogReader::Impl
{
	LogReaderOptions opts;
	std::unique_ptr<RawlogProbe> probe;  // runs ahead: only objects it got through are read here
	mrpt::io::CFileGZInputStream in;
	std::unique_ptr<mrpt::serialization::CArchive> arch;
	std::deque<LogEvent> queue;
	std::optional<LogEvent> held;  // odometry whose action had no timestamp
	std::size_t objects = 0;
	bool done = false;
	mrpt::poses::CPose2D odom;	// accumulated action–observation odometry
	bool odomEmitted = false;
	bool fixWarned = false;
	std::set<std::string> sliceWarned;	// reasons a 3D observation could not be sliced, warned once each
	double lastTs = 0;

	mutable bool estimated = false;
	mutable std::size_t estimate = 0;

	void push(LogEvent&& e)
	{
		if (e.kind == LogEvent::Kind::Odometry) odomEmitted = true;
		lastTs = e.timestamp;
		queue.push_back(std::move(e));
	}

	void flushHeld(double ts)
	{
		if (!held) return;
		held->timestamp = ts;
		push(std::move(*held));
		held.reset();
	}
};

RawlogReader::RawlogReader(const std::string& path, const LogReaderOptions& opts)
	: LogReader(path), m_impl(std::make_unique<Impl>())
{
	m_impl->opts = opts;
	bool ok = false;
	try
	{
		ok = m_impl->in.open(path);
	}
	catch (const std::exception&)
	{
	}
	if (!ok) throw LogError("pmslam: cannot open rawlog '" + path + "' for reading");
	m_impl->probe = std::make_unique<RawlogProbe>(path, opts.rawlogObjectTimeout);
	m_impl->arch = mrpt::serialization::archiveUniquePtrFrom(m_impl->in);
}

RawlogReader::~RawlogReader() = default;

std::size_t RawlogReader::estimatedScanCount() const
{
	Impl& d = *m_impl;
	if (d.estimated) return d.estimate;
	d.estimated = true;
	try
	{
		mrpt::io::CFileGZInputStream in;
		if (!in.open(m_path)) return 0;
		auto arch = mrpt::serialization::archiveFrom(in);
		std::size_t scans = 0;
		bool atEnd = false;
		for (std::size_t k = 0; k < 400 && in.getPosition() < (8u << 20); ++k)
		{
			if (!d.probe->safeToRead(k + 1))
			{
				atEnd = true;
				break;
			}
			mrpt::serialization::CSerializable::Ptr obj;
			try
			{
				obj = arch.ReadObject();
			}
			catch (const std::exception&)
			{
				atEnd = true;
				break;
			}
			if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obj))
				++scans;
			else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
			{
				for (const auto& o : *sf)
					if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o) || (o && isSliceable(*o))) ++scans;
			}
			else if (auto ob = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj); ob && isSliceable(*ob))
				++scans;
		}
		const std::uint64_t consumed = in.getPosition();
		if (atEnd || consumed == 0)
			d.estimate = scans;
		else
		{
			const double total = static_cast<double>(std::max<std::uint64_t>(contentSize(m_path), consumed));
			d.estimate = static_cast<std::size_t>(std::llround(scans * total / static_cast<double>(consumed)));
		}
	}
	catch (const std::exception&)
	{
	}
	return d.estimate;
}

bool RawlogReader::next(LogEvent& ev)
{
	Impl& d = *m_impl;
	while (d.queue.empty())
	{
		if (d.done) return false;

		// Stops reading for good, with the damage warning unless the file just ended (reason empty).
		auto stop = [&](const std::string& reason) {
			d.flushHeld(d.lastTs);
			d.done = true;
			if (!reason.empty())
				warn(m_path + ": damaged after object " + std::to_string(d.objects) + " (" + reason + "), stopping");
		};
		if (!d.probe->safeToRead(d.objects + 1))
		{
			// MRPT would crash, hang, throw or exhaust memory on the next object: stop before it.
			const std::string& why = d.probe->failure();
			stop(d.probe->failedWithException() ? exceptionSummary(why) : why);
			continue;
		}
		const std::uint64_t pos0 = d.in.getPosition();
		mrpt::serialization::CSerializable::Ptr obj;
		std::string failure;
		try
		{
			obj = d.arch->ReadObject();
		}
		catch (const std::exception& e)
		{
			failure = exceptionSummary(e.what());
		}
		catch (...)
		{
			failure = "unknown exception";
		}
		if (!failure.empty())
		{
			std::uint64_t pos1 = pos0;
			try
			{
				pos1 = d.in.getPosition();
			}
			catch (const std::exception&)
			{
			}
			stop(pos1 != pos0 ? failure : std::string());  // no byte of a next object: a clean end
			continue;
		}

		++d.objects;
		m_stats.linesOrObjects = d.objects;
		if (!obj) continue;

		auto handleObservation = [&](const mrpt::obs::CObservation::Ptr& o) {
			auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o);
			if (!scan && isSliceable(*o))
			{
				// A 3D lidar or an RGB-D camera: mapped through its horizontal slice.
				std::string why;
				scan = sliceObservation(*o, d.opts.slice, &why);
				if (!scan)
				{
					++m_stats.skipped;
					if (why.empty()) why = "no point between " + std::to_string(d.opts.slice.minHeight) + " and " +
										   std::to_string(d.opts.slice.maxHeight) + " m of height";
					if (d.sliceWarned.insert(why).second)
						warn(m_path + ": object " + std::to_string(d.objects) + " (" + o->GetRuntimeClass()->className +
							 ", sensor " + o->sensorLabel + "): " + why + ", skipped (and others like it)");
					return;
				}
			}
			if (scan)
			{
				if (scan->getScanSize() < 2)
				{
					++m_stats.skipped;
					warn(m_path + ": object " + std::to_string(d.objects) + ": scan with " +
						 std::to_string(scan->getScanSize()) + " beams, skipped");
					return;
				}
				if (hasCarmenImportGeometry(*scan))
				{
					if (!d.fixWarned)
					{
						d.fixWarned = true;
						char b[64];
						std::snprintf(b, sizeof(b), "%.2f", d.opts.noReturnRange);
						warn(m_path + ": scans labelled " + scan->sensorLabel +
							 " carry the geometry of MRPT's Carmen importer (aperture = N x 0.5 deg); re-applied the "
							 "Carmen 180-degree fan from -90 deg and no-return range " +
							 b + " m");
					}
					applyCarmenGeometry(*scan, d.opts.noReturnRange);
				}
				if (const std::string why = badGeometry(*scan); !why.empty())
				{
					++m_stats.skipped;
					warn(m_path + ": object " + std::to_string(d.objects) + ": scan with " + why + ", skipped");
					return;
				}
				bool anyValid = false;
				for (std::size_t i = 0; i < scan->getScanSize(); ++i)
				{
					const float r = scan->getScanRange(i);
					if (!scan->getScanRangeValidity(i)) continue;
					if (std::isfinite(r) && r > 0.0f && r <= kMaxReading)
						anyValid = true;
					else
						scan->setScanRangeValidity(i, false);
				}
				if (!anyValid)
				{  // as for Carmen lines: nothing to match or map
					++m_stats.skipped;
					warn(m_path + ": object " + std::to_string(d.objects) + ": scan has no valid beam, skipped");
					return;
				}
				LogEvent e;
				e.kind = LogEvent::Kind::Scan;
				e.timestamp = stampToDouble(scan->timestamp);
				e.scan = scan;
				e.sourceIndex = d.objects;
				d.push(std::move(e));
			}
			else if (auto od = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
			{
				if (!plausible(od->odometry.asTPose()))	 // NaN fails too
				{
					++m_stats.skipped;
					warn(m_path + ": object " + std::to_string(d.objects) + ": implausible odometry pose, skipped");
					return;
				}
				LogEvent e;
				e.kind = LogEvent::Kind::Odometry;
				e.timestamp = stampToDouble(od->timestamp);
				e.odometry = od->odometry.asTPose();
				e.sourceIndex = d.objects;
				d.push(std::move(e));
			}
		};

		if (auto ac = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
		{
			d.flushHeld(d.lastTs);
			const auto mv = ac->getBestMovementEstimation();
			const bool usable = mv && mv->poseChange && plausible(mv->poseChange->getMeanVal().asTPose()) &&
								plausible((d.odom + mv->poseChange->getMeanVal()).asTPose());
			if (mv && mv->poseChange && !usable)
			{
				++m_stats.skipped;
				warn(m_path + ": object " + std::to_string(d.objects) + ": implausible odometry increment, skipped");
			}
			if (usable)
			{
				d.odom = d.odom + mv->poseChange->getMeanVal();
				LogEvent e;
				e.kind = LogEvent::Kind::Odometry;
				e.odometry = d.odom.asTPose();
				e.sourceIndex = d.objects;
				if (mv->timestamp != INVALID_TIMESTAMP)
				{
					e.timestamp = mrpt::Clock::toDouble(mv->timestamp);
					d.push(std::move(e));
				}
				else
					d.held = std::move(e);
			}
		}
		else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
		{
			bool haveTs = false, hasScan = false;
			double sfTs = d.lastTs;
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
			d.flushHeld(sfTs);
			if (hasScan && !d.odomEmitted)
			{
				LogEvent e;  // the accumulated odometry before any action: the origin
				e.kind = LogEvent::Kind::Odometry;
				e.timestamp = sfTs;
				e.odometry = d.odom.asTPose();
				e.sourceIndex = d.objects;
				d.push(std::move(e));
			}
			for (const auto& o : *sf)
				if (o) handleObservation(o);
		}
		else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
		{
			d.flushHeld(d.lastTs);
			handleObservation(o);
		}
	}
	ev = std::move(d.queue.front());
	d.queue.pop_front();
	if (ev.kind == LogEvent::Kind::Scan)
		++m_stats.scans;
	else
		++m_stats.odometry;
	return true;
}

}  // namespace pmslam
