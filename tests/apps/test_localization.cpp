// Localisation on a prior map: CMetricMapBuilderPM::initializeWithFixedMap() and
// `pm-slam-app --localize MAP [--initial-pose X,Y,YAW_DEG]`.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/CMetricMapBuilderPM.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/io/Trajectory.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using pmslam::testing::angleDiff;
using pmslam::testing::quote;
using pmslam::testing::run;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kSample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

// The furnished room rasterised into a stock MRPT grid (5 cm, walls on cell centres).
mrpt::maps::COccupancyGridMap2D roomGrid()
{
	mrpt::maps::COccupancyGridMap2D g(-5, 6, -4, 4, 0.05f);
	pmslam::testing::furnishedRoom().rasterise(g);
	return g;
}

std::size_t obstacleCount(const mrpt::maps::COccupancyGridMap2D& g)
{
	std::size_t n = 0;
	for (auto c : g.getRawMap()) n += c < 0;
	return n;
}

struct Tracking
{
	double firstError = 0, finalError = 0, maxErrorAfter5 = 0, maxYawDegAfter5 = 0;
};

// Localises along roomPath() (truth in the grid's frame) with odometry that drifts, starting
// from `initial`; errors of the estimate against the truth.
Tracking localise(pmslam::CMetricMapBuilderPM& loc, const mrpt::maps::COccupancyGridMap2D& grid,
				  const TPose2D& initial, const mrpt::math::TPoint2D& expectedShift = {0, 0})
{
	const auto world = pmslam::testing::furnishedRoom();
	const auto truth = pmslam::testing::roomPath(120);
	const auto odo = pmslam::testing::driftingOdometry(truth, 1.03, 0.08, CPose2D(100, -50, 1.0));
	loc.initializeWithFixedMap(grid, initial);
	Tracking t;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		const auto& r = loc.processScan(world.scan(truth[k], 361, M_PI, 20.0, 0.005, unsigned(k + 3)), odo[k]);
		EXPECT_FALSE(r.inserted);
		const double e = std::hypot(r.pose.x - expectedShift.x - truth[k].x, r.pose.y - expectedShift.y - truth[k].y);
		if (k == 0) t.firstError = e;
		if (k >= 5)
		{
			t.maxErrorAfter5 = std::max(t.maxErrorAfter5, e);
			t.maxYawDegAfter5 = std::max(t.maxYawDegAfter5, std::abs(mrpt::RAD2DEG(angleDiff(r.pose.phi, truth[k].phi))));
		}
		t.finalError = e;
	}
	return t;
}
}  // namespace

TEST(Localization, ConvergesFromAWrongButCloseInitialPose)
{
	const auto grid = roomGrid();
	const TPose2D start = pmslam::testing::roomPath(120).front();
	pmslam::CMetricMapBuilderPM loc;
	const TPose2D wrong(start.x + 0.15, start.y - 0.12, start.phi + mrpt::DEG2RAD(4.0));
	const Tracking t = localise(loc, grid, wrong);
	std::cout << "first scan " << t.firstError << " m, max after 5 scans " << t.maxErrorAfter5 << " m / "
			  << t.maxYawDegAfter5 << " deg, final " << t.finalError << " m\n";
	EXPECT_LT(t.firstError, 0.05);
	EXPECT_LT(t.maxErrorAfter5, 0.02);
	EXPECT_LT(t.maxYawDegAfter5, 0.5);
	EXPECT_LT(t.finalError, 0.02);
	// Every scan matched against the fixed map; nothing inserted; the map is the prior, cell for cell.
	EXPECT_EQ(loc.scansMatched(), loc.scansProcessed());
	EXPECT_EQ(loc.scansInserted(), 0u);
	EXPECT_EQ(loc.getCurrentlyBuiltMapSize(), 0u);
	EXPECT_FALSE(loc.options.enableMapUpdating);
	// Cell for cell: grid cell (ix, iy) is lattice cell (ix, iy) + the grid origin in cells.
	const int ox = int(std::lround(grid.getXMin() / grid.getResolution())),
			  oy = int(std::lround(grid.getYMin() / grid.getResolution()));
	std::size_t differ = 0;
	for (unsigned iy = 0; iy < grid.getSizeY(); ++iy)
		for (unsigned ix = 0; ix < grid.getSizeX(); ++ix)
			differ += loc.grid().cells().get(int(ix) + ox, int(iy) + oy) != grid.getRawMap()[iy * grid.getSizeX() + ix];
	EXPECT_EQ(differ, 0u);
	EXPECT_EQ(loc.grid().cells().observedCells(), std::size_t(std::count_if(grid.getRawMap().begin(), grid.getRawMap().end(), [](auto c) { return c != 0; })));
	EXPECT_EQ(loc.fixedMapShift().x, 0.0);
	EXPECT_EQ(loc.fixedMapShift().y, 0.0);
}

