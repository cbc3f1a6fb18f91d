// pmslam as an installed package: `cmake --install` into a scratch prefix, then the stand-alone
// project in share/examples/external-project is configured with find_package(pmslam) against that
// prefix only, built (one small file, the headers' paths <pmslam/<folder>/X.h>) and run on MRPT's
// sample log; tests/apps/old-include-paths checks the old paths <pmslam/X.h> (deprecated forwarding
// headers) still compile against it.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using pmslam::testing::quote;
using pmslam::testing::run;

namespace
{
const std::string kCMake = PMSLAM_CMAKE_COMMAND;
const std::string kSample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
}  // namespace

TEST(Install, ExternalProjectBuildsAgainstTheInstalledPackage)
{
#ifdef PMSLAM_SANITIZE
	GTEST_SKIP() << "sanitizer build: the installed library needs the sanitizer runtime in every consumer";
#endif
	const auto t0 = std::chrono::steady_clock::now();
	pmslam::testing::ScratchDir scratch("install");
	const fs::path prefix = scratch.dir / "prefix";

	auto r = run(quote(kCMake) + " --install " + quote(PMSLAM_BINARY_DIR) + " --prefix " + quote(prefix.string()));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	for (const char* f : {"include/pmslam/slam/CMetricMapBuilderPM.h", "include/pmslam/match/PerfectMatchAligner.h",
						  "include/pmslam/map/OccupancyDistanceGridMap.h", "include/pmslam/io/MapExport.h",
						  "lib/libpmslam.a", "bin/pm-slam-app", "bin/pm-slam-eval", "lib/pmslam/libpmslam-viewer.so",
						  "include/pmslam/slam/KeyframeStore.h", "include/pmslam/util/RunStatistics.h",
						  "include/pmslam/sensor/ScanPoints.h", "include/pmslam/eval/RelativePoseEvaluation.h",
						  "include/pmslam/CMetricMapBuilderPM.h", "include/pmslam/MapExport.h",	 // old paths, forwarding
						  "share/pmslam/config/default.ini",
						  "share/pmslam/examples/external-project/CMakeLists.txt",
						  "share/pmslam/examples/replace-icp/main.cpp", "lib/cmake/pmslam/pmslamConfig.cmake",
						  "lib/cmake/pmslam/pmslamConfigVersion.cmake", "lib/cmake/pmslam/pmslamTargets.cmake"})
		EXPECT_TRUE(fs::exists(prefix / f)) << f << " not installed";
	// Every public header in its folder, and every old path as a forwarding header; the private ones stay out.
	const fs::path lib = PMSLAM_SOURCE_DIR "/libpmslam";
	for (const auto& h : fs::recursive_directory_iterator(lib / "include/pmslam"))
	{
		if (!h.is_regular_file()) continue;
		EXPECT_TRUE(fs::exists(prefix / "include" / fs::relative(h.path(), lib / "include"))) << h.path() << " not installed";
	}
	std::size_t forwarders = 0;
	for (const auto& h : fs::directory_iterator(lib / "deprecated/pmslam"))
	{
		++forwarders;
		EXPECT_TRUE(fs::exists(prefix / "include/pmslam" / h.path().filename())) << h.path() << " not installed";
	}
	EXPECT_EQ(forwarders, 18u);
	for (const char* f : {"include/pmslam/io/RawlogProbe.h", "include/pmslam/io/TextParsing.h",
						  "include/pmslam/io/CarmenGeometry.h", "include/pmslam/RawlogProbe.h"})
		EXPECT_FALSE(fs::exists(prefix / f)) << f << " is private but installed";
	// The package refers to the prefix, never to the source or build tree.
	for (const char* f : {"lib/cmake/pmslam/pmslamConfig.cmake", "lib/cmake/pmslam/pmslamTargets.cmake"})
	{
		const std::string text = pmslam::testing::readText(prefix / f);
		EXPECT_EQ(text.find(PMSLAM_SOURCE_DIR "/"), std::string::npos) << f << " mentions the source tree";
		EXPECT_EQ(text.find(PMSLAM_BINARY_DIR "/"), std::string::npos) << f << " mentions the build tree";
	}
	EXPECT_NE(pmslam::testing::readText(prefix / "lib/cmake/pmslam/pmslamTargets.cmake").find("pmslam::pmslam"),
			  std::string::npos);
	r = run(quote((prefix / "bin/pm-slam-app").string()) + " --help");
	EXPECT_EQ(r.exitCode, 0) << r.output;

	// The external project, configured against the prefix alone.
	const fs::path build = scratch.dir / "build";
	r = run(quote(kCMake) + " -S " + quote(PMSLAM_SOURCE_DIR "/share/examples/external-project") + " -B " +
			quote(build.string()) + " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + quote(prefix.string()) +
			" -DCMAKE_CXX_COMPILER=" + quote(PMSLAM_CXX_COMPILER) + " -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const std::string cache = pmslam::testing::readText(build / "CMakeCache.txt");
	EXPECT_NE(cache.find("pmslam_DIR:PATH=" + (prefix / "lib/cmake/pmslam").string()), std::string::npos)
		<< "find_package(pmslam) did not pick the installed package";
	r = run(quote(kCMake) + " --build " + quote(build.string()) + " -j2");
	ASSERT_EQ(r.exitCode, 0) << r.output;

	if (fs::exists(kSample))
	{
		r = run(quote((build / "map-a-rawlog").string()) + " " + quote(kSample) + " " +
				quote((scratch.dir / "map.gridmap.gz").string()));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		EXPECT_NE(r.output.find("scans 224, matched"), std::string::npos) << r.output;
		EXPECT_GT(fs::file_size(scratch.dir / "map.gridmap.gz"), 1000u);
	}
	else
	{
		r = run(quote((build / "map-a-rawlog").string()) + " /nonexistent.rawlog");
		EXPECT_EQ(r.exitCode, 1) << r.output;
	}

	// The old include paths (deprecated since 0.2) still compile against the prefix, without a warning.
	const fs::path oldPaths = scratch.dir / "old-include-paths";
	r = run(quote(kCMake) + " -S " + quote(PMSLAM_SOURCE_DIR "/tests/apps/old-include-paths") + " -B " +
			quote(oldPaths.string()) + " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + quote(prefix.string()) +
			" -DCMAKE_CXX_COMPILER=" + quote(PMSLAM_CXX_COMPILER) + " -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	r = run(quote(kCMake) + " --build " + quote(oldPaths.string()));
	EXPECT_EQ(r.exitCode, 0) << r.output;

	std::cout << "install + external project configure/build/run: "
			  << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
}

TEST(Install, ReadmeSnippetIsTheExternalProjectProgram)
{
	// README.md "Using pmslam from your code" shows share/examples/external-project/main.cpp, which
	// the test above compiles against the installed package: the two must not drift apart.
	const std::string readme = pmslam::testing::readText(PMSLAM_SOURCE_DIR "/README.md");
	const std::size_t section = readme.find("## Using pmslam from your code");
	ASSERT_NE(section, std::string::npos);
	const std::size_t begin = readme.find("```cpp\n", section);
	ASSERT_NE(begin, std::string::npos);
	const std::size_t end = readme.find("```\n", begin + 7);
	ASSERT_NE(end, std::string::npos);
	EXPECT_EQ(readme.substr(begin + 7, end - begin - 7),
			  pmslam::testing::readText(PMSLAM_SOURCE_DIR "/share/examples/external-project/main.cpp"));
	const std::string cmake = pmslam::testing::readText(PMSLAM_SOURCE_DIR "/share/examples/external-project/CMakeLists.txt");
	for (const char* line : {"find_package(pmslam 0.1 REQUIRED)", "target_link_libraries(map-a-rawlog PRIVATE pmslam::pmslam)"})
	{
		EXPECT_NE(readme.find(line, section), std::string::npos) << line;
		EXPECT_NE(cmake.find(line), std::string::npos) << line;
	}
}
