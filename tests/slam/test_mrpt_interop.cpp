// pmslam with MRPT's own types end to end: scanners of any aperture and mounting fed as
// CSensoryFrame / CActionCollection pairs or as observations, the built map read back by MRPT as a
// plain COccupancyGridMap2D, a saved .simplemap.gz reloaded by MRPT and rebuilt, and the
// share/examples/replace-icp program (CICP and PerfectMatchAligner behind the same reference).
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/slam/CMetricMapBuilderPM.h>
#include <pmslam/io/MapExport.h>

#include <cmath>
#include <map>
#include <sstream>

#include "RunProgram.h"
#include "SyntheticLogs.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using pmslam::testing::angleDiff;

namespace
{
struct Scanner
{
	const char* name;
	double apertureDeg;
	std::size_t beams;
	CPose3D sensorPose;	 // on the robot: x, y, z, yaw, pitch, roll
	bool actionObservation;	 // CActionCollection + CSensoryFrame, else CObservationOdometry + scan
};

std::ostream& operator<<(std::ostream& o, const Scanner& s) { return o << s.name; }

class MrptScanner : public ::testing::TestWithParam<Scanner>
{
};

// Robot poses along roomPath(), with 2 % scale and 0.05 rad/m heading drift in the odometry.
struct TrackingRun
{
	double meanError = 0, maxError = 0, maxYawErrorDeg = 0;
	std::size_t matched = 0, scans = 0;
};

TrackingRun trackWithMrptTypes(const Scanner& s, pmslam::CMetricMapBuilderPM& slam)
{
	const auto world = pmslam::testing::furnishedRoom();
	const auto truth = pmslam::testing::roomPath(150);
	const auto odo = pmslam::testing::driftingOdometry(truth, 1.02, 0.05);
	slam.initialize();
	TrackingRun r;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		auto scan = mrpt::obs::CObservation2DRangeScan::Create(
			world.scan(truth[k], s.beams, mrpt::DEG2RAD(s.apertureDeg), 20.0, 0.005, unsigned(k + 1), s.sensorPose));
		scan->sensorLabel = "LASER";
		if (s.actionObservation)
		{
			mrpt::obs::CActionCollection acts;
			if (k > 0)
			{
				mrpt::obs::CActionRobotMovement2D mov;
				mov.computeFromOdometry(CPose2D(odo[k]) - CPose2D(odo[k - 1]),
										mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
				acts.insert(mov);
			}
			mrpt::obs::CSensoryFrame sf;
			sf.insert(scan);
			slam.processActionObservation(acts, sf);
		}
		else
		{
			auto o = mrpt::obs::CObservationOdometry::Create();
			o->odometry = CPose2D(odo[k]);
			slam.processObservation(o);
			slam.processObservation(scan);
		}
		const CPose3D est = slam.getCurrentPoseEstimation()->getMeanVal();
		const TPose2D ref = pmslam::testing::relativeToFirst(truth, k);
		const double e = std::hypot(est.x() - ref.x, est.y() - ref.y);
		r.meanError += e / double(truth.size());
		r.maxError = std::max(r.maxError, e);
		r.maxYawErrorDeg = std::max(r.maxYawErrorDeg, std::abs(mrpt::RAD2DEG(angleDiff(est.yaw(), ref.phi))));
	}
	r.matched = slam.scansMatched();
	r.scans = slam.scansProcessed();
	return r;
}

// Occupied cells by global index (the distance layer's lattice).
std::map<std::pair<int, int>, bool> occupiedCells(const mrpt::maps::COccupancyGridMap2D& g)
{
	std::map<std::pair<int, int>, bool> out;
	const double r = g.getResolution();
	for (unsigned y = 0; y < g.getSizeY(); ++y)
		for (unsigned x = 0; x < g.getSizeX(); ++x)
			if (g.getRawMap()[std::size_t(y) * g.getSizeX() + x] < 0)
				out[{int(std::lround(g.getXMin() / r)) + int(x), int(std::lround(g.getYMin() / r)) + int(y)}] = true;
	return out;
}
}  // namespace

