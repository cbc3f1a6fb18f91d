/* pmslam — Carmen log reader (see CarmenLogReader.h). */
#include <mrpt/core/Clock.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/carmen_log_tools.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <pmslam/util/ExceptionText.h>
#include <pmslam/io/CarmenLogReader.h>
#include <pmslam/io/TextLineReader.h>

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

/** A laser line's text, validated: its ranges, its fan, and where its poses and timestamp are. */
struct LaserText
{
	std::vector<float> r;
	std::size_t rangesAt = 0, posesAt = 0, tsAt = 0;
	double start = 0, step = 0, maxRange = 0;
};

}  // namespace

struct CarmenLogReader::Impl
{
	LogReaderOptions opts;
	TextLineReader src;
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

	enum class Line
	{
		Ignored,  ///< PARAM, SYNC, comments, unknown keywords; ODOM unless opts.useOdomLines
		Odometry,
		FrontLaser,
		RearLaser,
		RobotLaser
	};
	/** The next line into `line` (counted, split into f); false at the end of the file, or at a read error
	 * that `error` then describes. */
	bool readLine(std::string& line, std::string& error);
	Line classify() const;
	/** The event of the current line; these throw SkipLine if the line is damaged. */
	LogEvent odometryEvent() const;
	LogEvent scanEvent(const std::string& line, Line kind) const;
	LaserText laserText() const;
	LaserText robotLaserText() const;
	double robotLaserStep(std::size_t n, double fov, double resolution) const;
	mrpt::obs::CObservation2DRangeScan::Ptr importedScan(const std::string& line, const LaserText& text,
														  const mrpt::math::TPose2D& robot,
														  const mrpt::poses::CPose2D& rel) const;
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
	std::size_t c = 0;
	try
	{
		TextLineReader s;
		if (!s.open(m_path)) return 0;
		std::string line;
		while (s.getline(line))
		{
			const auto b = line.find_first_not_of(" \t");
			if (b == std::string::npos) continue;
			if (line.compare(b, 7, "FLASER ") == 0 || line.compare(b, 7, "RLASER ") == 0 ||
				line.compare(b, 12, "ROBOTLASER1 ") == 0)
				++c;
		}
	}
	catch (const std::exception&)
	{
		// Damage: the scans before it are those next() delivers.
	}
	m_impl->scanCount = c;
	return c;
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
	std::string line;
	while (!d.done)
	{
		std::string readError;
		if (!d.readLine(line, readError))
		{
			d.done = true;
			if (!readError.empty())
				warn(m_path + ":" + std::to_string(d.lineNo + 1) + ": read error (" + readError + "), stopping");
			return false;
		}
		++m_stats.linesOrObjects;
		const Impl::Line kind = d.classify();
		if (kind == Impl::Line::Ignored) continue;
		try
		{
			ev = kind == Impl::Line::Odometry ? d.odometryEvent() : d.scanEvent(line, kind);
			d.accept(ev.timestamp);
			++(ev.kind == LogEvent::Kind::Scan ? m_stats.scans : m_stats.odometry);
			return true;
		}
		catch (const SkipLine& s)
		{
			++m_stats.skipped;
			warn(m_path + ":" + std::to_string(d.lineNo) + ": " + s.reason + ", skipped");
		}
	}
	return false;
}

bool CarmenLogReader::Impl::readLine(std::string& line, std::string& error)
{
	try
	{
		if (!src.getline(line)) return false;
	}
	catch (const std::exception& e)
	{
		error = exceptionSummary(e.what());
		return false;
	}
	++lineNo;
	splitFields(line, f);
	return true;
}

CarmenLogReader::Impl::Line CarmenLogReader::Impl::classify() const
{
	if (f.empty()) return Line::Ignored;
	const std::string& kw = f[0];
	if (kw == "ODOM") return opts.useOdomLines ? Line::Odometry : Line::Ignored;
	if (kw == "FLASER") return Line::FrontLaser;
	if (kw == "RLASER") return Line::RearLaser;
	if (kw == "ROBOTLASER1") return Line::RobotLaser;
	return Line::Ignored;
}

