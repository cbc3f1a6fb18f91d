// pm-slam-app on odd but valid input, from logs written here by ray casting in a
// synthetic world: very few beams, a 360° scanner, a laser mounted upside down
// or off the robot's centre, no odometry, a robot that never moves, odometry far
// from the origin, and a 2 km corridor. Each run must succeed, give one pose per
// scan, and (where scans can be matched) follow the true path.
#include <gtest/gtest.h>
#include <pmslam/io/Trajectory.h>

#include <iostream>
#include <tuple>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";

struct AppRun
{
	RunResult result;
	pmslam::Trajectory traj;
};

/** Maps `log` into a fresh folder of `d`; asserts success and one pose (and timing line) per scan. */
AppRun mapLog(const ScratchDir& d, const std::string& log, std::size_t expectedScans, const std::string& extra = "")
{
	AppRun a;
	const fs::path out = d.path("out-" + fs::path(log).stem().string());
	a.result = run(quote(kApp) + " --no-progress " + extra + " --out " + quote(out.string()) + " " + quote(log));
	EXPECT_EQ(a.result.exitCode, 0) << a.result.output;
	if (a.result.exitCode != 0) return a;
	EXPECT_EQ(a.result.output.find("warning:"), std::string::npos) << a.result.output;
	a.traj = pmslam::loadTrajectory((out / "trajectory.txt").string());
	EXPECT_EQ(a.traj.size(), expectedScans);
	EXPECT_EQ(countDataLines(out / "timing.txt"), expectedScans);
	for (const auto& p : a.traj)
		EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw)) << p.timestamp;
	return a;
}

/** Largest distance and heading error (deg) of the trajectory against the truth
 * relative to its first pose. */
std::pair<double, double> maxError(const pmslam::Trajectory& traj, const std::vector<mrpt::math::TPose2D>& truth)
{
	double dMax = 0, aMax = 0;
	for (std::size_t k = 0; k < std::min(traj.size(), truth.size()); ++k)
	{
		const auto t = relativeToFirst(truth, k);
		dMax = std::max(dMax, std::hypot(traj[k].x - t.x, traj[k].y - t.y));
		aMax = std::max(aMax, std::abs(angleDiff(traj[k].yaw, t.phi)) * 180.0 / M_PI);
	}
	return {dMax, aMax};
}

/** Odometry 4 % long and turning 3°/m: only matching keeps the map straight. */
std::vector<mrpt::math::TPose2D> badOdometry(const std::vector<mrpt::math::TPose2D>& truth,
											 const mrpt::poses::CPose2D& origin = mrpt::poses::CPose2D())
{
	return driftingOdometry(truth, 1.04, 3.0 * M_PI / 180.0, origin);
}

/** Odometry-only error at the end, to check that the test's drift is worth correcting. */
double odometryOnlyError(const std::vector<mrpt::math::TPose2D>& truth, const std::vector<mrpt::math::TPose2D>& odo)
{
	const auto t = relativeToFirst(truth, truth.size() - 1), o = relativeToFirst(odo, odo.size() - 1);
	return std::hypot(t.x - o.x, t.y - o.y);
}
}  // namespace

TEST(OddInput, EightBeamScansAreTrackedByOdometry)
{
	// Below MapBuilderOptions::minPoints (20) a scan is not matched: odometry alone carries the pose.
	ScratchDir d("odd-8beams");
	const auto truth = roomPath(60);
	CarmenLogSpec spec;
	spec.beams = 8;
	const auto log = d.write("eight.clf", carmenLog(furnishedRoom(), truth, truth, spec));
	const auto a = mapLog(d, log, truth.size());
	const auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 1e-4);
	EXPECT_LT(ang, 1e-3);
	EXPECT_NE(a.result.output.find("matched 0,"), std::string::npos) << a.result.output;
}

TEST(OddInput, FullTurnRobotLaser1)
{
	ScratchDir d("odd-360-carmen");
	const auto truth = roomPath(120);
	const auto odo = badOdometry(truth);
	ASSERT_GT(odometryOnlyError(truth, odo), 0.2);
	CarmenLogSpec spec;
	spec.robotLaser = true;
	spec.beams = 360;
	spec.startAngle = -M_PI;
	spec.fov = 2 * M_PI;
	const auto log = d.write("full-turn.clf", carmenLog(furnishedRoom(), truth, odo, spec));
	const auto a = mapLog(d, log, truth.size());
	const auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
}

