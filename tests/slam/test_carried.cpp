// A robot carried with its odometry unaware: the odometry stands still while the scans move.
// The builder must notice from the scans themselves (matchWhenScanChanged) and keep tracking.
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/PerfectMatchSlam.h>

#include <algorithm>

#include "RingWorld.h"
#include "SyntheticLogs.h"
#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using namespace pmslam::testing;

namespace
{
struct EndError
{
	double position = 0, headingDeg = 0;
};

// Odometry equal to `truth` except frozen over scans [from, to), after which it goes on with the true increments
// from where it stood (`catchUp` false: a robot carried, its wheels unaware) or jumps to where it would have been
// (`catchUp`: a stalled reading catching up in one step). `turnScale`: the odometry's own error over the frozen
// scans, its turn there that many times the true one (wheels that slip in a turn; 1: none).
std::vector<TPose2D> frozenOdometry(const std::vector<TPose2D>& truth, std::size_t from, std::size_t to, bool catchUp,
									double turnScale = 1.0, double distanceScale = 1.0)
{
	std::vector<TPose2D> odo{truth.front()}, unfrozen{truth.front()};
	for (std::size_t k = 1; k < truth.size(); ++k)
	{
		const CPose2D d = CPose2D(truth[k]) - CPose2D(truth[k - 1]);
		const bool frozen = k >= from && k < to;
		const double turn = frozen ? turnScale * d.phi() : d.phi(), f = frozen ? distanceScale : 1.0;
		unfrozen.push_back((CPose2D(unfrozen.back()) + CPose2D(f * d.x(), f * d.y(), turn)).asTPose());
		if (k >= from && k < to)
			odo.push_back(odo.back());
		else
			odo.push_back(catchUp ? unfrozen.back() : (CPose2D(odo.back()) + CPose2D(d.x(), d.y(), turn)).asTPose());
	}
	return odo;
}

// The builder on scans of `world` along `truth` (181 beams over 180 degrees, a scan every 0.2 s) with odometry
// `odo`: how far its last pose is from the truth's.
EndError runOn(const pmslam::testing::SyntheticWorld& world, const std::vector<TPose2D>& truth,
			   const std::vector<TPose2D>& odo, double matchWhenScanChanged, std::size_t beams = 361)
{
	pmslam::PerfectMatchSlam slam;
	slam.PM_options.odometrySmoothing = false;
	slam.PM_options.matchWhenScanChanged = matchWhenScanChanged;
	slam.initialize();
	TPose2D last;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		auto scan = world.scan(truth[k], beams, M_PI, 30.0, 0.005, unsigned(k + 1));
		scan.timestamp = mrpt::Clock::fromDouble(1000 + 0.2 * double(k));
		slam.processOdometry(odo[k], 1000 + 0.2 * double(k));
		last = slam.processScan(scan).pose;
	}
	const auto t = relativeToFirst(truth, truth.size() - 1);
	return {std::hypot(last.x - t.x, last.y - t.y), std::abs(mrpt::math::wrapToPi(last.phi - t.phi)) * 180 / M_PI};
}

// The same in the furnished room.
EndError endError(double matchWhenScanChanged, std::size_t from, std::size_t to, bool catchUp = false,
				  const std::vector<TPose2D>& truth = roomPath(240))
{
	return runOn(furnishedRoom(), truth, frozenOdometry(truth, from, to, catchUp), matchWhenScanChanged);
}

// roomPath(240) with a spin of 90 degrees on the spot over scans [100, 110).
std::vector<TPose2D> spinningPath()
{
	auto p = roomPath(240);
	for (std::size_t k = 0; k < p.size(); ++k) p[k].phi += std::clamp((double(k) - 100) / 10, 0.0, 1.0) * M_PI / 2;
	return p;
}
}  // namespace

TEST(Carried, ScansThatMoveWhileOdometryStandsStillAreTracked)
{
	// Frozen while the robot crosses the room (about 2.6 m): tracked to the end within 2 cm.
	EXPECT_LT(endError(0.3, 20, 120).position, 0.02);
	// Without the check the robot is where odometry left it: far off.
	EXPECT_GT(endError(0.0, 20, 120).position, 0.3);
}

TEST(Carried, AReadingThatStallsDuringASpinAndCatchesUpIsNotCountedTwice)
{
	// The reading stands still over 8 scans of a 90-degree spin, then jumps by the whole turn at once. The scans
	// measured the turn meanwhile; counting the catch-up on top of it predicts 70-90 degrees off, beyond what the
	// match or its ±30-degree search can bring back.
	const EndError stalled = endError(0.3, 101, 109, true, spinningPath());
	EXPECT_LT(stalled.position, 0.03);
	EXPECT_LT(stalled.headingDeg, 1.0);
	// A robot carried through the same spin (its odometry never catches up) is followed all the same.
	const EndError carried = endError(0.3, 101, 109, false, spinningPath());
	EXPECT_LT(carried.position, 0.03);
	EXPECT_LT(carried.headingDeg, 1.0);
}

TEST(Carried, AStalledReadingWhoseOwnTurnIsOffIsNotCountedTwiceEither)
{
	// Driving round a corner of the ring's corridors, the reading stands still for 40 scans (2.4 m, the corner's
	// 90 degrees among them) and then catches up; meanwhile the wheels slipped, and the reading overstates the turn
	// by 25 % and the distance by 30 % (fr079's odometry over one such stall said 84 degrees where the scans
	// turned 71). Counted from where it stood still, the catch-up is then about 24 degrees off, too far for the
	// match alone (goodness 0.16; the prediction that counts the turn twice, 115 degrees off: 0.09). Both are
	// searched in their windows, and the scans clearly prefer the first. Searching only around the prediction
	// took a wrong pose there: 8.4 m and 90 degrees off at the end.
	const auto all = pmslam::testing::ringPath(0.35, 0.06);
	std::size_t corner = 0;
	while (corner < all.size() && std::abs(all[corner].phi) < 0.1) ++corner;
	ASSERT_LT(corner + 150, all.size());
	const std::vector<TPose2D> truth(all.begin() + std::ptrdiff_t(corner - 60), all.begin() + std::ptrdiff_t(corner + 150));
	const auto world = pmslam::testing::nearbyPart(pmslam::testing::ringWorld(), truth[60].x, truth[60].y, 40);
	const EndError e = runOn(world, truth, frozenOdometry(truth, 59, 99, true, 1.25, 1.3), 0.3, 181);
	EXPECT_LT(e.position, 0.05);
	EXPECT_LT(e.headingDeg, 1.0);
}
