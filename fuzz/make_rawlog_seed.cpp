// Writes the seed rawlogs of fuzz/corpus/fuzz_rawlog/ (run once, output committed):
//   make_rawlog_seed DIR
// obs_only.rawlog: CObservationOdometry + CObservation2DRangeScan pairs;
// action_obs.rawlog: CActionCollection + CSensoryFrame pairs;
// obs_3d.rawlog: a CObservationPointCloud and a small CObservation3DRangeScan (the 2D slice).
// A few short scans each, so that mutations reach every part of the object reader.
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <iostream>
#include <string>

namespace
{
mrpt::obs::CObservation2DRangeScan::Ptr makeScan(double t, std::size_t beams, double aperture, const char* label)
{
	auto s = mrpt::obs::CObservation2DRangeScan::Create();
	s->sensorLabel = label;
	s->aperture = static_cast<float>(aperture);
	s->rightToLeft = true;
	s->maxRange = 30.0f;
	s->sensorPose = mrpt::poses::CPose3D(0.1, 0.0, 0.3, 0.0, 0.0, 0.0);
	s->resizeScan(beams);
	for (std::size_t i = 0; i < beams; ++i)
	{
		s->setScanRange(i, static_cast<float>(1.0 + 0.25 * static_cast<double>(i)));
		s->setScanRangeValidity(i, i % 3 != 2);
	}
	s->timestamp = mrpt::Clock::fromDouble(t);
	return s;
}
}  // namespace

int main(int argc, char** argv)
{
	if (argc != 2)
	{
		std::cerr << "usage: make_rawlog_seed DIR\n";
		return 2;
	}
	const std::string dir = argv[1];
	{
		mrpt::io::CFileOutputStream f(dir + "/obs_only.rawlog");
		auto a = mrpt::serialization::archiveFrom(f);
		for (int k = 0; k < 2; ++k)
		{
			auto o = mrpt::obs::CObservationOdometry::Create();
			o->odometry = mrpt::poses::CPose2D(0.1 * k, 0.0, 0.05 * k);
			o->timestamp = mrpt::Clock::fromDouble(100.0 + k);
			a << *o;
			a << *makeScan(100.5 + k, 6, M_PI, "LASER");
		}
	}
	{
		mrpt::io::CFileOutputStream f(dir + "/action_obs.rawlog");
		auto a = mrpt::serialization::archiveFrom(f);
		for (int k = 0; k < 2; ++k)
		{
			mrpt::obs::CActionCollection acts;
			mrpt::obs::CActionRobotMovement2D mv;
			mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
			mv.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0.0, 0.02), opts);
			mv.timestamp = mrpt::Clock::fromDouble(200.0 + k);
			acts.insert(mv);
			a << acts;
			mrpt::obs::CSensoryFrame sf;
			sf.insert(makeScan(200.5 + k, 5, 2 * M_PI, k == 0 ? "FLASER" : "LASER"));
			a << sf;
		}
	}
	{
		mrpt::io::CFileOutputStream f(dir + "/obs_3d.rawlog");
		auto a = mrpt::serialization::archiveFrom(f);
		mrpt::obs::CObservationPointCloud pc;
		pc.sensorLabel = "LIDAR3D";
		pc.sensorPose = mrpt::poses::CPose3D(0, 0, 0.8, 0, 0, 0);
		pc.timestamp = mrpt::Clock::fromDouble(300.0);
		auto pts = mrpt::maps::CSimplePointsMap::Create();
		for (int k = 0; k < 8; ++k) pts->insertPoint(float(2 * std::cos(k)), float(2 * std::sin(k)), float(0.1 * k - 0.4));
		pc.pointcloud = pts;
		a << pc;
		mrpt::obs::CObservation3DRangeScan r;
		r.sensorLabel = "RGBD";
		r.hasRangeImage = true;
		r.range_is_depth = true;
		r.rangeUnits = 0.001f;
		r.cameraParams.ncols = 8;
		r.cameraParams.nrows = 6;
		r.cameraParams.fx(10);
		r.cameraParams.fy(10);
		r.cameraParams.cx(4);
		r.cameraParams.cy(3);
		r.rangeImage.resize(6, 8);
		r.rangeImage.fill(2000);
		r.sensorPose = mrpt::poses::CPose3D(0, 0, 0.5, 0, 0, 0);
		r.timestamp = mrpt::Clock::fromDouble(301.0);
		a << r;
	}
	return 0;
}