TEST(OddInput, FullTurnRawlogAperture2Pi)
{
	ScratchDir d("odd-360-rawlog");
	const auto truth = roomPath(120);
	const auto odo = badOdometry(truth);
	RawlogSpec spec;
	spec.beams = 361;
	spec.aperture = 2 * M_PI;
	writeRawlog(d.path("full-turn.rawlog"), furnishedRoom(), truth, odo, spec);
	const auto a = mapLog(d, d.path("full-turn.rawlog"), truth.size());
	const auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
}

TEST(OddInput, LaserMountedUpsideDown)
{
	// roll = π mirrors the scan plane: beams counted right to left in the sensor run left to
	// right on the robot. scanToPoints must use the full 3D sensor pose.
	ScratchDir d("odd-upside-down");
	const auto truth = roomPath(120);
	const auto odo = badOdometry(truth);
	RawlogSpec spec;
	spec.sensorPose = mrpt::poses::CPose3D(0.15, -0.05, 0.4, 0.1, 0.0, M_PI);
	writeRawlog(d.path("upside-down.rawlog"), furnishedRoom(), truth, odo, spec);
	const auto a = mapLog(d, d.path("upside-down.rawlog"), truth.size());
	const auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
}

TEST(OddInput, LaserOffTheRobotCentre)
{
	ScratchDir d("odd-offset");
	const auto truth = roomPath(120);
	const auto odo = badOdometry(truth);
	// Carmen: the offset comes from the laser and odometry pose triples of each line.
	CarmenLogSpec spec;
	spec.laserOnRobot = mrpt::poses::CPose2D(0.35, 0.12, 0.25);
	const auto log = d.write("offset.clf", carmenLog(furnishedRoom(), truth, odo, spec));
	auto a = mapLog(d, log, truth.size());
	auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
	// Rawlog: the offset is the scan's sensorPose.
	RawlogSpec rs;
	rs.sensorPose = mrpt::poses::CPose3D(-0.3, 0.2, 0.2, -0.4, 0.0, 0.0);
	writeRawlog(d.path("offset.rawlog"), furnishedRoom(), truth, odo, rs);
	a = mapLog(d, d.path("offset.rawlog"), truth.size());
	std::tie(dist, ang) = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
}

TEST(OddInput, NoOdometryAtAll)
{
	// Observation-only rawlog with scans only: each scan is predicted at the previous pose.
	ScratchDir d("odd-no-odometry");
	const auto truth = roomPath(150);
	RawlogSpec spec;
	spec.odometry = false;
	writeRawlog(d.path("scans-only.rawlog"), furnishedRoom(), truth, truth, spec);
	const auto a = mapLog(d, d.path("scans-only.rawlog"), truth.size());
	EXPECT_NE(a.result.output.find("odometry readings 0,"), std::string::npos) << a.result.output;
	// Without odometry the prediction never moves, so the builder matches every scan.
	const auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
}

TEST(OddInput, RobotThatNeverMoves)
{
	ScratchDir d("odd-still");
	const std::vector<mrpt::math::TPose2D> truth(200, mrpt::math::TPose2D(0.5, -0.5, 0.3));
	CarmenLogSpec spec;
	spec.odomLines = true;
	const auto log = d.write("still.clf", carmenLog(furnishedRoom(), truth, truth, spec));
	const auto a = mapLog(d, log, truth.size());
	for (const auto& p : a.traj)
	{
		ASSERT_EQ(p.x, 0.0);
		ASSERT_EQ(p.y, 0.0);
		ASSERT_EQ(p.yaw, 0.0);
	}
	EXPECT_NE(a.result.output.find("inserted 1,"), std::string::npos) << a.result.output;
}