TEST(Localization, KeepsTheGridResolutionAndAcceptsAFreshBuilderState)
{
	// A 10 cm prior map with a builder configured for 5 cm: the map keeps its 10 cm cells.
	mrpt::maps::COccupancyGridMap2D coarse(-5, 6, -4, 4, 0.10f);
	pmslam::testing::furnishedRoom().rasterise(coarse);
	pmslam::CMetricMapBuilderPM loc;
	loc.initialize();  // a previous SLAM state is discarded
	const Tracking t = localise(loc, coarse, pmslam::testing::roomPath(120).front());
	EXPECT_FLOAT_EQ(loc.grid().getResolution(), 0.10f);
	EXPECT_LT(t.maxErrorAfter5, 0.05);
	EXPECT_EQ(loc.scansInserted(), 0u);

	// An empty map is refused.
	mrpt::maps::COccupancyGridMap2D blank(-1, 1, -1, 1, 0.05f);
	EXPECT_THROW(loc.initializeWithFixedMap(blank, TPose2D(0, 0, 0)), std::invalid_argument);
}

TEST(Localization, GridOffTheResolutionLatticeIsMovedOntoIt)
{
	// MRPT's setSize() and deserialisation round a grid's origin to a multiple of the resolution,
	// but resizeGrid() keeps a requested origin up to 5 % of a cell off that lattice.
	const auto grid = roomGrid();
	const float r = grid.getResolution();
	mrpt::maps::COccupancyGridMap2D offLattice = grid;
	offLattice.resizeGrid(grid.getXMin() - 10.04f * r, grid.getXMax(), grid.getYMin() - 20.03f * r, grid.getYMax(),
						  0.95f, false);
	const double fx = offLattice.getXMin() / r - std::round(offLattice.getXMin() / r);
	const double fy = offLattice.getYMin() / r - std::round(offLattice.getYMin() / r);
	ASSERT_GT(std::abs(fx), 0.01) << "the grid must be off the lattice for this test";
	ASSERT_GT(std::abs(fy), 0.01);
	// The cells kept their indices: the content moved with the origin's fraction of a cell.
	const mrpt::math::TPoint2D movedBy(fx * r, fy * r);
	pmslam::CMetricMapBuilderPM loc;
	const TPose2D start = pmslam::testing::roomPath(120).front();
	const TPose2D startInMap(start.x + movedBy.x, start.y + movedBy.y, start.phi);
	// Truth in the off-lattice map's frame is truth + movedBy; the builder's map is shifted again by
	// fixedMapShift() (< half a cell per axis), which the estimate carries.
	const auto world = pmslam::testing::furnishedRoom();
	const auto truth = pmslam::testing::roomPath(120);
	loc.initializeWithFixedMap(offLattice, startInMap);
	const auto shift = loc.fixedMapShift();
	EXPECT_LE(std::abs(shift.x), r / 2 + 1e-6);
	EXPECT_LE(std::abs(shift.y), r / 2 + 1e-6);
	EXPECT_NEAR(shift.x, -movedBy.x, 1e-5);
	EXPECT_NEAR(shift.y, -movedBy.y, 1e-5);
	// The cells are the same, each on the lattice cell the shifted origin puts it in.
	const int ox = int(std::lround((offLattice.getXMin() + shift.x) / r)),
			  oy = int(std::lround((offLattice.getYMin() + shift.y) / r));
	EXPECT_NEAR(ox * r, offLattice.getXMin() + shift.x, 1e-5);
	std::size_t differ = 0;
	for (unsigned iy = 0; iy < offLattice.getSizeY(); ++iy)
		for (unsigned ix = 0; ix < offLattice.getSizeX(); ++ix)
			differ += loc.grid().cells().get(int(ix) + ox, int(iy) + oy) !=
					  offLattice.getRawMap()[iy * offLattice.getSizeX() + ix];
	EXPECT_EQ(differ, 0u);
	// Every obstacle survives the move.
	EXPECT_EQ(obstacleCount(loc.grid().denseCopy()), obstacleCount(offLattice));
	EXPECT_GT(obstacleCount(offLattice), 500u);
	double maxErr = 0;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		const auto& p = loc.processScan(world.scan(truth[k], 361, M_PI, 20.0, 0.0, 1)).pose;
		maxErr = std::max(maxErr, std::hypot(p.x - (truth[k].x + movedBy.x + shift.x), p.y - (truth[k].y + movedBy.y + shift.y)));
	}
	EXPECT_LT(maxErr, 0.02);
}

