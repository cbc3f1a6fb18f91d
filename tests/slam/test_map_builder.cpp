// CMetricMapBuilderPM on a synthetic log with known truth, and on the sample log MRPT ships.
#include <gtest/gtest.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/CMetricMapBuilderPM.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/match/PerfectMatchAligner.h>

#include <filesystem>
#include <random>
#include <tuple>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using pmslam::testing::angleDiff;

namespace
{
// An office floor: a ring corridor around a block of rooms, with door frames and pillars
// so that every pose is constrained. Walls on 0.05 m cell centres.
pmslam::testing::SyntheticWorld officeFloor()
{
	pmslam::testing::SyntheticWorld w;
	w.addBox(-1.975, -1.975, 16.025, 10.025);  // outer wall
	w.addBox(1.025, 1.025, 13.025, 7.025);	 // inner block
	for (double x : {3.025, 6.025, 9.525, 12.025}) w.addBox(x, -1.975, x + 0.3, -1.475);	 // pillars along the south wall
	for (double x : {2.525, 7.025, 11.025}) w.addBox(x, 9.525, x + 0.4, 10.025);  // cabinets on the north wall
	w.addBox(-1.975, 3.025, -1.475, 3.525);
	w.addBox(15.525, 5.025, 16.025, 5.525);
	w.segments.push_back({5.025, 7.025, 5.025, 5.525});	 // inner walls visible through gaps
	w.segments.push_back({9.025, 1.025, 9.025, 2.525});
	return w;
}

// A loop around the ring corridor, 2 cm per step, turning in the corners.
std::vector<TPose2D> loopPath()
{
	const std::vector<std::pair<double, double>> corners = {{-0.5, -0.5}, {14.5, -0.5}, {14.5, 8.5}, {-0.5, 8.5}, {-0.5, -0.5}};
	std::vector<TPose2D> path;
	for (std::size_t c = 0; c + 1 < corners.size(); ++c)
	{
		const auto [x0, y0] = corners[c];
		const auto [x1, y1] = corners[c + 1];
		const double heading = std::atan2(y1 - y0, x1 - x0), len = std::hypot(x1 - x0, y1 - y0);
		if (!path.empty())
		{
			// Turn on the spot in 3° steps.
			double phi = path.back().phi;
			while (std::abs(angleDiff(heading, phi)) > mrpt::DEG2RAD(3.0))
			{
				phi += mrpt::DEG2RAD(3.0) * (angleDiff(heading, phi) > 0 ? 1 : -1);
				path.emplace_back(x0, y0, phi);
			}
		}
		for (double s = 0; s < len; s += 0.05) path.emplace_back(x0 + s * std::cos(heading), y0 + s * std::sin(heading), heading);
	}
	return path;
}

// Odometry with a heading bias and noise, like a real differential drive.
std::vector<TPose2D> driftingOdometry(const std::vector<TPose2D>& truth, unsigned seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> n(0, 1);
	std::vector<TPose2D> odo{truth.front()};
	for (std::size_t i = 1; i < truth.size(); ++i)
	{
		CPose2D d = CPose2D(truth[i]) - CPose2D(truth[i - 1]);
		const double dist = std::hypot(d.x(), d.y());
		d = CPose2D(d.x() * (1.02 + 0.01 * n(rng)), d.y() + 0.002 * dist * n(rng),
					d.phi() * 1.03 + 0.03 * dist + 0.002 * n(rng));
		odo.push_back((CPose2D(odo.back()) + d).asTPose());
	}
	return odo;
}

double positionError(const TPose2D& a, const TPose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }
}  // namespace