TEST_P(MrptScanner, TracksTheRobot)
{
	const Scanner s = GetParam();
	pmslam::CMetricMapBuilderPM slam;
	const TrackingRun r = trackWithMrptTypes(s, slam);
	std::cout << s.name << ": mean " << r.meanError << " m, max " << r.maxError << " m, yaw max " << r.maxYawErrorDeg
			  << " deg, matched " << r.matched << "/" << r.scans << "\n";
	EXPECT_EQ(r.scans, 150u);
	EXPECT_GT(r.matched, 100u);
	EXPECT_LT(r.meanError, 0.01);
	EXPECT_LT(r.maxError, 0.03);
	EXPECT_LT(r.maxYawErrorDeg, 0.5);
}

INSTANTIATE_TEST_SUITE_P(
	MrptInterop, MrptScanner,
	::testing::Values(
		Scanner{"hokuyo240", 240, 683, CPose3D(0.20, 0.05, 0.30, 0, 0, 0), true},
		Scanner{"sick270_yawed", 270, 541, CPose3D(-0.10, 0.12, 0.25, mrpt::DEG2RAD(90.0), 0, 0), false},
		Scanner{"lidar360", 360, 720, CPose3D(0.0, 0.0, 0.4, mrpt::DEG2RAD(45.0), 0, 0), true},
		Scanner{"upside_down180", 180, 181, CPose3D(0.15, 0.0, 0.30, 0, 0, M_PI), false},
		Scanner{"upside_down360_yawed", 360, 400, CPose3D(-0.2, -0.1, 0.2, mrpt::DEG2RAD(-30.0), 0, M_PI), true}),
	[](const ::testing::TestParamInfo<Scanner>& i) { return std::string(i.param.name); });

TEST(MrptInterop, BuiltMetricMapIsAPlainMrptGridWhenSerialised)
{
	pmslam::CMetricMapBuilderPM slam;
	trackWithMrptTypes(Scanner{"sick", 180, 361, CPose3D(), true}, slam);
	const mrpt::maps::CMultiMetricMap* mm = slam.getCurrentlyBuiltMetricMap();
	ASSERT_NE(mm, nullptr);
	ASSERT_EQ(mm->countMapsByClass<mrpt::maps::COccupancyGridMap2D>(), 1u);
	const auto grid = mm->mapByClass<mrpt::maps::COccupancyGridMap2D>();
	ASSERT_TRUE(grid);

	// The grid alone, as MRPT's tools write and read it (polymorphic object in an archive).
	mrpt::io::CMemoryStream buf;
	mrpt::serialization::archiveFrom(buf) << *grid;
	buf.Seek(0);
	const auto obj = mrpt::serialization::archiveFrom(buf).ReadObject();
	ASSERT_TRUE(obj);
	EXPECT_STREQ(obj->GetRuntimeClass()->className, "mrpt::maps::COccupancyGridMap2D");
	const auto back = std::dynamic_pointer_cast<mrpt::maps::COccupancyGridMap2D>(obj);
	ASSERT_TRUE(back);
	EXPECT_EQ(back->getSizeX(), grid->getSizeX());
	EXPECT_EQ(back->getSizeY(), grid->getSizeY());
	EXPECT_FLOAT_EQ(back->getXMin(), grid->getXMin());
	EXPECT_FLOAT_EQ(back->getResolution(), 0.05f);
	EXPECT_EQ(back->getRawMap(), grid->getRawMap());
	EXPECT_GT(occupiedCells(*back).size(), 300u);

	// The whole CMultiMetricMap too: it reads back with its grid as a COccupancyGridMap2D.
	mrpt::io::CMemoryStream buf2;
	mrpt::serialization::archiveFrom(buf2) << *mm;
	buf2.Seek(0);
	mrpt::maps::CMultiMetricMap mm2;
	mrpt::serialization::archiveFrom(buf2) >> mm2;
	const auto grid2 = mm2.mapByClass<mrpt::maps::COccupancyGridMap2D>();
	ASSERT_TRUE(grid2);
	EXPECT_EQ(grid2->getRawMap(), grid->getRawMap());

	// And the .gridmap.gz pm-slam-app writes holds the same cells.
	pmslam::testing::ScratchDir dir("interop-grid");
	pmslam::saveGridMapGz(slam.grid(), dir.path("map.gridmap.gz"));
	mrpt::io::CFileGZInputStream f(dir.path("map.gridmap.gz"));
	const auto obj3 = mrpt::serialization::archiveFrom(f).ReadObject();
	const auto grid3 = std::dynamic_pointer_cast<mrpt::maps::COccupancyGridMap2D>(obj3);
	ASSERT_TRUE(grid3);
	EXPECT_EQ(grid3->getRawMap(), grid->getRawMap());
}

