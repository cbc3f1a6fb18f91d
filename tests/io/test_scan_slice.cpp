// 3D lidars and RGB-D cameras through a 2D slice: synthetic 3D observations of a ray-cast room whose
// horizontal slice is known (the room's 2D ray cast), MRPT's own 3D range-scan conversion, and a
// rawlog of point clouds mapped end to end.
#include <gtest/gtest.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/sensor/ScanSlice.h>
#include <pmslam/slam/PerfectMatchSlam.h>

#include <cmath>
#include <limits>

#include "SyntheticLogs.h"
#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using namespace pmslam::testing;

namespace
{
constexpr double kSensorHeight = 0.8, kWallHeight = 2.5;

// A 16-ring lidar (±15°) at kSensorHeight on the robot at `pose` in `world` (walls kWallHeight high,
// a floor at 0): each ray ends on a wall, the floor or the ceiling. Points in the sensor frame.
mrpt::obs::CObservationPointCloud lidarCloud(const SyntheticWorld& world, const TPose2D& pose, double t)
{
	mrpt::obs::CObservationPointCloud o;
	o.sensorLabel = "LIDAR3D";
	o.sensorPose = CPose3D(0, 0, kSensorHeight, 0, 0, 0);
	o.timestamp = mrpt::Clock::fromDouble(t);
	auto pts = mrpt::maps::CSimplePointsMap::Create();
	for (int ring = 0; ring < 16; ++ring)
	{
		const double e = mrpt::DEG2RAD(-15.0 + 2.0 * ring);
		for (int k = 0; k < 720; ++k)
		{
			const double a = mrpt::DEG2RAD(0.5 * k);  // robot frame
			const double d = world.castRay(pose.x, pose.y, pose.phi + a);
			if (!std::isfinite(d)) continue;
			double h = d, z = kSensorHeight + d * std::tan(e);
			if (z < 0) h = kSensorHeight / std::tan(-e), z = 0;  // the floor first
			if (z > kWallHeight) h = (kWallHeight - kSensorHeight) / std::tan(e), z = kWallHeight;  // the ceiling
			pts->insertPoint(float(h * std::cos(a)), float(h * std::sin(a)), float(z - kSensorHeight));
		}
	}
	o.pointcloud = pts;
	return o;
}

// The share of the slice's valid beams whose range is within 3 % of the room's 2D ray cast (the
// nearest of rays across the beam's width: a beam takes the nearest point within half a beam of its
// angle; at a corner the lidar's own azimuths may all pass it, so a few beams may differ).
double sliceAgreement(const mrpt::obs::CObservation2DRangeScan& s, const SyntheticWorld& world, const TPose2D& pose,
					  std::size_t& valid)
{
	std::size_t good = 0;
	valid = 0;
	for (std::size_t i = 0; i < s.getScanSize(); ++i)
	{
		if (!s.getScanRangeValidity(i)) continue;
		++valid;
		const double a = s.getScanAngle(i), half = 0.5 * s.aperture / double(s.getScanSize() - 1);
		double d = std::numeric_limits<double>::infinity();
		for (int k = -4; k <= 4; ++k) d = std::min(d, world.castRay(pose.x, pose.y, pose.phi + a + half * k / 4.0));
		good += std::abs(s.getScanRange(i) - d) <= 0.03 * std::max(1.0, d);
	}
	return valid ? double(good) / double(valid) : 0.0;
}
}  // namespace

TEST(ScanSlice, PointCloudSliceIsTheRoomsRayCast)
{
	const SyntheticWorld world = furnishedRoom();
	const TPose2D pose{-1.0, -0.5, 0.3};
	const auto cloud = lidarCloud(world, pose, 10.0);
	pmslam::ScanSliceOptions o;
	const auto s = pmslam::sliceObservation(cloud, o);
	ASSERT_TRUE(s);
	EXPECT_EQ(s->getScanSize(), 720u);
	EXPECT_NEAR(s->aperture, 2 * M_PI, 1e-6);
	EXPECT_EQ(s->sensorLabel, "LIDAR3D_slice");
	EXPECT_EQ(s->timestamp, cloud.timestamp);
	std::size_t valid = 0;
	EXPECT_GT(sliceAgreement(*s, world, pose, valid), 0.98);
	EXPECT_GT(valid, 680u);	 // a closed room: nearly every beam sees a wall
	// The floor and the ceiling are out of the band: with a band that takes the floor, the nearest
	// points are floor returns, far short of the walls.
	o.minHeight = -0.1;
	const auto withFloor = pmslam::sliceObservation(cloud, o);
	ASSERT_TRUE(withFloor);
	EXPECT_LT(sliceAgreement(*withFloor, world, pose, valid), 0.5);
}