TEST(CMetricMapBuilderPM, CorrectsDriftingOdometryOnSyntheticLoop)
{
	const auto world = officeFloor();
	const auto truth = loopPath();
	const auto odo = driftingOdometry(truth, 42);
	ASSERT_GT(truth.size(), 900u);

	pmslam::CMetricMapBuilderPM slam;
	slam.initialize();
	// Everything is relative to the first pose, which SLAM puts at the origin.
	const CPose2D origin(truth.front());
	std::vector<TPose2D> est, ref, odoRel;
	for (std::size_t i = 0; i < truth.size(); ++i)
	{
		const auto scan = world.scan(truth[i], 181, M_PI, 10.0, 0.01, unsigned(i + 1));
		est.push_back(slam.processScan(scan, odo[i]).pose);
		ref.push_back((CPose2D(truth[i]) - origin).asTPose());
		odoRel.push_back((CPose2D(odo[i]) - CPose2D(odo.front())).asTPose());
	}
	// Relative error over 1 m of travel (20 steps), the Kuemmerle et al. metric on this path,
	// plus the absolute error all the way round the loop.
	auto relativeError = [&](const std::vector<TPose2D>& traj) {
		double sum = 0;
		std::size_t n = 0;
		for (std::size_t i = 0; i + 20 < traj.size(); ++i, ++n)
		{
			const CPose2D d = CPose2D(traj[i + 20]) - CPose2D(traj[i]);
			const CPose2D dTrue = CPose2D(ref[i + 20]) - CPose2D(ref[i]);
			const CPose2D e = d - dTrue;
			sum += std::hypot(e.x(), e.y());
		}
		return sum / n;
	};
	double absSum = 0, absMax = 0, headMax = 0, odoSum = 0;
	for (std::size_t i = 0; i < est.size(); ++i)
	{
		absSum += positionError(est[i], ref[i]);
		absMax = std::max(absMax, positionError(est[i], ref[i]));
		headMax = std::max(headMax, std::abs(angleDiff(est[i].phi, ref[i].phi)));
		odoSum += positionError(odoRel[i], ref[i]);
	}
	const double slamRel = relativeError(est), odoRelErr = relativeError(odoRel);
	std::cout << "relative error over 1 m: SLAM " << slamRel << " m, odometry " << odoRelErr
			  << " m; absolute: SLAM mean " << absSum / est.size() << " max " << absMax << " m, odometry mean "
			  << odoSum / est.size() << " m; max heading error " << mrpt::RAD2DEG(headMax) << " deg\n";
	// The odometry drifts by metres over the loop (2 % scale, 3 % + 1.7 deg/m heading error).
	// Scan matching must keep the relative error at the millimetre level and the whole loop
	// within a few centimetres: the first matches against a one-scan map may leave an offset
	// of about one cell, which later scans inherit but do not grow.
	EXPECT_GT(odoSum / est.size(), 0.5);
	EXPECT_GT(odoRelErr, 0.02);
	EXPECT_LT(slamRel, 0.01);
	EXPECT_LT(absSum / est.size(), 0.06);
	EXPECT_LT(absMax, 0.10);
	EXPECT_LT(mrpt::RAD2DEG(headMax), 1.0);
	EXPECT_EQ(slam.scansProcessed(), truth.size());
	EXPECT_GT(slam.scansMatched(), truth.size() * 9 / 10);

	// The map matches the world: built obstacles lie on true walls, and walls seen are mapped.
	const auto grid = slam.grid().denseCopy();
	mrpt::maps::COccupancyGridMap2D truthGrid(-4, 18, -4, 12, 0.05f);
	world.rasterise(truthGrid);
	std::size_t built = 0, onWall = 0;
	const CPose2D originInv = CPose2D() - origin;  // truth frame -> SLAM frame is (origin)^-1
	for (unsigned y = 0; y < grid.getSizeY(); ++y)
		for (unsigned x = 0; x < grid.getSizeX(); ++x)
		{
			if (grid.getCell(x, y) >= 0.5f) continue;
			++built;
			// Obstacle cell in SLAM frame -> truth frame.
			double wx, wy;
			origin.composePoint(grid.idx2x(x), grid.idx2y(y), wx, wy);
			bool near = false;
			for (int dy = -1; dy <= 1 && !near; ++dy)
				for (int dx = -1; dx <= 1 && !near; ++dx)
				{
					const int tx = truthGrid.x2idx(wx) + dx, ty = truthGrid.y2idx(wy) + dy;
					near = tx >= 0 && ty >= 0 && tx < int(truthGrid.getSizeX()) && ty < int(truthGrid.getSizeY()) &&
						   truthGrid.getCell(tx, ty) < 0.5f;
				}
			onWall += near;
		}
	(void)originInv;
	ASSERT_GT(built, 1000u);
	EXPECT_GT(double(onWall) / built, 0.95) << onWall << " of " << built << " obstacle cells within a cell of a wall";
}