TEST(MrptInterop, SavedSimpleMapReloadsWithMrptAndRebuildsTheSameMap)
{
	pmslam::CMetricMapBuilderPM slam;
	trackWithMrptTypes(Scanner{"sick270", 270, 541, CPose3D(0.1, 0, 0.3, 0, 0, 0), false}, slam);
	mrpt::maps::CSimpleMap keyframes;
	slam.getCurrentlyBuiltMap(keyframes);
	ASSERT_EQ(keyframes.size(), slam.scansInserted());
	ASSERT_GT(keyframes.size(), 10u);

	pmslam::testing::ScratchDir dir("interop-simplemap");
	const std::string path = dir.path("map.simplemap.gz");
	pmslam::saveSimpleMapGz(keyframes, path);

	// Read with MRPT's own serialization, nothing of pmslam.
	mrpt::maps::CSimpleMap reloaded;
	{
		mrpt::io::CFileGZInputStream f;
		ASSERT_TRUE(f.open(path));
		mrpt::serialization::archiveFrom(f) >> reloaded;
	}
	ASSERT_EQ(reloaded.size(), keyframes.size());
	for (std::size_t i = 0; i < reloaded.size(); ++i)
	{
		const auto& [pose, sf] = reloaded.get(i);
		ASSERT_TRUE(pose && sf);
		ASSERT_EQ(sf->size(), 1u);
		const auto scan = sf->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
		ASSERT_TRUE(scan);
		EXPECT_NEAR(scan->sensorPose.x(), 0.1, 1e-9);
		const CPose3D p = pose->getMeanVal(), q = std::get<0>(keyframes.get(i))->getMeanVal();
		EXPECT_NEAR(p.x(), q.x(), 1e-12);
		EXPECT_NEAR(p.yaw(), q.yaw(), 1e-12);
	}

	pmslam::CMetricMapBuilderPM rebuilt;
	rebuilt.initialize(reloaded);
	const auto a = occupiedCells(slam.grid().denseCopy()), b = occupiedCells(rebuilt.grid().denseCopy());
	EXPECT_GT(a.size(), 300u);
	EXPECT_EQ(a, b) << "occupied cells: built " << a.size() << ", rebuilt " << b.size();
	EXPECT_EQ(rebuilt.getCurrentlyBuiltMapSize(), keyframes.size());
}

TEST(MrptInterop, ReplaceIcpExampleFindsThePoseWithBothAligners)
{
	const std::string exe = PMSLAM_BINARY_DIR "/bin/example-replace-icp";
	if (!std::filesystem::exists(exe)) GTEST_SKIP() << exe << " not built (PMSLAM_BUILD_EXAMPLES=OFF)";
	// With MRPT's Malaga campus map when installed, and with the synthetic room regardless.
	for (const std::string& arg : {std::string(), std::string("/nonexistent.gridmap.gz")})
	{
		const auto r = pmslam::testing::run(pmslam::testing::quote(exe) + (arg.empty() ? "" : " " + arg));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		std::map<std::string, TPose2D> poses;
		std::istringstream in(r.output);
		std::string name;
		double x, y, yawDeg;
		for (std::string line; std::getline(in, line);)
			if (std::istringstream(line) >> name >> x >> y >> yawDeg) poses[name] = {x, y, yawDeg};
		ASSERT_EQ(poses.count("truth"), 1u) << r.output;
		const TPose2D t = poses["truth"];
		EXPECT_GT(std::hypot(poses["guess"].x - t.x, poses["guess"].y - t.y), 0.2) << r.output;
		for (const char* aligner : {"CICP", "PerfectMatchAligner"})
		{
			ASSERT_EQ(poses.count(aligner), 1u) << r.output;
			const TPose2D p = poses[aligner];
			EXPECT_LT(std::hypot(p.x - t.x, p.y - t.y), 0.02) << aligner << "\n" << r.output;
			EXPECT_LT(std::abs(p.phi - t.phi), 0.2) << aligner << " (deg)\n" << r.output;
		}
	}
}
