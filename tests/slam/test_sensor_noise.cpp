// A lidar noisier than a SICK: its range noise is read from its own scans (decisions.md D52), and the
// likelihood field widens to it, so that the true pose scores as a match and the map grows.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/sensor/RangeNoise.h>
#include <pmslam/slam/PerfectMatchSlam.h>
#include <pmslam/slam/SensorNoise.h>

#include "SyntheticWorld.h"
#include "lidar_emulator/LidarEmulator.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using namespace pmslam::testing;

namespace
{
// The scan's returns in the sensor frame, in scan order.
std::vector<mrpt::math::TPoint2Df> returns(const mrpt::obs::CObservation2DRangeScan& scan)
{
	std::vector<mrpt::math::TPoint2Df> out;
	for (std::size_t i = 0; i < scan.getScanSize(); ++i)
		if (scan.getScanRangeValidity(i))
		{
			const double a = scan.getScanAngle(i), r = scan.getScanRange(i);
			out.emplace_back(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)));
		}
	return out;
}

// The noise RangeNoise reads from 30 scans along the corridors' loop, taken with Gaussian range noise `noise`.
double readNoise(double noise, std::size_t beams)
{
	const auto world = corridorsWorld();
	const auto path = LoopPath::forWorld("corridors", 0.5);
	pmslam::RangeNoise reader;
	for (int k = 0; k < 30; ++k)
		reader.add(returns(world.scan(path.at(1.0 * k), beams, 1.5 * M_PI, 30.0, noise, unsigned(k + 1))));
	return reader.noise().value_or(-1);
}

struct NoisyRun
{
	std::size_t scans = 0, rejected = 0, wideSearches = 0;
	double worst = 0;  // m, worst position error relative to the first pose
	double sigma = 0;  // the σ the lidar was matched with at the end
};

// Once round `world`'s loop at 0.5 m/s with a 270° lidar at 20 Hz and odometry that drifts 2 % sideways.
NoisyRun drive(const std::string& world, double noise)
{
	const auto walls = world == "room" ? furnishedRoom() : corridorsWorld();
	const auto path = LoopPath::forWorld(world, 0.5);
	pmslam::PerfectMatchSlam slam;
	slam.initialize();
	const CPose2D t0(path.at(0));
	NoisyRun out;
	for (int k = 0; k < 20 * 50; ++k)
	{
		const double t = 0.05 * k, s = 0.5 * t;
		const TPose2D truth = path.at(s);
		const CPose2D rel = CPose2D(truth) - t0;
		slam.processOdometry(TPose2D(rel.x(), rel.y() + 0.02 * s, rel.phi()), 100 + t);
		auto scan = walls.scan(truth, 541, 1.5 * M_PI, 30.0, noise, unsigned(k + 1));
		scan.timestamp = mrpt::Clock::fromDouble(100 + t);
		const TPose2D est = slam.processScan(scan).pose;
		out.worst = std::max(out.worst, std::hypot(est.x - rel.x(), est.y - rel.y()));
	}
	out.scans = slam.scansProcessed();
	out.rejected = slam.scansRejected();
	out.wideSearches = slam.wideSearches();
	out.sigma = slam.sensorNoise().sigma("");
	return out;
}
}  // namespace

TEST(SensorNoise, TheRangeNoiseOfALidarIsReadFromItsScans)
{
	// A noiseless lidar reads (nearly) none: only the float rounding of its points and the corners.
	EXPECT_LT(readNoise(0.0, 1081), 0.002);
	// Within 15 % of the truth while the noise is well under the spacing of the returns.
	for (const double noise : {0.005, 0.01, 0.03})
	{
		const double read = readNoise(noise, 541);
		EXPECT_NEAR(read, noise, 0.15 * noise) << "noise " << noise;
	}
	// Noisier than the spacing of the returns, it reads low, never high: σ errs towards the configured one.
	const double read = readNoise(0.15, 541);
	EXPECT_GT(read, 0.06);
	EXPECT_LT(read, 0.15);
}

TEST(SensorNoise, SigmaIsTheConfiguredOneUnlessTheLidarIsNoisier)
{
	pmslam::SensorNoise noise(0.055);
	EXPECT_EQ(noise.sigma("front"), 0.055);	 // nothing measured yet
	const auto world = corridorsWorld();
	const auto path = LoopPath::forWorld("corridors", 0.5);
	for (int k = 0; k < 30; ++k)
	{
		noise.add("front", returns(world.scan(path.at(1.0 * k), 541, 1.5 * M_PI, 30.0, 0.01, unsigned(k + 1))));
		noise.add("back", returns(world.scan(path.at(1.0 * k), 541, 1.5 * M_PI, 30.0, 0.12, unsigned(k + 1))));
	}
	EXPECT_EQ(noise.sigma("front"), 0.055);	 // a SICK-like lidar keeps the configured σ exactly
	EXPECT_NEAR(noise.sigma("back"), 0.7 * *noise.noise("back"), 1e-12);
	EXPECT_GT(noise.sigma("back"), 0.07);  // each sensor is measured apart
}

TEST(SensorNoise, ANoisyLidarIsMatchedWithoutSearchingWideOnEveryScan)
{
	// 0.2 m of range noise, about ten times a SICK's. With σ fixed at 0.055 m a true pose scores under the wide
	// search's trigger: along the corridors it ran on 380 of the 1000 scans (in the room 39), each costing a search
	// over ±0.5 m and ±30°. With σ from the lidar's own noise it runs on none, and the room is mapped as well.
	const NoisyRun corridors = drive("corridors", 0.2);
	EXPECT_GT(corridors.sigma, 0.7 * 0.75 * 0.2);
	EXPECT_LE(corridors.sigma, 0.7 * 0.2);
	EXPECT_EQ(corridors.rejected, 0u);
	EXPECT_LT(corridors.wideSearches, corridors.scans / 100);
	const NoisyRun room = drive("room", 0.2);
	EXPECT_EQ(room.rejected, 0u);
	EXPECT_LT(room.wideSearches, room.scans / 100);
	EXPECT_LT(room.worst, 0.35);  // 2 % odometry drift over the 25 m loop is 0.5 m
	// A quiet lidar on the same path keeps the configured σ, and its accuracy.
	const NoisyRun quiet = drive("room", 0.01);
	EXPECT_EQ(quiet.sigma, 0.055);
	EXPECT_EQ(quiet.rejected, 0u);
	EXPECT_LT(quiet.worst, 0.1);
}
