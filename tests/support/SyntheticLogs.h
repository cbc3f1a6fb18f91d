// Test support: robot logs written from a SyntheticWorld — Carmen text lines
// (FLASER, ROBOTLASER1, ODOM) and MRPT rawlogs (observation-only) — and small
// helpers to run pm-slam-app on them and read its outputs.
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "SyntheticWorld.h"

namespace pmslam::testing
{
namespace fs = std::filesystem;

/** A fresh folder under the system temp dir, removed at the end of the test. */
struct ScratchDir
{
	fs::path dir;
	explicit ScratchDir(const std::string& name)
	{
		static int counter = 0;
		dir = fs::temp_directory_path() /
			  ("pmslam-" + name + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
		fs::remove_all(dir);
		fs::create_directories(dir);
	}
	~ScratchDir()
	{
		std::error_code ec;
		fs::remove_all(dir, ec);
	}
	std::string path(const std::string& name) const { return (dir / name).string(); }
	std::string write(const std::string& name, const std::string& content) const
	{
		std::ofstream(path(name), std::ios::binary) << content;
		return path(name);
	}
};

inline std::string fmt(double v, int decimals = 6)
{
	char b[64];
	std::snprintf(b, sizeof(b), "%.*f", decimals, v);
	return b;
}

/** Lines of a text file that are neither empty nor '#' comments. */
inline std::size_t countDataLines(const fs::path& p)
{
	std::ifstream in(p);
	std::string line;
	std::size_t n = 0;
	while (std::getline(in, line))
		if (!line.empty() && line[0] != '#') ++n;
	return n;
}

inline std::string readText(const fs::path& p)
{
	std::ifstream in(p, std::ios::binary);
	return std::string(std::istreambuf_iterator<char>(in), {});
}

/** Ranges of `n` beams cast from `laser` (world pose of the laser) at laser-frame angles
 * start + i·step; misses are written as `noReturn`. */
inline std::vector<double> castFan(const SyntheticWorld& w, const mrpt::poses::CPose2D& laser, std::size_t n,
								   double start, double step, double maxRange, double noReturn)
{
	std::vector<double> r(n);
	for (std::size_t i = 0; i < n; ++i)
	{
		const double d = w.castRay(laser.x(), laser.y(), laser.phi() + start + static_cast<double>(i) * step);
		r[i] = std::isfinite(d) && d < maxRange ? d : noReturn;
	}
	return r;
}

/** One Carmen log written from a world: robot poses (truth), odometry poses (what the
 * log says), the laser's mounting pose on the robot. */
struct CarmenLogSpec
{
	std::size_t beams = 181;
	bool robotLaser = false;  ///< ROBOTLASER1 instead of FLASER
	double startAngle = -M_PI / 2, fov = M_PI;	///< ROBOTLASER1 only (FLASER: always 180° from −90°)
	mrpt::poses::CPose2D laserOnRobot{0, 0, 0};
	bool odomLines = false;	 ///< also write an ODOM line before each scan
	double maxRange = 30.0;
	double t0 = 1000.0, dt = 0.1;
};

inline std::string carmenLog(const SyntheticWorld& w, const std::vector<mrpt::math::TPose2D>& truth,
							 const std::vector<mrpt::math::TPose2D>& odometry, const CarmenLogSpec& spec)
{
	std::ostringstream out;
	out << "# synthetic Carmen log written by the pmslam tests\nPARAM robot_front_laser_max " << spec.maxRange
		<< " nohost 0\n";
	const double flaserStep = spec.beams % 2 ? M_PI / double(spec.beams - 1) : M_PI / double(spec.beams);
	// A full turn has no repeated end beam; a partial fan has both ends.
	const double fanStep = spec.fov > 2 * M_PI - 1e-9 ? spec.fov / double(spec.beams) : spec.fov / double(spec.beams - 1);
	const double step = spec.robotLaser ? fanStep : flaserStep;
	const double start = spec.robotLaser ? spec.startAngle : -M_PI / 2;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		const std::string ts = fmt(spec.t0 + spec.dt * double(k));
		const mrpt::poses::CPose2D odo(odometry[k]);
		const mrpt::poses::CPose2D laserOdo = odo + spec.laserOnRobot;
		const auto r = castFan(w, mrpt::poses::CPose2D(truth[k]) + spec.laserOnRobot, spec.beams, start, step,
							   spec.maxRange, 81.9);
		if (spec.odomLines)
			out << "ODOM " << fmt(odo.x()) << " " << fmt(odo.y()) << " " << fmt(odo.phi()) << " 0 0 0 " << ts
				<< " nohost " << ts << "\n";
		if (spec.robotLaser)
			out << "ROBOTLASER1 0 " << fmt(start) << " " << fmt(spec.fov, 9) << " " << fmt(step, 9) << " "
				<< fmt(spec.maxRange, 2) << " 0.01 0 " << spec.beams;
		else
			out << "FLASER " << spec.beams;
		for (double v : r) out << " " << fmt(v, 3);
		if (spec.robotLaser) out << " 0";  // no remissions
		out << " " << fmt(laserOdo.x()) << " " << fmt(laserOdo.y()) << " " << fmt(laserOdo.phi()) << " "
			<< fmt(odo.x()) << " " << fmt(odo.y()) << " " << fmt(odo.phi());
		if (spec.robotLaser) out << " 0 0 0 0 0";  // tv rv forward_safety side_safety turn_axis
		out << " " << ts << " nohost " << ts << "\n";
	}
	return out.str();
}

/** An observation-only rawlog: per pose an optional CObservationOdometry, then a scan
 * ray-cast by SyntheticWorld::scan (MRPT's fan convention, any aperture and sensorPose). */
struct RawlogSpec
{
	std::size_t beams = 181;
	double aperture = M_PI;
	mrpt::poses::CPose3D sensorPose;
	bool odometry = true;
	double maxRange = 30.0;
	double t0 = 1000.0, dt = 0.1;
};

inline void writeRawlog(const std::string& path, const SyntheticWorld& w, const std::vector<mrpt::math::TPose2D>& truth,
						const std::vector<mrpt::math::TPose2D>& odometry, const RawlogSpec& spec)
{
	mrpt::io::CFileOutputStream f(path);
	auto a = mrpt::serialization::archiveFrom(f);
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		const double t = spec.t0 + spec.dt * double(k);
		if (spec.odometry)
		{
			mrpt::obs::CObservationOdometry o;
			o.sensorLabel = "ODOMETRY";
			o.odometry = mrpt::poses::CPose2D(odometry[k]);
			o.timestamp = mrpt::Clock::fromDouble(t);
			a << o;
		}
		auto s = w.scan(truth[k], spec.beams, spec.aperture, spec.maxRange, 0.0, 1, spec.sensorPose);
		s.sensorLabel = "LASER";
		s.timestamp = mrpt::Clock::fromDouble(t + 0.01);
		a << s;
	}
}

