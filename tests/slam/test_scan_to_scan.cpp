// ScanToScan: the motion a lidar alone measures between consecutive scans, added up, must follow the robot. Along
// a corridor whose walls the distance map's cells round by centimetres, the rounding must not turn into motion.
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/sensor/ScanPoints.h>
#include <pmslam/slam/ScanToScan.h>

#include <cmath>

#include "SyntheticWorld.h"
#include "lidar_emulator/LidarEmulator.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;

namespace
{
struct Drift
{
	double lateral = 0, along = 0, yawDeg = 0;	// of the summed motions against the truth's, in its frame
};

// The emulator's lidar (270 degrees, 1081 beams, 5 mm noise, 40 Hz) driven `steps` scans from `from` by `step`
// (robot frame) each; the motions measured scan to scan, composed.
Drift drive(const TPose2D& from, const TPose2D& step, int steps)
{
	const auto world = pmslam::testing::corridorsWorld();
	pmslam::PerfectMatchMatcher matcher;
	pmslam::ScanToScan s2s(0.05, 0.5);
	CPose2D truth(from), summed;
	const auto points = [&](const CPose2D& p, int k) {
		return pmslam::scanToPoints(world.scan(p.asTPose(), 1081, 1.5 * M_PI, 30.0, 0.005, unsigned(k + 1))).hits;
	};
	s2s.keep(points(truth, 0));
	for (int k = 1; k <= steps; ++k)
	{
		truth = truth + CPose2D(step);
		const auto m = s2s.motion(matcher, points(truth, k), step);
		EXPECT_TRUE(m.has_value()) << "scan " << k;
		summed = summed + CPose2D(m.value_or(step));
	}
	const CPose2D want = truth - CPose2D(from);	// the truth's motion, from `from`
	const CPose2D err = summed - want;
	return {err.y(), err.x(), mrpt::RAD2DEG(mrpt::math::wrapToPi(err.phi()))};
}
}  // namespace

TEST(ScanToScan, MotionsAlongACorridorAddUpToTheRobotsWithoutDrift)
{
	// 2 m along the first corridor at 0.5 m/s (160 scans of 12.5 mm); before the scans were put in a frame of
	// their own, the walls' rounding to cell centres pulled each match: 0.1-2.2 m sideways, 0.55-0.91 m along.
	for (const double y : {-4.75, -4.73, -4.71})
	{
		const Drift d = drive(TPose2D(-6.0, y, 0), TPose2D(0.0125, 0, 0), 160);
		EXPECT_LT(std::abs(d.lateral), 0.04) << "y " << y;
		EXPECT_LT(std::abs(d.along), 0.05) << "y " << y;
		EXPECT_LT(std::abs(d.yawDeg), 0.5) << "y " << y;
	}
	// Turning on the spot, and a curve.
	const Drift turn = drive(TPose2D(-6.0, -4.75, 0), TPose2D(0, 0, mrpt::DEG2RAD(0.5)), 120);
	EXPECT_LT(std::hypot(turn.lateral, turn.along), 0.05);
	EXPECT_LT(std::abs(turn.yawDeg), 0.5);
	const Drift curve = drive(TPose2D(-6.0, -4.75, 0), TPose2D(0.0125, 0, mrpt::DEG2RAD(0.3)), 120);
	EXPECT_LT(std::hypot(curve.lateral, curve.along), 0.1);
	EXPECT_LT(std::abs(curve.yawDeg), 1.0);
}