// Odometry read every 0.15 s, each scan stamped 0.1 s after the latest reading and carrying
// a copy of it (as aces's FLASER lines): with odometryToScanTime the scan's odometry given to the
// smoother is extrapolated to its timestamp minus scanLatency; a bursty stream (intel) is left
// alone; the prediction always follows the readings as they are.
TEST(CMetricMapBuilderPM, OdometryAtTheScanTime)
{
	const auto world = officeFloor();
	const double speed = 0.4;  // m/s along x
	auto odoAt = [&](double t) { return TPose2D(speed * t, 0, 0); };
	for (const bool enabled : {true, false})
		for (const bool bursty : {false, true})
		{
			pmslam::CMetricMapBuilderPM slam;
			slam.PM_options.odometryToScanTime = enabled;
			slam.PM_options.scanLatency = 0.08;
			slam.initialize();
			TPose2D previous;
			for (int k = 0; k < 40; ++k)
			{
				const double t = 10.0 + 0.15 * k;
				if (bursty) slam.processOdometry(odoAt(t - 0.001), t - 0.001);	// a second reading 1 ms before
				slam.processOdometry(odoAt(t), t);
				auto scan = world.scan(TPose2D(speed * (t + 0.02), 0, 0), 181, M_PI, 10.0);
				scan.timestamp = mrpt::Clock::fromDouble(t + 0.1);
				const auto& r = slam.processScan(scan, odoAt(t));
				ASSERT_TRUE(r.odometry);
				const double expected = enabled && !bursty && k >= 9 ? speed * (t + 0.1 - 0.08) : speed * t;
				EXPECT_NEAR(r.odometry->x, expected, 1e-6) << "enabled " << enabled << " bursty " << bursty << " k " << k;
				// The first extrapolated scan: its reading moved by 0.15 s of travel, not 0.17 s.
				if (k == 9)
				{
					EXPECT_NEAR(r.predicted.x - previous.x, speed * 0.15, 1e-9);
				}
				previous = r.pose;
				if (enabled && !bursty && k >= 9)
				{
					// A scan with odometry of its own (not the latest reading) keeps it.
					pmslam::CMetricMapBuilderPM other;
					other.PM_options.odometryToScanTime = true;
					other.initialize();
					other.processOdometry(odoAt(t - 0.15), t - 0.15);
					other.processOdometry(odoAt(t), t);
					EXPECT_EQ(other.processScan(scan, odoAt(t + 0.05)).odometry->x, speed * (t + 0.05));
					break;
				}
			}
		}
}

// With odometrySmoothing every scan gets exactly one smoothed pose, in order, the last ones
// when asked to finish; without it none.
TEST(CMetricMapBuilderPM, SmoothedPosesCoverEveryScan)
{
	const auto world = officeFloor();
	const auto truth = loopPath();
	for (const bool smoothing : {true, false})
	{
		pmslam::CMetricMapBuilderPM slam;
		slam.PM_options.odometrySmoothing = smoothing;
		slam.PM_options.odometrySmoothingLag = 3;
		slam.initialize();
		std::vector<std::size_t> got;
		for (std::size_t i = 0; i < 300; ++i)
		{
			const auto& r = slam.processScan(world.scan(truth[i], 181, M_PI, 10.0, 0.01, unsigned(i + 1)), truth[i]);
			for (const auto& [k, p] : slam.takeSmoothedPoses())
			{
				got.push_back(k);
				EXPECT_LT(std::hypot(p.x - (CPose2D(truth[k]) - CPose2D(truth[0])).x(),
									 p.y - (CPose2D(truth[k]) - CPose2D(truth[0])).y()),
						  0.1);
			}
			if (smoothing && i >= 3)
			{
				EXPECT_EQ(got.size(), i - 2) << "final 3 scans later";
			}
			(void)r;
		}
		for (const auto& kp : slam.takeSmoothedPoses(true)) got.push_back(kp.first);
		if (!smoothing)
		{
			EXPECT_TRUE(got.empty());
		}
		else
		{
			ASSERT_EQ(got.size(), 300u);
			for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], i);
			ASSERT_NE(slam.smoother(), nullptr);
		}
	}
}