TEST(ScanSlice, RangeImageThroughMrptsConversion)
{
	// A depth camera 0.5 m up, looking along the robot's x at a wall 3 m ahead.
	mrpt::obs::CObservation3DRangeScan o;
	o.sensorLabel = "RGBD";
	o.hasRangeImage = true;
	o.range_is_depth = true;
	o.rangeUnits = 0.001f;
	const int W = 160, H = 120;
	o.cameraParams.ncols = W;
	o.cameraParams.nrows = H;
	o.cameraParams.fx(200);
	o.cameraParams.fy(200);
	o.cameraParams.cx(80);
	o.cameraParams.cy(60);
	o.rangeImage.resize(H, W);
	o.rangeImage.fill(3000);  // 3 m of depth everywhere: a wall
	o.sensorPose = CPose3D(0, 0, 0.5, 0, 0, 0);
	o.timestamp = mrpt::Clock::fromDouble(5.0);
	const auto s = pmslam::sliceObservation(o, pmslam::ScanSliceOptions());
	ASSERT_TRUE(s);
	std::size_t valid = 0;
	double worst = 0;
	for (std::size_t i = 0; i < s->getScanSize(); ++i)
	{
		if (!s->getScanRangeValidity(i)) continue;
		++valid;
		const mrpt::poses::CPose3D sp = s->sensorPose;
		const double a = s->getScanAngle(i) + sp.yaw();
		const double x = sp.x() + s->getScanRange(i) * std::cos(a);
		worst = std::max(worst, std::abs(x - 3.0));  // every return on the wall x = 3
	}
	EXPECT_GT(valid, 20u);
	EXPECT_LT(worst, 0.05);
}

TEST(ScanSlice, RotatingScanSaysWhyNot)
{
	mrpt::obs::CObservationRotatingScan o;
	std::string why;
	EXPECT_TRUE(pmslam::isSliceable(o));
	EXPECT_FALSE(pmslam::sliceObservation(o, pmslam::ScanSliceOptions(), &why));
	EXPECT_NE(why.find("elevation"), std::string::npos) << why;
}

// A rawlog of odometry and 3D point clouds (no 2D scan at all) is mapped: the trajectory follows the truth.
TEST(ScanSlice, RawlogOfPointCloudsIsMapped)
{
	const SyntheticWorld world = furnishedRoom();
	const auto truth = roomPath(120);
	ScratchDir dir("slice");
	const std::string path = dir.path("cloud.rawlog");
	{
		mrpt::io::CFileOutputStream f(path);
		auto a = mrpt::serialization::archiveFrom(f);
		for (std::size_t k = 0; k < truth.size(); ++k)
		{
			const double t = 1000 + 0.1 * double(k);
			mrpt::obs::CObservationOdometry od;
			od.odometry = CPose2D(truth[k]);  // exact odometry: the test is the slice, not the drift
			od.timestamp = mrpt::Clock::fromDouble(t);
			a << od;
			a << lidarCloud(world, truth[k], t + 0.01);
		}
	}
	auto reader = pmslam::LogReader::open(path, pmslam::LogReaderOptions());
	pmslam::PerfectMatchSlam slam;
	slam.initialize();
	std::vector<TPose2D> est;
	pmslam::LogEvent ev;
	while (reader->next(ev))
	{
		if (ev.kind == pmslam::LogEvent::Kind::Odometry)
			slam.processOdometry(ev.odometry, ev.timestamp);
		else
			est.push_back(slam.processScan(*ev.scan).pose);
	}
	ASSERT_EQ(est.size(), truth.size());
	double worst = 0;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		const TPose2D t = relativeToFirst(truth, k);
		worst = std::max(worst, std::hypot(est[k].x - t.x, est[k].y - t.y));
	}
	EXPECT_LT(worst, 0.05);
	EXPECT_GT(slam.scansMatched(), truth.size() / 2);
}
