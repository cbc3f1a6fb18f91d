// pm-slam-app end to end: the MRPT sample log, the benchmark logs, and its command line.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <dlfcn.h>

#include <filesystem>
#include <fstream>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using pmslam::testing::quote;
using pmslam::testing::run;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kSample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
const std::string kDatasets = PMSLAM_SOURCE_DIR "/../shared/datasets";

fs::path freshDir(const std::string& name)
{
	const fs::path d = fs::temp_directory_path() / ("pmslam-test-" + name + "-" + std::to_string(::getpid()));
	fs::remove_all(d);
	return d;
}

}  // namespace

TEST(PmSlamApp, MapsTheMrptSampleLogAndWritesEveryOutput)
{
	if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not installed (package mrpt-common)";
	const auto out = freshDir("sample");
	const auto r = run(quote(kApp) + " --out " + quote(out.string()) + " " + quote(kSample));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	for (const char* f : {"trajectory.txt", "timing.txt", "map.png", "map.pgm", "map.yaml", "map.gridmap.gz",
						  "map.simplemap.gz"})
	{
		EXPECT_TRUE(fs::exists(out / f)) << f;
		EXPECT_GT(fs::file_size(out / f), 100u) << f;
	}
	// One pose per scan: the summary says how many scans there were.
	const auto traj = pmslam::loadTrajectory((out / "trajectory.txt").string());
	EXPECT_NE(r.output.find("scans " + std::to_string(traj.size()) + ","), std::string::npos) << r.output;
	EXPECT_GT(traj.size(), 200u);
	EXPECT_EQ(pmslam::testing::countDataLines(out / "timing.txt"), traj.size());
	EXPECT_EQ(traj.front().x, 0.0);
	EXPECT_EQ(traj.front().y, 0.0);
	for (std::size_t i = 1; i < traj.size(); ++i) EXPECT_GT(traj[i].timestamp, traj[i - 1].timestamp);
	// The MRPT-format map loads back, and has walls.
	mrpt::maps::COccupancyGridMap2D grid;
	pmslam::loadGridMapGz((out / "map.gridmap.gz").string(), grid);
	std::size_t occupied = 0;
	for (unsigned y = 0; y < grid.getSizeY(); ++y)
		for (unsigned x = 0; x < grid.getSizeX(); ++x) occupied += grid.getCell(x, y) < 0.3f;
	EXPECT_GT(occupied, 2000u);
	// The ROS map's header matches its YAML.
	std::ifstream yaml(out / "map.yaml");
	std::string text((std::istreambuf_iterator<char>(yaml)), std::istreambuf_iterator<char>());
	EXPECT_NE(text.find("image: map.pgm"), std::string::npos);
	EXPECT_NE(text.find("resolution: 0.05"), std::string::npos);
	std::ifstream pgm(out / "map.pgm", std::ios::binary);
	std::string magic;
	pgm >> magic;
	EXPECT_EQ(magic, "P5");
	fs::remove_all(out);
}

TEST(PmSlamApp, RejectsBadCommandLinesWithExitCode2)
{
	const auto out = freshDir("bad");
	auto r = run(quote(kApp) + " --out " + quote(out.string()) + " /nonexistent/log.clf");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("/nonexistent/log.clf"), std::string::npos) << r.output;
	r = run(quote(kApp) + " --frobnicate");
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("unknown option '--frobnicate'"), std::string::npos) << r.output;
	r = run(quote(kApp) + " --set PerfectMatch.sigmaa=1 " + quote(kSample));
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("did you mean 'sigma'"), std::string::npos) << r.output;
	r = run(quote(kApp) + " --config /nonexistent.ini " + quote(kSample));
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.output.find("/nonexistent.ini"), std::string::npos) << r.output;
	r = run(quote(kApp) + " --help");
	EXPECT_EQ(r.exitCode, 0);
	EXPECT_NE(r.output.find("usage: pm-slam-app"), std::string::npos);
	fs::remove_all(out);
}