TEST(CMetricMapBuilderPM, SimpleMapRebuildsTheSameGrid)
{
	const auto world = officeFloor();
	const auto truth = loopPath();
	pmslam::CMetricMapBuilderPM slam;
	slam.initialize();
	for (std::size_t i = 0; i < 300; ++i) slam.processScan(world.scan(truth[i], 181, M_PI, 10.0), truth[i]);
	mrpt::maps::CSimpleMap keyframes;
	slam.getCurrentlyBuiltMap(keyframes);
	EXPECT_EQ(keyframes.size(), slam.scansInserted());
	pmslam::CMetricMapBuilderPM again;
	again.initialize(keyframes);
	// Same keyframes at the same poses: the same cells, the same distance layer.
	const auto a = slam.grid().denseCopy();
	const auto b = again.grid().denseCopy();
	std::size_t differ = 0, occupied = 0;
	for (double y = -2; y < 10; y += 0.05)
		for (double x = -2; x < 16; x += 0.05)
		{
			differ += (a.getPos(x, y) < 0.5f) != (b.getPos(x, y) < 0.5f);
			occupied += a.getPos(x, y) < 0.5f;
		}
	EXPECT_GT(occupied, 100u);
	EXPECT_EQ(differ, 0u);
}

// Matching and map insertion are decoupled: every scan that moved past the (small) matching
// thresholds is matched, but the map only takes a scan after mapInsertLinDistance /
// mapInsertAngDistance of motion since the last inserted one, or when much of the scan falls
// outside what the map explains. With both at 0 every matched scan is inserted (the paper).
TEST(CMetricMapBuilderPM, InsertsIntoTheMapOnlyAfterKeyframeMotionOrOnNewGround)
{
	const auto world = officeFloor();
	const auto truth = loopPath();
	auto runWith = [&](double lin, double angDeg, double belowInliers) {
		pmslam::CMetricMapBuilderPM slam;
		slam.PM_options.mapInsertLinDistance = lin;
		slam.PM_options.mapInsertAngDistance = mrpt::DEG2RAD(angDeg);
		slam.PM_options.mapInsertBelowInliers = belowInliers;
		slam.initialize();
		std::vector<TPose2D> inserted;
		std::vector<double> inliersAtInsert;
		for (std::size_t i = 0; i < truth.size(); ++i)
		{
			const auto& r = slam.processScan(world.scan(truth[i], 181, M_PI, 10.0, 0.01, unsigned(i + 1)), truth[i]);
			if (r.inserted)
			{
				inserted.push_back(r.pose);
				inliersAtInsert.push_back(r.info.inlierFraction);
			}
		}
		return std::make_tuple(slam.scansMatched(), slam.scansInserted(), inserted, inliersAtInsert);
	};

	// The paper's behaviour: every matched scan (and the first one) is inserted.
	const auto [matchedAll, insertedAll, posesAll, inliersAll] = runWith(0, 0, 0);
	EXPECT_EQ(insertedAll, matchedAll + 1);

	// Keyframes every 0.3 m / 6 deg only (no new-ground rule): far fewer insertions, the same matching,
	// and consecutive inserted poses at least one threshold apart.
	const auto [matched, insertedCount, poses, inliers] = runWith(0.3, 6, 0);
	EXPECT_GT(matched, truth.size() * 9 / 10);
	EXPECT_LT(insertedCount, matchedAll / 4);
	for (std::size_t k = 1; k < poses.size(); ++k)
	{
		const double lin = positionError(poses[k], poses[k - 1]);
		const double ang = std::abs(angleDiff(poses[k].phi, poses[k - 1].phi));
		EXPECT_TRUE(lin >= 0.3 - 1e-9 || ang >= mrpt::DEG2RAD(6.0) - 1e-9)
			<< "insertion " << k << " only " << lin << " m / " << mrpt::RAD2DEG(ang) << " deg after the previous one";
	}

	// The new-ground rule adds insertions exactly where the scan saw unmapped space.
	// (Not more insertions in total: one on new ground re-times every keyframe after it.)
	const auto [matchedNg, insertedNg, posesNg, inliersNg] = runWith(0.3, 6, 0.95);
	EXPECT_GT(matchedNg, truth.size() * 9 / 10);
	(void)insertedNg;
	std::size_t closeAndNew = 0;
	for (std::size_t k = 1; k < posesNg.size(); ++k)
	{
		const double lin = positionError(posesNg[k], posesNg[k - 1]);
		const double ang = std::abs(angleDiff(posesNg[k].phi, posesNg[k - 1].phi));
		if (lin < 0.3 && ang < mrpt::DEG2RAD(6.0))
		{
			++closeAndNew;
			EXPECT_LT(inliersNg[k], 0.95) << "insertion " << k << " was neither far enough nor on new ground";
		}
	}
	EXPECT_GT(closeAndNew, 0u);
}