LogEvent CarmenLogReader::Impl::odometryEvent() const
{
	// MRPT's importer ignores ODOM lines: parsed here.
	// ODOM x y theta tv rv accel ipc_timestamp host logger_timestamp
	if (f.size() != 10) throw SkipLine{"ODOM line has " + std::to_string(f.size()) + " fields, expected 10"};
	LogEvent e;
	e.kind = LogEvent::Kind::Odometry;
	e.odometry = mrpt::math::TPose2D(number(1, "x"), number(2, "y"), number(3, "theta"));
	checkPose(e.odometry, "odometry pose");
	for (std::size_t i = 4; i <= 6; ++i) number(i, "velocity field");
	e.timestamp = number(7, "ipc_timestamp");
	number(9, "logger_timestamp");
	checkTimestamp(e.timestamp);
	e.sourceIndex = lineNo;
	return e;
}

LogEvent CarmenLogReader::Impl::scanEvent(const std::string& line, Line kind) const
{
	// The text is validated first, then read by MRPT's importer, whose result is checked against it and corrected.
	if (f.size() < 2) throw SkipLine{f[0] + " line without beam count"};
	const LaserText text = kind == Line::RobotLaser ? robotLaserText() : laserText();
	const std::size_t at = text.posesAt;
	const mrpt::math::TPose2D laser(number(at, "laser x"), number(at + 1, "laser y"), number(at + 2, "laser theta"));
	const mrpt::math::TPose2D robot(number(at + 3, "odometry x"), number(at + 4, "odometry y"),
									number(at + 5, "odometry theta"));
	const double ts = number(text.tsAt, "ipc_timestamp");
	number(text.tsAt + 2, "logger_timestamp");
	checkTimestamp(ts);
	checkPose(laser, "laser pose");
	checkPose(robot, "odometry pose");
	const mrpt::poses::CPose2D rel(mrpt::poses::CPose2D(laser) - mrpt::poses::CPose2D(robot));
	if (std::hypot(rel.x(), rel.y()) > kMaxSensorOffset)
		throw SkipLine{"laser pose " + fmt6(std::hypot(rel.x(), rel.y())) + " m away from the odometry pose"};

	const mrpt::obs::CObservation2DRangeScan::Ptr scan = importedScan(line, text, robot, rel);
	const auto& sp = scan->sensorPose;
	double laserYaw = rel.phi();
	if (kind == Line::RearLaser && std::abs(mrpt::math::wrapToPi(laserYaw)) < 0.5 * M_PI) laserYaw += M_PI;
	finishScan(*scan, text.r, sp.x(), sp.y(), laserYaw, text.start, text.step, text.maxRange, ts);
	if (!anyValid(*scan)) throw SkipLine{"scan has no valid beam"};

	LogEvent e;
	e.kind = LogEvent::Kind::Scan;
	e.timestamp = ts;
	e.scan = scan;
	e.scanHasOdometry = true;
	e.scanOdometry = robot;
	e.sourceIndex = lineNo;
	return e;
}

/** FLASER / RLASER n r1..rn lx ly lth ox oy oth ipc_timestamp host logger_timestamp */
LaserText CarmenLogReader::Impl::laserText() const
{
	LaserText t;
	const std::size_t n = count(1, "beam count", kMaxBeams);
	if (n < 2) throw SkipLine{"beam count " + std::to_string(n) + " (need at least 2)"};
	const std::size_t expected = n + 11;
	if (f.size() != expected)
		throw SkipLine{"beam count " + std::to_string(n) + " disagrees with the line (" + std::to_string(f.size()) +
					   " fields, expected " + std::to_string(expected) + ")"};
	ranges(2, n, t.r);
	t.step = flaserBeamStep(n);
	t.start = -0.5 * M_PI;
	t.maxRange = opts.noReturnRange;
	t.rangesAt = 2;
	t.posesAt = 2 + n;
	t.tsAt = t.posesAt + 6;
	return t;
}

/** ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode n r1..rn m e1..em
 * lx ly lth ox oy oth tv rv fwd side turn ipc_timestamp host logger_timestamp */
LaserText CarmenLogReader::Impl::robotLaserText() const
{
	if (f.size() < 10) throw SkipLine{"ROBOTLASER1 line has only " + std::to_string(f.size()) + " fields"};
	const std::size_t n = count(8, "beam count", kMaxBeams);
	if (n < 2) throw SkipLine{"beam count " + std::to_string(n) + " (need at least 2)"};
	if (f.size() < 10 + n)
		throw SkipLine{"beam count " + std::to_string(n) + " disagrees with the line (" + std::to_string(f.size()) +
					   " fields)"};
	const std::size_t m = count(9 + n, "remission count", kMaxBeams);
	const std::size_t expected = n + m + 24;
	if (f.size() != expected)
		throw SkipLine{"beam count " + std::to_string(n) + " disagrees with the line (" + std::to_string(f.size()) +
					   " fields, expected " + std::to_string(expected) + ")"};
	LaserText t;
	number(1, "laser_type");
	t.start = number(2, "start_angle");
	const double fov = number(3, "field_of_view");
	const double resolution = number(4, "angular_resolution");
	const double lineMax = number(5, "maximum_range");
	number(6, "accuracy");
	number(7, "remission_mode");
	t.step = robotLaserStep(n, fov, resolution);
	t.maxRange = opts.noReturnRange;
	if (lineMax > 0 && lineMax < t.maxRange) t.maxRange = lineMax;
	ranges(9, n, t.r);
	for (std::size_t i = 0; i < m; ++i) number(10 + n + i, "remission");
	t.rangesAt = 9;
	t.posesAt = 10 + n + m;
	for (std::size_t i = t.posesAt + 6; i < t.posesAt + 11; ++i) number(i, "velocity field");
	t.tsAt = t.posesAt + 11;
	return t;
}

/** ROBOTLASER1's beam step: its angular_resolution, or field_of_view / (n − 1) if it has none; when both are
 * given they must agree with the n beams (a fan of n − 1 steps, or a full turn of n). */
double CarmenLogReader::Impl::robotLaserStep(std::size_t n, double fov, double resolution) const
{
	if (!(resolution > 0))
	{
		if (!(fov > 0)) throw SkipLine{"no usable angular_resolution or field_of_view"};
		return fov / static_cast<double>(n - 1);
	}
	if (fov > 0)
	{
		const double tol = 0.5 * resolution + 1e-6;
		if (std::abs(fov - resolution * static_cast<double>(n - 1)) > tol &&
			std::abs(fov - resolution * static_cast<double>(n)) > tol)
			throw SkipLine{"beam count " + std::to_string(n) + " disagrees with field_of_view " + f[3] +
						   " / angular_resolution " + f[4]};
	}
	return resolution;
}

/** The line through MRPT's importer, checked against the validated text: the same ranges, sensor offset
 * (MRPT computes laser ⊖ odometry, the laser pose in the robot frame: right, kept) and odometry. */
mrpt::obs::CObservation2DRangeScan::Ptr CarmenLogReader::Impl::importedScan(const std::string& line,
																			const LaserText& text,
																			const mrpt::math::TPose2D& robot,
																			const mrpt::poses::CPose2D& rel) const
{
	const std::vector<float>& r = text.r;
	const std::size_t n = r.size();
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
						   fmt6(scan->getScanRange(i)) + " instead of " + f[text.rangesAt + i]};
	const auto& sp = scan->sensorPose;
	if (std::abs(sp.x() - rel.x()) > 1e-4 || std::abs(sp.y() - rel.y()) > 1e-4)
		throw SkipLine{"MRPT's Carmen importer computed a different sensor offset"};
	if (odo && (std::abs(odo->odometry.x() - robot.x) > 1e-4 || std::abs(odo->odometry.y() - robot.y) > 1e-4))
		throw SkipLine{"MRPT's Carmen importer read a different odometry pose"};
	return scan;
}

}  // namespace pmslam
