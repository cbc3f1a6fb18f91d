/* pmslam — Carmen log reader (see CarmenLogReader.h). */
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/carmen_log_tools.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <pmslam/util/ExceptionText.h>
#include <pmslam/io/CarmenLogReader.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <vector>

#include "CarmenGeometry.h"

namespace pmslam
{
namespace
{
constexpr std::size_t kMaxBeams = 100000;
/** Pose fields beyond these are damage, not a robot: |x|, |y| in m (Earth scale), |theta| in rad. */
constexpr double kMaxCoordinate = 1e7;
constexpr double kMaxHeading = 1e3;
/** A laser farther than this from the robot base (m) is not mounted on it. */
constexpr double kMaxSensorOffset = 100.0;
constexpr std::size_t kChunk = 1 << 16;

/** Reads a (possibly gz-compressed) text file line by line. */
class LineSource
{
   public:
	bool open(const std::string& path) { return m_in.open(path); }

	/** False at end of file. Throws std::exception on a read error. */
	bool getline(std::string& line)
	{
		for (;;)
		{
			const std::size_t nl = m_buf.find('\n', m_pos);
			if (nl != std::string::npos)
			{
				line.assign(m_buf, m_pos, nl - m_pos);
				m_pos = nl + 1;
				return true;
			}
			if (m_eof)
			{
				if (m_pos >= m_buf.size()) return false;
				line.assign(m_buf, m_pos, std::string::npos);
				m_pos = m_buf.size();
				return true;
			}
			m_buf.erase(0, m_pos);
			m_pos = 0;
			char tmp[kChunk];
			const std::size_t got = m_in.Read(tmp, sizeof(tmp));
			if (got == 0)
				m_eof = true;
			else
				m_buf.append(tmp, got);
		}
	}

   private:
	mrpt::io::CFileGZInputStream m_in;
	std::string m_buf;
	std::size_t m_pos = 0;
	bool m_eof = false;
};

void splitFields(const std::string& line, std::vector<std::string>& out)
{
	out.clear();
	std::size_t i = 0;
	const std::size_t n = line.size();
	auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; };
	while (i < n)
	{
		while (i < n && isSpace(line[i])) ++i;
		if (i >= n) break;
		std::size_t j = i;
		while (j < n && !isSpace(line[j])) ++j;
		out.emplace_back(line, i, j - i);
		i = j;
	}
}

/** Whole-token number (strtod syntax, so "nan"/"inf" parse and are caught by
 * the finiteness checks of the callers). */
bool parseNumber(const std::string& s, double& v)
{
	if (s.empty()) return false;
	char* end = nullptr;
	v = std::strtod(s.c_str(), &end);
	return end == s.c_str() + s.size();
}

/** Whole-token non-negative decimal integer. */
bool parseCount(const std::string& s, std::size_t& v)
{
	if (s.empty() || s.size() > 9) return false;
	v = 0;
	for (char c : s)
	{
		if (c < '0' || c > '9') return false;
		v = v * 10 + static_cast<std::size_t>(c - '0');
	}
	return true;
}

std::string fmt6(double v)
{
	char b[64];
	std::snprintf(b, sizeof(b), "%.6f", v);
	return b;
}

/** Thrown internally to skip the current line. */
struct SkipLine
{
	std::string reason;
};

}  // namespace

struct CarmenLogReader::Impl
{
	LogReaderOptions opts;
	LineSource src;
	std::size_t lineNo = 0;
	bool done = false;
	bool haveLatest = false;
	double latestTs = 0;
	std::vector<std::string> f;

	mutable bool counted = false;
	mutable std::size_t scanCount = 0;

	double number(std::size_t i, const char* what) const
	{
		double v = 0;
		if (!parseNumber(f[i], v)) throw SkipLine{std::string("non-numeric ") + what + " '" + f[i] + "'"};
		if (!std::isfinite(v)) throw SkipLine{std::string("non-finite ") + what + " '" + f[i] + "'"};
		return v;
	}

	std::size_t count(std::size_t i, const char* what, std::size_t maxValue) const
	{
		std::size_t v = 0;
		if (!parseCount(f[i], v) || v > maxValue) throw SkipLine{std::string("bad ") + what + " '" + f[i] + "'"};
		return v;
	}

	void ranges(std::size_t first, std::size_t n, std::vector<float>& out) const
	{
		out.resize(n);
		for (std::size_t i = 0; i < n; ++i)
		{
			double v = 0;
			const std::string& t = f[first + i];
			if (!parseNumber(t, v))
				throw SkipLine{"non-numeric range '" + t + "' (beam " + std::to_string(i) + ")"};
			if (!std::isfinite(v)) throw SkipLine{"non-finite range '" + t + "' (beam " + std::to_string(i) + ")"};
			if (v < 0) throw SkipLine{"negative range '" + t + "' (beam " + std::to_string(i) + ")"};
			out[i] = static_cast<float>(v);
		}
	}

