// The maps pm-slam-app writes, opened by MRPT's own programs (package mrpt-apps):
// observations2map rebuilds a grid from map.simplemap.gz that agrees with map.gridmap.gz,
// grid-matching aligns the simple map with itself at the identity, and rawlog-edit parses it.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/io/MapExport.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>
#include <string>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace
{
namespace fs = std::filesystem;
using pmslam::testing::quote;
using pmslam::testing::run;

const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kSample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

bool haveTools()
{
	for (const char* t : {"observations2map", "grid-matching", "rawlog-edit"})
		if (!fs::exists(std::string("/usr/bin/") + t)) return false;
	return true;
}

/** Maps MRPT's sample log once for every test here. */
const fs::path& sampleOutput()
{
	static pmslam::testing::ScratchDir dir("mrpt-tools");
	static const fs::path out = [] {
		const fs::path o = dir.dir / "out";
		const auto r = run(quote(kApp) + " --quiet --no-progress --out " + quote(o.string()) + " " + quote(kSample));
		EXPECT_EQ(r.exitCode, 0) << r.output;
		return o;
	}();
	return out;
}

class MrptTools : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		if (!haveTools()) GTEST_SKIP() << "MRPT's programs (package mrpt-apps) are not installed";
		if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not installed (package mrpt-common)";
	}
};
}  // namespace

TEST_F(MrptTools, Observations2MapRebuildsTheGridFromOurSimpleMap)
{
	const fs::path out = sampleOutput();
	const fs::path ini = out / "o2m.ini", prefix = out / "rebuilt";
	std::FILE* f = std::fopen(ini.c_str(), "w");
	ASSERT_NE(f, nullptr);
	std::fputs(
		"[MappingApplication]\noccupancyGrid_count=1\n"
		"[MappingApplication_occupancyGrid_00_creationOpts]\nresolution=0.05\n"
		"[MappingApplication_occupancyGrid_00_insertOpts]\nmaxDistanceInsertion=100\n",
		f);
	std::fclose(f);
	const auto r = run("observations2map " + quote(ini.string()) + " " + quote((out / "map.simplemap.gz").string()) +
					   " " + quote(prefix.string()) + " </dev/null");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const fs::path rebuilt = prefix.string() + "_gridmap_no00.gridmap";
	ASSERT_TRUE(fs::exists(rebuilt)) << r.output;

	mrpt::maps::COccupancyGridMap2D ours, theirs;
	pmslam::loadGridMapGz((out / "map.gridmap.gz").string(), ours);
	pmslam::loadGridMapGz(rebuilt.string(), theirs);
	// MRPT inserts the same scans at the same poses with its own sensor model, so the walls
	// must be where ours are: most cells we call occupied have an occupied cell of MRPT's
	// within one cell (measured: 85 %). Not all: MRPT's model needs more hits before a cell
	// passes 0.5 and lets later beams clear thin or far walls. Scans at wrong poses would
	// leave well under half.
	std::size_t occupied = 0, confirmed = 0;
	for (unsigned y = 0; y < ours.getSizeY(); ++y)
		for (unsigned x = 0; x < ours.getSizeX(); ++x)
		{
			if (ours.getCell(x, y) >= 0.5f) continue;	 // getCell() is the probability of free
			++occupied;
			const double wx = ours.idx2x(x), wy = ours.idx2y(y);
			bool near = false;
			for (int dy = -1; dy <= 1 && !near; ++dy)
				for (int dx = -1; dx <= 1 && !near; ++dx)
				{
					const int tx = theirs.x2idx(wx + dx * 0.05), ty = theirs.y2idx(wy + dy * 0.05);
					near = tx >= 0 && ty >= 0 && tx < int(theirs.getSizeX()) && ty < int(theirs.getSizeY()) &&
						   theirs.getCell(tx, ty) < 0.5f;
				}
			confirmed += near;
		}
	ASSERT_GT(occupied, 1000u);
	EXPECT_GT(double(confirmed) / double(occupied), 0.8) << confirmed << " of " << occupied;
}

TEST_F(MrptTools, GridMatchingAlignsOurSimpleMapWithItselfAtTheIdentity)
{
	const fs::path out = sampleOutput();
	const std::string sm = quote((out / "map.simplemap.gz").string());
	const auto r = run("cd " + quote(out.string()) + " && grid-matching -m --nologo -n -1 " + sm + " -2 " + sm +
					   " --out-dir " + quote((out / "gm").string()) + " </dev/null");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto p = r.output.find("Mean pose:");
	ASSERT_NE(p, std::string::npos) << r.output;
	double x = 1, y = 1, phi = 1;
	ASSERT_EQ(std::sscanf(r.output.c_str() + r.output.find('(', p), "(%lf,%lf,%lfdeg)", &x, &y, &phi), 3) << r.output;
	EXPECT_NEAR(x, 0.0, 0.05);
	EXPECT_NEAR(y, 0.0, 0.05);
	EXPECT_NEAR(phi, 0.0, 1.0);
}

TEST_F(MrptTools, RawlogEditParsesOurSimpleMap)
{
	const fs::path out = sampleOutput();
	const auto r = run("cd " + quote(out.string()) + " && rawlog-edit --info -i " +
					   quote((out / "map.simplemap.gz").string()) + " </dev/null");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	// The whole file is one serialised CSimpleMap, read to its end without error.
	EXPECT_NE(r.output.find("Overall number of objects         : 1\n"), std::string::npos) << r.output;
}