// --gui must never cost a headless run: MRPT's GUI stack lives in a plugin loaded on demand.
TEST(PmSlamApp, HeadlessRunsLinkNeitherTheGuiStackNorMrptSlamAndTheWindowPluginLoads)
{
	const auto ldd = run("ldd " + quote(kApp));
	ASSERT_EQ(ldd.exitCode, 0) << ldd.output;
	EXPECT_EQ(ldd.output.find("libmrpt-gui"), std::string::npos) << ldd.output;
	EXPECT_EQ(ldd.output.find("libwx_"), std::string::npos);
	// Nor MRPT's SLAM library and what it pulls in (OpenCV's feature and video modules, ...):
	// pm-slam-app maps with PerfectMatchSlam, not the CMetricMapBuilder wrapper (~30 MB less).
	EXPECT_EQ(ldd.output.find("libmrpt-slam"), std::string::npos) << ldd.output;
	EXPECT_EQ(ldd.output.find("libmrpt-vision"), std::string::npos) << ldd.output;

	const std::string plugin = PMSLAM_BINARY_DIR "/bin/libpmslam-viewer.so";
	void* lib = ::dlopen(plugin.c_str(), RTLD_NOW | RTLD_LOCAL);
	ASSERT_NE(lib, nullptr) << ::dlerror();
	for (const char* sym : {"pmslam_viewer_open", "pmslam_viewer_show", "pmslam_viewer_wait", "pmslam_viewer_close"})
		EXPECT_NE(::dlsym(lib, sym), nullptr) << sym;
}

TEST(PmSlamApp, GuiWithoutADisplayWarnsAndRunsHeadless)
{
	if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not installed (package mrpt-common)";
	const auto out = freshDir("gui-headless");
	const auto r = run("env -u DISPLAY -u WAYLAND_DISPLAY " + quote(kApp) + " --gui --max-scans 30 --quiet --out " +
					   quote(out.string()) + " " + quote(kSample));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_NE(r.output.find("--gui needs a display"), std::string::npos) << r.output;
	EXPECT_TRUE(fs::exists(out / "trajectory.txt"));
	fs::remove_all(out);
}


class BenchmarkLog : public ::testing::TestWithParam<std::string>
{
};

TEST_P(BenchmarkLog, RunsToTheEndWithAPosePerScan)
{
	const std::string name = GetParam();
	const fs::path clf = fs::path(kDatasets) / name / (name + ".clf");
	if (!fs::exists(clf)) GTEST_SKIP() << clf << " absent: the benchmark logs live in ../shared/datasets beside the project";
	const auto out = freshDir(name);
	std::string config = PMSLAM_SOURCE_DIR "/config/" + name + ".ini";
	if (!fs::exists(config)) config = PMSLAM_SOURCE_DIR "/config/default.ini";
	const auto r = run(quote(kApp) + " --config " + quote(config) + " --out " + quote(out.string()) + " " + quote(clf.string()));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	// Every FLASER line has a pose, stamped with its own ipc_timestamp.
	std::ifstream in(clf);
	std::string line;
	std::size_t lasers = 0;
	while (std::getline(in, line)) lasers += line.rfind("FLASER ", 0) == 0;
	const auto traj = pmslam::loadTrajectory((out / "trajectory.txt").string());
	EXPECT_EQ(traj.size(), lasers);
	// All relations find their poses; the accuracy itself is measured by bench/run.sh, here only
	// a bound that catches a broken build (lost tracking gives metres).
	const auto rel = pmslam::loadRelations((fs::path(kDatasets) / name / (name + ".relations")).string());
	const auto err = pmslam::evaluateRelativePoses(traj, rel);
	EXPECT_EQ(err.missing, 0u);
	EXPECT_LT(err.transMean, 0.15) << name;
	EXPECT_LT(err.rotMeanDeg, 1.5) << name;
	std::cout << name << ": " << err.transMean << " +- " << err.transStd << " m, " << err.rotMeanDeg << " +- "
			  << err.rotStdDeg << " deg\n";
	fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(PmSlamApp, BenchmarkLog, ::testing::Values("intel", "aces", "fr079"));