TEST(Localization, PmSlamAppLocalisesOnItsOwnMapOfTheMrptSampleLog)
{
	if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not installed (comes with libmrpt-dev)";
	pmslam::testing::ScratchDir dir("localize");
	const std::string slamOut = dir.path("slam"), locOut = dir.path("loc");
	auto r = run(quote(kApp) + " --quiet --out " + quote(slamOut) + " " + quote(kSample));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const fs::path map = fs::path(slamOut) / "map.gridmap.gz";
	const std::string mapBytes = pmslam::testing::readText(map);
	const auto mapTime = fs::last_write_time(map);

	r = run(quote(kApp) + " --localize " + quote(map.string()) + " --initial-pose 0,0,0 --out " + quote(locOut) + " " +
			quote(kSample));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("inserted 0,"), std::string::npos) << r.output;
	EXPECT_TRUE(fs::exists(fs::path(locOut) / "map.png"));
	EXPECT_TRUE(fs::exists(fs::path(locOut) / "timing.txt"));
	EXPECT_FALSE(fs::exists(fs::path(locOut) / "map.gridmap.gz"));  // the fixed map is not rewritten
	EXPECT_FALSE(fs::exists(fs::path(locOut) / "map.simplemap.gz"));
	EXPECT_EQ(pmslam::testing::readText(map), mapBytes) << "the prior map changed";
	EXPECT_EQ(fs::last_write_time(map), mapTime);

	const auto slam = pmslam::loadTrajectory((fs::path(slamOut) / "trajectory.txt").string());
	const auto loc = pmslam::loadTrajectory((fs::path(locOut) / "trajectory.txt").string());
	ASSERT_EQ(slam.size(), loc.size());
	ASSERT_GT(slam.size(), 200u);
	double sum = 0, maxD = 0, maxYaw = 0;
	for (std::size_t i = 0; i < slam.size(); ++i)
	{
		EXPECT_EQ(slam[i].timestamp, loc[i].timestamp);
		const double d = std::hypot(slam[i].x - loc[i].x, slam[i].y - loc[i].y);
		sum += d;
		maxD = std::max(maxD, d);
		maxYaw = std::max(maxYaw, std::abs(mrpt::RAD2DEG(angleDiff(slam[i].yaw, loc[i].yaw))));
	}
	std::cout << "localisation vs SLAM trajectory over " << slam.size() << " scans: mean " << sum / slam.size()
			  << " m, max " << maxD << " m, max yaw " << maxYaw << " deg\n";
	EXPECT_LT(sum / slam.size(), 0.05);
	EXPECT_LT(maxD, 0.2);
	EXPECT_LT(maxYaw, 2.0);

	// Started 30 cm and 5 degrees away, it still finds the SLAM trajectory.
	r = run(quote(kApp) + " --quiet --localize " + quote(map.string()) + " --initial-pose 0.3,-0.2,5 --out " +
			quote(locOut) + " " + quote(kSample));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto loc2 = pmslam::loadTrajectory((fs::path(locOut) / "trajectory.txt").string());
	ASSERT_EQ(loc2.size(), slam.size());
	double sum2 = 0;
	for (std::size_t i = 10; i < slam.size(); ++i) sum2 += std::hypot(slam[i].x - loc2[i].x, slam[i].y - loc2[i].y);
	EXPECT_LT(sum2 / double(slam.size() - 10), 0.05);
}