// An MRPT user's icp-slam configuration: pm-slam-app maps the log it names into the folder it names,
// with one note on what it does not use.
TEST(IcpSlamIni, ConfigurationMapsItsLog)
{
	const std::string ini = "/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini";
	if (!fs::exists(ini) || !fs::exists(kSample)) GTEST_SKIP() << ini << " or MRPT's sample log not installed";
	pmslam::testing::ScratchDir dir("icp-slam-ini");
	const auto r = run("cd " + quote(dir.dir.string()) + " && " + quote(kApp) + " --no-progress --config " + quote(ini));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("is an icp-slam configuration"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("[ICP]"), std::string::npos) << r.output;
	EXPECT_NE(r.output.find("one_loop_only.rawlog"), std::string::npos) << r.output;
	const fs::path traj = dir.dir / "LOG_ICP-SLAM" / "trajectory.txt";	// logOutput_dir
	ASSERT_TRUE(fs::exists(traj));
	EXPECT_GT(pmslam::testing::countDataLines(traj), 200u);	// the sample log's 225 scans
}

// MRPT's own 3D-lidar and RGB-D sample rawlogs are mapped through their 2D slice (ScanSlice.h).
TEST(ThreeDRawlogs, MrptSampleLogsAreMapped)
{
	for (const char* name : {"test_velodyne_VLP16.rawlog", "tests_rgbd.rawlog"})
	{
		const std::string log = std::string("/usr/share/mrpt/datasets/") + name;
		if (!fs::exists(log))
		{
			std::printf("skipped: %s not installed (package mrpt-common)\n", log.c_str());
			continue;
		}
		pmslam::testing::ScratchDir dir("3d");
		const auto r = run(quote(kApp) + " --no-progress --out " + quote(dir.path("out")) + " " + quote(log));
		ASSERT_EQ(r.exitCode, 0) << name << ": " << r.output;
		EXPECT_EQ(pmslam::testing::countDataLines(dir.dir / "out" / "trajectory.txt"), 1u) << name;	// one observation each
		EXPECT_TRUE(fs::exists(dir.dir / "out" / "map.png"));
	}
	// A rotating scan without ring geometry is named, not silently dropped.
	const std::string rot = "/usr/share/mrpt/datasets/rot_scan_velodyne.rawlog";
	if (fs::exists(rot))
	{
		pmslam::testing::ScratchDir dir("rot");
		const auto r = run(quote(kApp) + " --no-progress --out " + quote(dir.path("out")) + " " + quote(rot));
		EXPECT_EQ(r.exitCode, 2) << r.output;
		EXPECT_NE(r.output.find("elevation angles"), std::string::npos) << r.output;
	}
}

// The pose graph pm-slam-app writes (graph.graph) is read and optimised by MRPT's graph-slam, and
// agrees with the final trajectory: its vertices are the keyframes where trajectory.txt has them
// (with the reported trajectory's odometry smoothing off, which otherwise moves a scan off its match).
TEST_F(MrptTools, GraphSlamReadsOurPoseGraph)
{
	if (!fs::exists("/usr/bin/graph-slam")) GTEST_SKIP() << "graph-slam not installed (package mrpt-apps)";
	pmslam::testing::ScratchDir dir("graph-slam");
	const fs::path out = dir.dir / "out";
	const auto slam = run(quote(kApp) + " --quiet --no-progress --set MappingApplication.odometrySmoothing=false --out " +
						  quote(out.string()) + " " + quote(kSample));
	ASSERT_EQ(slam.exitCode, 0) << slam.output;
	const fs::path graph = out / "graph.graph", optimised = out / "graph-slam-out.graph";
	ASSERT_TRUE(fs::exists(graph));
	const auto r = run("env -u DISPLAY timeout 120 graph-slam --2d --levmarq -q -i " + quote(graph.string()) + " -o " +
					   quote(optimised.string()) + " </dev/null");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	ASSERT_TRUE(fs::exists(optimised)) << r.output;
	// Every vertex of our graph is at a pose of the final trajectory (the keyframes are scans).
	std::ifstream g(graph), t(out / "trajectory.txt");
	std::vector<std::array<double, 3>> traj;
	for (std::string line; std::getline(t, line);)
	{
		if (line.empty() || line[0] == '#') continue;
		double ts, x, y, yaw;
		if (std::sscanf(line.c_str(), "%lf %lf %lf %lf", &ts, &x, &y, &yaw) == 4) traj.push_back({x, y, yaw});
	}
	std::size_t vertices = 0, onTrajectory = 0;
	double worst = 0;
	for (std::string line; std::getline(g, line);)
	{
		double x, y, phi;
		unsigned id;
		if (std::sscanf(line.c_str(), "VERTEX_SE2 %u %lf %lf %lf", &id, &x, &y, &phi) != 4) continue;
		++vertices;
		double nearest = 1e9;
		for (const auto& p : traj) nearest = std::min(nearest, std::hypot(p[0] - x, p[1] - y));
		worst = std::max(worst, nearest);
		onTrajectory += nearest < 1e-3;
	}
	std::printf("graph.graph: %zu vertices, %zu exactly on trajectory.txt, the farthest %.3f m from it\n", vertices,
				onTrajectory, worst);
	EXPECT_GT(vertices, 20u);
	EXPECT_EQ(onTrajectory, vertices);
}
