// The wide basin: the correlative search and the SLAM's re-localisation, on ray-cast scans
// with known truth, against brute force and against what the local PM match alone does.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/match/CorrelativeSearch.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>
#include <pmslam/slam/PerfectMatchSlam.h>

#include <random>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using pmslam::testing::angleDiff;

namespace
{
// A room with furniture of different shapes: every pose is constrained and none looks alike.
pmslam::testing::SyntheticWorld furnishedRoom()
{
	pmslam::testing::SyntheticWorld w;
	w.addBox(-12.025, -7.025, 14.025, 9.025);
	w.addBox(1.025, 1.525, 1.625, 2.025);
	w.addBox(-2.525, -2.025, -1.525, -1.025);
	w.addBox(3.525, -1.525, 4.025, 0.525);
	w.addBox(7.025, 4.025, 7.525, 4.525);
	w.addBox(-7.025, 3.025, -6.525, 3.525);
	w.addBox(9.025, -4.025, 10.025, -3.525);
	w.addBox(-8.025, -5.025, -7.525, -4.025);
	w.segments.push_back({-12.025, 1.025, -10.025, 2.525});
	w.segments.push_back({12.525, 6.525, 14.025, 7.025});
	return w;
}

void configure(pmslam::PerfectMatchSlam& slam)
{
	slam.PM_options.odometrySmoothing = false;
	slam.initialize();
}

// First scan at the origin maps the room; the second, taken at `truth`, comes with an odometry
// reading that says the robot is at `odometry`.
TPose2D secondScanPose(const pmslam::testing::SyntheticWorld& w, const TPose2D& truth, const TPose2D& odometry,
					   pmslam::PerfectMatchSlam& slam)
{
	auto s0 = w.scan(TPose2D(0, 0, 0), 361, M_PI, 30.0, 0.005, 1);
	slam.processOdometry(TPose2D(0, 0, 0));
	slam.processScan(s0);
	auto s1 = w.scan(truth, 361, M_PI, 30.0, 0.005, 2);
	slam.processOdometry(odometry);
	return slam.processScan(s1).pose;
}
}  // namespace

TEST(CorrelativeSearch, FindsTheBruteForceOptimumOfItsOwnScore)
{
	const auto w = furnishedRoom();
	pmslam::OccupancyDistanceGridMap grid;
	grid.insertScan(pmslam::scanToPoints(w.scan(TPose2D(0, 0, 0), 361, M_PI, 30.0), {}), TPose2D(0, 0, 0));
	const TPose2D truth(0.23, -0.17, mrpt::DEG2RAD(12.0));
	const auto pts = pmslam::scanToPoints(w.scan(truth, 361, M_PI, 30.0), {}).hits;
	pmslam::CorrelativeSearch cs;
	const TPose2D centre(0, 0, 0);
	const auto found = cs.search(grid.distanceMap(), pts, centre, 0.5, mrpt::DEG2RAD(30.0));
	ASSERT_FALSE(found.empty());
	// Brute force over a finer rotation lattice and the same translations: the search's best is
	// within one lattice step of the brute-force best, and scores within 5 % of it.
	double bestScore = -1;
	TPose2D best;
	const double s2 = cs.options.fieldSigma * cs.options.fieldSigma;
	for (double a = -30; a <= 30; a += 0.25)
		for (double x = -0.5; x <= 0.5 + 1e-9; x += 0.1)
			for (double y = -0.5; y <= 0.5 + 1e-9; y += 0.1)
			{
				const CPose2D p(x, y, mrpt::DEG2RAD(a));
				double sc = 0;
				std::size_t n = 0;
				for (std::size_t i = 0; i < pts.size(); i += (pts.size() + 159) / 160, ++n)
				{
					double wx, wy;
					p.composePoint(pts[i].x, pts[i].y, wx, wy);
					const auto& dm = grid.distanceMap();
					const double d = dm.cellDistance(dm.worldToCell(wx), dm.worldToCell(wy));
					sc += s2 / (s2 + d * d);
				}
				if (sc / n > bestScore) bestScore = sc / n, best = p.asTPose();
			}
	EXPECT_NEAR(found.front().pose.x, best.x, 0.1 + 1e-6);
	EXPECT_NEAR(found.front().pose.y, best.y, 0.1 + 1e-6);
	EXPECT_NEAR(angleDiff(found.front().pose.phi, best.phi), 0.0, mrpt::DEG2RAD(1.0));
	EXPECT_GT(found.front().score, 0.95 * bestScore);
	// And the best is near the truth.
	EXPECT_NEAR(found.front().pose.x, truth.x, 0.1);
	EXPECT_NEAR(found.front().pose.y, truth.y, 0.1);
	EXPECT_NEAR(angleDiff(found.front().pose.phi, truth.phi), 0.0, mrpt::DEG2RAD(1.5));
}