TEST(Localization, PmSlamAppLocalisesOnMrptsOwnGridmapFormat)
{
	// A map MRPT wrote (not pm-slam-app): a stock COccupancyGridMap2D serialised to a plain
	// (uncompressed) .gridmap file, and an observation-only rawlog of the same room.
	pmslam::testing::ScratchDir dir("localize-mrpt");
	const auto grid = roomGrid();
	{
		mrpt::io::CFileOutputStream f(dir.path("room.gridmap"));
		mrpt::serialization::archiveFrom(f) << grid;
	}
	const auto truth = pmslam::testing::roomPath(80);
	const auto odo = pmslam::testing::driftingOdometry(truth, 1.02, 0.05, CPose2D(truth.front()));
	pmslam::testing::writeRawlog(dir.path("room.rawlog"), pmslam::testing::furnishedRoom(), truth, odo,
								 pmslam::testing::RawlogSpec{});
	const TPose2D s = truth.front();
	const std::string pose = pmslam::testing::fmt(s.x, 4) + "," + pmslam::testing::fmt(s.y, 4) + "," +
							 pmslam::testing::fmt(mrpt::RAD2DEG(s.phi), 4);
	auto r = run(quote(kApp) + " --quiet --localize " + quote(dir.path("room.gridmap")) + " --initial-pose " + pose +
				 " --out " + quote(dir.path("out")) + " " + quote(dir.path("room.rawlog")));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto loc = pmslam::loadTrajectory(dir.path("out/trajectory.txt"));
	ASSERT_EQ(loc.size(), truth.size());
	for (std::size_t i = 0; i < loc.size(); ++i)
		EXPECT_LT(std::hypot(loc[i].x - truth[i].x, loc[i].y - truth[i].y), 0.02) << "scan " << i;

	// Bad uses: exit code 2, and no --out folder is created for a bad map.
	r = run(quote(kApp) + " --localize /nonexistent.gridmap.gz --out " + quote(dir.path("bad")) + " " +
			quote(dir.path("room.rawlog")));
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("/nonexistent.gridmap.gz"), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(dir.path("bad")));
	r = run(quote(kApp) + " --localize " + quote(dir.path("room.rawlog")) + " --out " + quote(dir.path("bad")) + " " +
			quote(dir.path("room.rawlog")));
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("COccupancyGridMap2D"), std::string::npos) << r.output;
	r = run(quote(kApp) + " --localize " + quote(dir.path("room.gridmap")) + " --initial-pose 1,2 " +
			quote(dir.path("room.rawlog")));
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("X,Y,YAW_DEG"), std::string::npos) << r.output;
	r = run(quote(kApp) + " --initial-pose 1,2,3 " + quote(dir.path("room.rawlog")));
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("needs --localize"), std::string::npos) << r.output;
}
