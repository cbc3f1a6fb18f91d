// A robot carried with its odometry unaware: the odometry stands still while the scans move.
// The builder must notice from the scans themselves (matchWhenScanChanged) and keep tracking.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/PerfectMatchSlam.h>

#include "SyntheticLogs.h"
#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using namespace pmslam::testing;

namespace
{
// Truth along roomPath(); odometry equal to it except frozen over scans [from, to), after which it
// goes on with the true increments from where it stood.
double endError(double matchWhenScanChanged, std::size_t from, std::size_t to)
{
	const auto world = furnishedRoom();
	const auto truth = roomPath(240);
	std::vector<TPose2D> odo{truth.front()};
	for (std::size_t k = 1; k < truth.size(); ++k)
	{
		const CPose2D d = CPose2D(truth[k]) - CPose2D(truth[k - 1]);
		odo.push_back(k >= from && k < to ? odo.back() : (CPose2D(odo.back()) + d).asTPose());
	}
	pmslam::PerfectMatchSlam slam;
	slam.PM_options.odometrySmoothing = false;
	slam.PM_options.matchWhenScanChanged = matchWhenScanChanged;
	slam.initialize();
	TPose2D last;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		auto scan = world.scan(truth[k], 361, M_PI, 30.0, 0.005, unsigned(k + 1));
		scan.timestamp = mrpt::Clock::fromDouble(1000 + 0.2 * double(k));
		slam.processOdometry(odo[k], 1000 + 0.2 * double(k));
		last = slam.processScan(scan).pose;
	}
	const auto t = relativeToFirst(truth, truth.size() - 1);
	return std::hypot(last.x - t.x, last.y - t.y);
}
}  // namespace

TEST(Carried, ScansThatMoveWhileOdometryStandsStillAreTracked)
{
	// Frozen while the robot crosses the room (about 2.6 m): tracked to the end within 2 cm.
	EXPECT_LT(endError(0.3, 20, 120), 0.02);
	// Without the check the robot is where odometry left it: far off.
	EXPECT_GT(endError(0.0, 20, 120), 0.3);
}