	void checkPose(const mrpt::math::TPose2D& p, const char* what) const
	{
		if (std::abs(p.x) > kMaxCoordinate || std::abs(p.y) > kMaxCoordinate || std::abs(p.phi) > kMaxHeading)
		{
			char b[120];
			std::snprintf(b, sizeof(b), " (%.6g, %.6g, %.6g)", p.x, p.y, p.phi);
			throw SkipLine{std::string("implausible ") + what + b};
		}
	}

	void checkTimestamp(double ts) const
	{
		if (ts < 0) throw SkipLine{"negative ipc_timestamp " + fmt6(ts)};
		if (haveLatest && ts < latestTs - kBackwardsToleranceSec)
			throw SkipLine{"timestamp " + fmt6(ts) + " goes back " + fmt6(latestTs - ts) + " s before " +
						   fmt6(latestTs)};
	}

	void accept(double ts)
	{
		if (!haveLatest || ts > latestTs) latestTs = ts;
		haveLatest = true;
	}
};

CarmenLogReader::CarmenLogReader(const std::string& path, const LogReaderOptions& opts)
	: LogReader(path), m_impl(std::make_unique<Impl>())
{
	m_impl->opts = opts;
	if (!m_impl->src.open(path)) throw LogError("pmslam: cannot open Carmen log '" + path + "' for reading");
}

CarmenLogReader::~CarmenLogReader() = default;

double CarmenLogReader::flaserBeamStep(std::size_t n)
{
	return carmen::flaserBeamStep(n);
}

std::size_t CarmenLogReader::estimatedScanCount() const
{
	if (m_impl->counted) return m_impl->scanCount;
	m_impl->counted = true;
	try
	{
		LineSource s;
		if (!s.open(m_path)) return 0;
		std::string line;
		std::size_t c = 0;
		while (s.getline(line))
		{
			const auto b = line.find_first_not_of(" \t");
			if (b == std::string::npos) continue;
			if (line.compare(b, 7, "FLASER ") == 0 || line.compare(b, 7, "RLASER ") == 0 ||
				line.compare(b, 12, "ROBOTLASER1 ") == 0)
				++c;
		}
		m_impl->scanCount = c;
	}
	catch (const std::exception&)
	{
	}
	return m_impl->scanCount;
}

namespace
{
/** Runs MRPT's importer on one line; returns its scan and odometry objects. */
void mrptParse(const std::string& line, std::size_t n, mrpt::obs::CObservation2DRangeScan::Ptr& scan,
			   mrpt::obs::CObservationOdometry::Ptr& odo)
{
	std::istringstream ss(line);
	std::vector<mrpt::obs::CObservation::Ptr> obs;
	// The time origin is irrelevant: MRPT 2.5.8 does not keep the
	// ipc_timestamp anyway, it is set from the line afterwards. Throws on
	// lines it cannot parse.
	mrpt::obs::carmen_log_parse_line(ss, obs, mrpt::Clock::fromDouble(0.0));
	for (const auto& o : obs)
	{
		if (!o) continue;
		if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) scan = s;
		if (auto d = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) odo = d;
	}
	if (!scan) throw SkipLine{"MRPT's Carmen importer returned no scan"};
	if (scan->getScanSize() != n)
		throw SkipLine{"MRPT's Carmen importer returned " + std::to_string(scan->getScanSize()) +
					   " beams instead of " + std::to_string(n)};
}

/** Sets the corrected fan geometry, range limits, validity and timestamp. */
void finishScan(mrpt::obs::CObservation2DRangeScan& scan, const std::vector<float>& r, double laserX,
				double laserY, double laserYaw, double fanStart, double step, double maxRange, double ts)
{
	const std::size_t n = r.size();
	const double aperture = step * static_cast<double>(n - 1);
	scan.aperture = static_cast<float>(aperture);
	scan.rightToLeft = true;
	// Beam i at laserYaw + fanStart + i·step == yaw(sensorPose) + getScanAngle(i).
	const double yaw = mrpt::math::wrapToPi(laserYaw + fanStart + 0.5 * aperture);
	scan.sensorPose = mrpt::poses::CPose3D(laserX, laserY, 0.0, yaw, 0.0, 0.0);
	scan.maxRange = static_cast<float>(maxRange);
	for (std::size_t i = 0; i < n; ++i)
	{
		// The text is the reference: keep the raw value even for "no return".
		scan.setScanRange(i, r[i]);
		scan.setScanRangeValidity(i, r[i] > 0.0f && r[i] < scan.maxRange);
	}
	scan.timestamp = mrpt::Clock::fromDouble(ts);
}