TEST(WideBasin, PredictionsOffBy30DegreesAndHalfAMetreConverge)
{
	const auto w = furnishedRoom();
	const TPose2D truth(0.3, 0.1, mrpt::DEG2RAD(5.0));
	std::mt19937 rng(7);
	std::uniform_real_distribution<double> u(-1, 1);
	for (int trial = 0; trial < 12; ++trial)
	{
		// Prediction errors at the edges of ±30° / ±0.5 m (at least 20° / 0.3 m off).
		const double da = mrpt::DEG2RAD(20 + 10 * std::abs(u(rng))) * (trial % 2 ? 1 : -1);
		const double dx = (0.3 + 0.2 * std::abs(u(rng))) * (trial % 4 < 2 ? 1 : -1), dy = 0.3 * u(rng);
		const TPose2D odometry(truth.x + dx, truth.y + dy, truth.phi + da);
		pmslam::PerfectMatchSlam slam;
		configure(slam);
		const TPose2D p = secondScanPose(w, truth, odometry, slam);
		SCOPED_TRACE("trial " + std::to_string(trial));
		EXPECT_NEAR(p.x, truth.x, 0.01);
		EXPECT_NEAR(p.y, truth.y, 0.01);
		EXPECT_NEAR(angleDiff(p.phi, truth.phi), 0.0, mrpt::DEG2RAD(0.2));
	}
}

TEST(WideBasin, CleanMatchesDoNotSearch)
{
	const auto w = furnishedRoom();
	pmslam::PerfectMatchSlam slam;
	configure(slam);
	const TPose2D truth(0.05, 0.02, mrpt::DEG2RAD(1.0));
	const TPose2D p = secondScanPose(w, truth, TPose2D(0.07, 0.0, mrpt::DEG2RAD(2.0)), slam);
	EXPECT_NEAR(p.x, truth.x, 0.01);
	EXPECT_FALSE(slam.lastScanResult().wideSearch);
	EXPECT_EQ(slam.wideSearches(), 0u);
}

TEST(WideBasin, FeaturelessCorridorReportsLowConfidenceAlongIt)
{
	// A plain corridor, 2.4 m wide, closed far beyond the laser's reach: across it and in heading
	// the scan decides; along it nothing can, and the reported covariance must say so.
	pmslam::testing::SyntheticWorld w;
	w.segments.push_back({-50, -1.2, 90, -1.2});
	w.segments.push_back({-50, 1.2, 90, 1.2});
	const TPose2D truth(0.4, 0.2, mrpt::DEG2RAD(3.0)), odometry(0.5, 0.0, mrpt::DEG2RAD(9.0));
	{
		// By default (degenerateBelow) the position along the corridor is the prediction's: the scan
		// has no say there, so it neither slides nor claims to know.
		pmslam::PerfectMatchSlam held;
		configure(held);
		const TPose2D p = secondScanPose(w, truth, odometry, held);
		ASSERT_TRUE(held.lastScanResult().matched);
		EXPECT_TRUE(held.lastScanResult().degenerate);
		EXPECT_NEAR(p.x, odometry.x, 0.005);
		EXPECT_NEAR(p.y, truth.y, 0.02);
		EXPECT_NEAR(angleDiff(p.phi, truth.phi), 0.0, mrpt::DEG2RAD(0.5));
	}
	// The match alone (the handling off): what it reports along the corridor.
	pmslam::PerfectMatchSlam slam;
	slam.PM_options.degenerateBelow = 0;
	configure(slam);
	const TPose2D p = secondScanPose(w, truth, odometry, slam);
	ASSERT_TRUE(slam.lastScanResult().matched);
	EXPECT_FALSE(slam.lastScanResult().degenerate);
	EXPECT_NEAR(p.y, truth.y, 0.02);
	EXPECT_NEAR(angleDiff(p.phi, truth.phi), 0.0, mrpt::DEG2RAD(0.5));
	mrpt::math::CMatrixDouble66 cov;
	mrpt::poses::CPose3D mean;
	slam.getCurrentPoseEstimation()->getCovarianceAndMean(cov, mean);
	// The uncertainty reported along the corridor covers the error there (the match's curvature
	// alone, fixed by the dots and wall ends of the map, claimed ~6 mm for a 5 cm error), and is
	// several times the uncertainty across it.
	const double along = std::sqrt(cov(0, 0)), across = std::sqrt(cov(1, 1));
	EXPECT_LT(std::abs(p.x - truth.x), 3 * along) << "along " << along << " m, x error " << p.x - truth.x;
	EXPECT_GT(along, 4 * across) << "along " << along << " m, across " << across << " m";

	// In the furnished room every direction is fixed: no such disproportion.
	const auto room = furnishedRoom();
	pmslam::PerfectMatchSlam roomSlam;
	configure(roomSlam);
	secondScanPose(room, truth, TPose2D(0.45, 0.15, mrpt::DEG2RAD(5.0)), roomSlam);
	roomSlam.getCurrentPoseEstimation()->getCovarianceAndMean(cov, mean);
	EXPECT_LT(cov(0, 0), 10 * cov(1, 1));
	EXPECT_LT(cov(1, 1), 10 * cov(0, 0));
}