TEST(OddInput, OdometryFarFromTheOrigin)
{
	// Odometry starting at x = 3000 m (and y = −2000 m, heading 2 rad): SLAM poses are relative
	// to the first scan, so the trajectory must be the same as from the origin.
	ScratchDir d("odd-far");
	const auto truth = roomPath(120);
	const mrpt::poses::CPose2D far(3000.0, -2000.0, 2.0);
	CarmenLogSpec spec;
	spec.odomLines = true;
	const auto log = d.write("far.clf", carmenLog(furnishedRoom(), truth, badOdometry(truth, far), spec));
	const auto a = mapLog(d, log, truth.size());
	EXPECT_EQ(a.traj.front().x, 0.0);
	const auto [dist, ang] = maxError(a.traj, truth);
	EXPECT_LT(dist, 0.05);
	EXPECT_LT(ang, 1.0);
	// The same through an MRPT rawlog (double-precision odometry observations).
	writeRawlog(d.path("far.rawlog"), furnishedRoom(), truth, badOdometry(truth, far), RawlogSpec{});
	const auto b = mapLog(d, d.path("far.rawlog"), truth.size());
	const auto [dist2, ang2] = maxError(b.traj, truth);
	EXPECT_LT(dist2, 0.05);
	EXPECT_LT(ang2, 1.0);
}

namespace
{
/** A straight corridor 3 m wide along +x with door recesses and pillars every few metres
 * (so that the position along it is observable); only the part within `range` of `x`. */
SyntheticWorld corridorAround(double x, double range)
{
	SyntheticWorld w;
	w.segments.push_back({x - range, -1.5, x + range, -1.5});
	w.segments.push_back({x - range, 1.5, x + range, 1.5});
	w.segments.push_back({-1.0, -1.5, -1.0, 1.5});	// the start wall
	const long first = static_cast<long>(std::floor((x - range) / 4.0)), last = static_cast<long>((x + range) / 4.0);
	for (long i = std::max(0L, first); i <= last; ++i)
	{
		const double c = 4.0 * double(i) + 1.0 + 0.7 * std::sin(double(i));	 // irregular spacing
		const double side = (i % 2) ? 1.5 : -1.5, depth = (i % 2) ? -0.3 : 0.3;  // a cabinet against the wall
		w.segments.push_back({c, side, c, side + depth});
		w.segments.push_back({c, side + depth, c + 0.9, side + depth});
		w.segments.push_back({c + 0.9, side + depth, c + 0.9, side});
		if (i % 3 == 0) w.addBox(c + 2.0, 0.6, c + 2.3, 0.9);  // a pillar off the robot's path
	}
	return w;
}
}  // namespace

TEST(OddInput, TwoKilometreCorridor)
{
	// 2 km straight, one scan every 0.5 m, odometry drifting. The occupancy grid is dense
	// (COccupancyGridMap2D, 1 byte per 0.05 m cell plus the distance map's blocks), so its
	// bounding box is what costs memory: 2 km × a few metres stays far below a gigabyte.
#ifdef PMSLAM_SANITIZE
	const double length = 300.0;  // AddressSanitizer: a shorter corridor, same code paths
#else
	const double length = 2000.0;
#endif
	ScratchDir d("odd-corridor");
	std::vector<mrpt::math::TPose2D> truth;
	for (double x = 0.0; x <= length; x += 0.5) truth.push_back({x, 0.3 * std::sin(x / 40.0), 0.05 * std::sin(x / 40.0)});
	const auto odo = driftingOdometry(truth, 1.01, 0.2 * M_PI / 180.0);
	std::string text = "# 2 km corridor\n";
	CarmenLogSpec spec;
	spec.beams = 181;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		spec.t0 = 1000.0 + 0.25 * double(k);
		const std::string one = carmenLog(corridorAround(truth[k].x, 35.0), {truth[k]}, {odo[k]}, spec);
		text += one.substr(one.find("FLASER"));
	}
	const auto log = d.write("corridor.clf", text);
	const auto a = mapLog(d, log, truth.size());
	ASSERT_EQ(a.traj.size(), truth.size());
	const auto [dist, ang] = maxError(a.traj, truth);
	std::cout << "corridor " << length << " m: max error " << dist << " m, " << ang << " deg\n"
			  << a.result.output;
	// No loop closure: a scan-to-map matcher drifts slowly along a featureless-looking
	// corridor. Bound it well below what the odometry alone does (several % of the length).
	EXPECT_LT(dist, 0.01 * length);
	EXPECT_GT(odometryOnlyError(truth, odo), 5.0 * dist);
	EXPECT_LT(ang, 2.0);
	// Peak memory from the summary ("peak memory 123.4 MB").
	const auto p = a.result.output.find("peak memory ");
	ASSERT_NE(p, std::string::npos) << a.result.output;
	const double mb = std::stod(a.result.output.substr(p + 12));
	EXPECT_LT(mb, 1500.0) << "the dense grid of a 2 km corridor";
}