TEST(CMetricMapBuilderPM, ActionObservationInterfaceUsesOdometryIncrements)
{
	// MRPT's action/observation interface must give exactly what the direct calls give
	// when the actions carry the odometry increments.
	const auto world = officeFloor();
	const auto truth = loopPath();
	pmslam::CMetricMapBuilderPM viaActions, direct;
	viaActions.initialize();
	direct.initialize();
	for (std::size_t i = 0; i < 200; ++i)
	{
		const auto scan = world.scan(truth[i], 181, M_PI, 10.0, 0.01, unsigned(i + 7));
		mrpt::obs::CActionCollection acts;
		if (i > 0)
		{
			mrpt::obs::CActionRobotMovement2D mov;
			mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
			mov.computeFromOdometry(CPose2D(truth[i]) - CPose2D(truth[i - 1]), opts);
			acts.insert(mov);
		}
		mrpt::obs::CSensoryFrame sf;
		sf.insert(mrpt::obs::CObservation2DRangeScan::Create(scan));
		viaActions.processActionObservation(acts, sf);
		const auto& r = direct.processScan(scan, (CPose2D(truth[i]) - CPose2D(truth[0])).asTPose());
		const auto est = viaActions.getCurrentPoseEstimation()->getMeanVal();
		ASSERT_NEAR(est.x(), r.pose.x, 1e-6) << "scan " << i;
		ASSERT_NEAR(est.y(), r.pose.y, 1e-6) << "scan " << i;
		ASSERT_NEAR(angleDiff(est.yaw(), r.pose.phi), 0.0, 1e-6) << "scan " << i;
	}
	const auto est = viaActions.getCurrentPoseEstimation()->getMeanVal();
	const TPose2D t = (CPose2D(truth[199]) - CPose2D(truth[0])).asTPose();
	EXPECT_GT(t.x, 5.0);  // the robot did travel, and the estimate followed
	EXPECT_NEAR(est.x(), t.x, 0.08);
	EXPECT_NEAR(est.y(), t.y, 0.02);
	EXPECT_EQ(viaActions.scansInserted(), direct.scansInserted());
	EXPECT_EQ(viaActions.getCurrentlyBuiltMetricMap()->maps.size(), 1u);
}

TEST(CMetricMapBuilderPM, ClosesTheLoopOfMrptSampleLog)
{
	const std::string path = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
	if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not installed (comes with libmrpt-dev)";
	auto reader = pmslam::LogReader::open(path);
	pmslam::CMetricMapBuilderPM slam;
	slam.initialize();
	struct Kept
	{
		mrpt::obs::CObservation2DRangeScan::Ptr scan;
		TPose2D pose;
	};
	std::vector<Kept> scans;
	pmslam::LogEvent ev;
	while (reader->next(ev))
	{
		if (ev.kind == pmslam::LogEvent::Kind::Odometry)
			slam.processOdometry(ev.odometry);
		else
			scans.push_back({ev.scan, slam.processScan(*ev.scan).pose});
	}
	ASSERT_GT(scans.size(), 200u);
	// Independent check of the loop: a map made only from the first 25 scans (before the robot
	// left) must agree with where SLAM put the scans taken when it came back near the start.
	// If SLAM had drifted, re-aligning those late scans to the early map would move them.
	pmslam::OccupancyDistanceGridMap early;
	for (std::size_t i = 0; i < 25; ++i) early.insertScan(pmslam::scanToPoints(*scans[i].scan), scans[i].pose);
	pmslam::PerfectMatchAligner aligner;
	int checked = 0;
	for (std::size_t i = scans.size() * 3 / 4; i < scans.size(); ++i)
	{
		if (std::hypot(scans[i].pose.x, scans[i].pose.y) > 3.0) continue;  // only where the loop closes
		pmslam::PerfectMatchAligner::TReturnInfo info;
		const auto pts = pmslam::scanToPoints(*scans[i].scan);
		const TPose2D re = aligner.alignPoints(early.distanceMap(), pts.hits, scans[i].pose, &info);
		// 0.10 m / 1°: several cells would be a visible double wall; less is within what
		// a 0.05 m grid and a SICK at 0.25° (1 cm noise) can tell apart.
		EXPECT_LT(positionError(re, scans[i].pose), 0.10) << "scan " << i;
		EXPECT_LT(std::abs(mrpt::RAD2DEG(angleDiff(re.phi, scans[i].pose.phi))), 1.0) << "scan " << i;
		EXPECT_GT(info.inlierFraction, 0.5) << "scan " << i;
		++checked;
	}
	EXPECT_GT(checked, 5);
}