/** A path through furnishedRoom(): forward along y = −0.5, a turn, and back, `n` poses. */
inline std::vector<mrpt::math::TPose2D> roomPath(std::size_t n = 120)
{
	std::vector<mrpt::math::TPose2D> p;
	for (std::size_t k = 0; k < n; ++k)
	{
		const double s = double(k) / double(n - 1);	 // 0..1
		const double x = -1.5 + 3.5 * std::sin(M_PI * s);  // out to x = 2 and back
		const double y = -0.5 + 0.4 * s;
		const double phi = 0.3 * std::sin(2 * M_PI * s);
		p.push_back({x, y, phi});
	}
	return p;
}

/** Odometry that drifts: translation scaled by `scale`, `yawPerMetre` rad of extra turn per
 * metre, and everything expressed from a start pose `origin` (e.g. far from zero). */
inline std::vector<mrpt::math::TPose2D> driftingOdometry(const std::vector<mrpt::math::TPose2D>& truth, double scale,
														 double yawPerMetre,
														 const mrpt::poses::CPose2D& origin = mrpt::poses::CPose2D())
{
	std::vector<mrpt::math::TPose2D> out;
	mrpt::poses::CPose2D odo = origin;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		if (k > 0)
		{
			const mrpt::poses::CPose2D d = mrpt::poses::CPose2D(truth[k]) - mrpt::poses::CPose2D(truth[k - 1]);
			const double len = std::hypot(d.x(), d.y());
			odo = odo + mrpt::poses::CPose2D(scale * d.x(), scale * d.y(), d.phi() + yawPerMetre * len);
		}
		out.push_back(odo.asTPose());
	}
	return out;
}

/** Truth expressed relative to its first pose (what the SLAM trajectory estimates). */
inline mrpt::math::TPose2D relativeToFirst(const std::vector<mrpt::math::TPose2D>& truth, std::size_t k)
{
	return (mrpt::poses::CPose2D(truth[k]) - mrpt::poses::CPose2D(truth[0])).asTPose();
}

}  // namespace pmslam::testing
