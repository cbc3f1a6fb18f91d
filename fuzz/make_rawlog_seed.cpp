// Writes the seed rawlogs of fuzz/corpus/fuzz_rawlog/ (run once, output committed):
//   make_rawlog_seed DIR
// obs_only.rawlog: CObservationOdometry + CObservation2DRangeScan pairs;
// action_obs.rawlog: CActionCollection + CSensoryFrame pairs. A few short
// scans each, so that mutations reach every part of the object reader.
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
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
	return 0;
}