bool anyValid(const mrpt::obs::CObservation2DRangeScan& scan)
{
	for (std::size_t i = 0; i < scan.getScanSize(); ++i)
		if (scan.getScanRangeValidity(i)) return true;
	return false;
}

}  // namespace

bool CarmenLogReader::next(LogEvent& ev)
{
	Impl& d = *m_impl;
	if (d.done) return false;
	std::string line;
	std::vector<float> r;
	for (;;)
	{
		try
		{
			if (!d.src.getline(line))
			{
				d.done = true;
				return false;
			}
		}
		catch (const std::exception& e)
		{
			warn(m_path + ":" + std::to_string(d.lineNo + 1) + ": read error (" + exceptionSummary(e.what()) +
				 "), stopping");
			d.done = true;
			return false;
		}
		++d.lineNo;
		++m_stats.linesOrObjects;
		splitFields(line, d.f);
		if (d.f.empty()) continue;
		const std::string& kw = d.f[0];
		const bool isOdom = kw == "ODOM";
		const bool isFront = kw == "FLASER";
		const bool isRear = kw == "RLASER";
		const bool isRobotLaser = kw == "ROBOTLASER1";
		if (isOdom && !d.opts.useOdomLines) continue;
		if (!isOdom && !isFront && !isRear && !isRobotLaser) continue;  // PARAM, SYNC, #..., unknown

		try
		{
			const auto& f = d.f;
			if (isOdom)
			{
				// MRPT's importer ignores ODOM lines: parsed here.
				// ODOM x y theta tv rv accel ipc_timestamp host logger_timestamp
				if (f.size() != 10)
					throw SkipLine{"ODOM line has " + std::to_string(f.size()) + " fields, expected 10"};
				LogEvent e;
				e.kind = LogEvent::Kind::Odometry;
				e.odometry = mrpt::math::TPose2D(d.number(1, "x"), d.number(2, "y"), d.number(3, "theta"));
				d.checkPose(e.odometry, "odometry pose");
				for (std::size_t i = 4; i <= 6; ++i) d.number(i, "velocity field");
				e.timestamp = d.number(7, "ipc_timestamp");
				d.number(9, "logger_timestamp");
				d.checkTimestamp(e.timestamp);
				e.sourceIndex = d.lineNo;
				d.accept(e.timestamp);
				++m_stats.odometry;
				ev = std::move(e);
				return true;
			}

			// ---- laser lines: validate the text first ----
			if (f.size() < 2) throw SkipLine{kw + " line without beam count"};
			std::size_t n = 0, posesAt = 0, tsAt = 0;
			double start = 0, step = 0, maxRange = d.opts.noReturnRange;
			if (isRobotLaser)
			{
				if (f.size() < 10) throw SkipLine{"ROBOTLASER1 line has only " + std::to_string(f.size()) + " fields"};
				n = d.count(8, "beam count", kMaxBeams);
				if (n < 2) throw SkipLine{"beam count " + std::to_string(n) + " (need at least 2)"};
				if (f.size() < 10 + n)
					throw SkipLine{"beam count " + std::to_string(n) + " disagrees with the line (" +
								   std::to_string(f.size()) + " fields)"};
				const std::size_t m = d.count(9 + n, "remission count", kMaxBeams);
				const std::size_t expected = n + m + 24;
				if (f.size() != expected)
					throw SkipLine{"beam count " + std::to_string(n) + " disagrees with the line (" +
								   std::to_string(f.size()) + " fields, expected " + std::to_string(expected) + ")"};
				d.number(1, "laser_type");
				start = d.number(2, "start_angle");
				const double fov = d.number(3, "field_of_view");
				step = d.number(4, "angular_resolution");
				const double lineMax = d.number(5, "maximum_range");
				d.number(6, "accuracy");
				d.number(7, "remission_mode");
				if (!(step > 0))
				{
					if (!(fov > 0)) throw SkipLine{"no usable angular_resolution or field_of_view"};
					step = fov / static_cast<double>(n - 1);
				}
				else if (fov > 0)
				{
					const double tol = 0.5 * step + 1e-6;
					if (std::abs(fov - step * static_cast<double>(n - 1)) > tol &&
						std::abs(fov - step * static_cast<double>(n)) > tol)
						throw SkipLine{"beam count " + std::to_string(n) + " disagrees with field_of_view " +
									   f[3] + " / angular_resolution " + f[4]};
				}
				if (lineMax > 0 && lineMax < maxRange) maxRange = lineMax;
				d.ranges(9, n, r);
				for (std::size_t i = 0; i < m; ++i) d.number(10 + n + i, "remission");
				posesAt = 10 + n + m;
				for (std::size_t i = posesAt + 6; i < posesAt + 11; ++i) d.number(i, "velocity field");
				tsAt = posesAt + 11;
			}
			else
			{
				n = d.count(1, "beam count", kMaxBeams);
				if (n < 2) throw SkipLine{"beam count " + std::to_string(n) + " (need at least 2)"};
				const std::size_t expected = n + 11;
				if (f.size() != expected)
					throw SkipLine{"beam count " + std::to_string(n) + " disagrees with the line (" +
								   std::to_string(f.size()) + " fields, expected " + std::to_string(expected) + ")"};
				d.ranges(2, n, r);
				step = flaserBeamStep(n);
				start = -0.5 * M_PI;
				posesAt = 2 + n;
				tsAt = posesAt + 6;
			}
			const mrpt::math::TPose2D laser(d.number(posesAt, "laser x"), d.number(posesAt + 1, "laser y"),
											d.number(posesAt + 2, "laser theta"));
			const mrpt::math::TPose2D robot(d.number(posesAt + 3, "odometry x"), d.number(posesAt + 4, "odometry y"),
											d.number(posesAt + 5, "odometry theta"));
			const double ts = d.number(tsAt, "ipc_timestamp");
			d.number(tsAt + 2, "logger_timestamp");
			d.checkTimestamp(ts);
			d.checkPose(laser, "laser pose");
			d.checkPose(robot, "odometry pose");
			const mrpt::poses::CPose2D rel(mrpt::poses::CPose2D(laser) - mrpt::poses::CPose2D(robot));
			if (std::hypot(rel.x(), rel.y()) > kMaxSensorOffset)
				throw SkipLine{"laser pose " + fmt6(std::hypot(rel.x(), rel.y())) + " m away from the odometry pose"};

			// ---- MRPT's importer, then the corrections ----
			mrpt::obs::CObservation2DRangeScan::Ptr scan;
			mrpt::obs::CObservationOdometry::Ptr odo;
			try
			{
				mrptParse(line, n, scan, odo);
			}
			catch (const std::exception& e)
			{
				throw SkipLine{"MRPT's Carmen importer rejected the line (" + exceptionSummary(e.what()) + ")"};
			}
			for (std::size_t i = 0; i < n; ++i)
				if (std::abs(scan->getScanRange(i) - r[i]) > 1e-5f * std::max(1.0f, r[i]))
					throw SkipLine{"MRPT's Carmen importer read beam " + std::to_string(i) + " as " +
								   fmt6(scan->getScanRange(i)) + " instead of " + f[(isRobotLaser ? 9 : 2) + i]};
			// MRPT computes the sensor offset as laser ⊖ odometry, i.e. the
			// laser pose in the robot frame: right, kept (x, y, yaw).
			const auto& sp = scan->sensorPose;
			if (std::abs(sp.x() - rel.x()) > 1e-4 || std::abs(sp.y() - rel.y()) > 1e-4)
				throw SkipLine{"MRPT's Carmen importer computed a different sensor offset"};
			if (odo && (std::abs(odo->odometry.x() - robot.x) > 1e-4 || std::abs(odo->odometry.y() - robot.y) > 1e-4))
				throw SkipLine{"MRPT's Carmen importer read a different odometry pose"};
			double laserYaw = rel.phi();
			if (isRear && std::abs(mrpt::math::wrapToPi(laserYaw)) < 0.5 * M_PI) laserYaw += M_PI;
			finishScan(*scan, r, sp.x(), sp.y(), laserYaw, start, step, maxRange, ts);
			if (!anyValid(*scan)) throw SkipLine{"scan has no valid beam"};

			LogEvent e;
			e.kind = LogEvent::Kind::Scan;
			e.timestamp = ts;
			e.scan = scan;
			e.scanHasOdometry = true;
			e.scanOdometry = robot;
			e.sourceIndex = d.lineNo;
			d.accept(ts);
			++m_stats.scans;
			ev = std::move(e);
			return true;
		}
		catch (const SkipLine& s)
		{
			++m_stats.skipped;
			warn(m_path + ":" + std::to_string(d.lineNo) + ": " + s.reason + ", skipped");
		}
	}
}

}  // namespace pmslam
