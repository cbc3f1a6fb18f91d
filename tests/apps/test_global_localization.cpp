// Localisation without a start pose: GlobalLocalizer (a whole-map branch-and-bound search, then the
// scans decide between the places that fit) and `pm-slam-app --localize MAP` without --initial-pose,
// on the maps users have (a pm-slam-app folder, map.yaml, a simple map).
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/PriorMap.h>
#include <pmslam/io/Trajectory.h>
#include <pmslam/slam/GlobalLocalizer.h>
#include <pmslam/slam/OdometrySelector.h>
#include <pmslam/slam/SlamConfig.h>

#include <cmath>
#include <filesystem>

#include "RunProgram.h"
#include "SyntheticLogs.h"
#include "lidar_emulator/LidarEmulator.h"

namespace fs = std::filesystem;
using pmslam::testing::quote;
using pmslam::testing::run;

namespace
{
const std::string kApp = PMSLAM_BINARY_DIR "/bin/pm-slam-app";
const std::string kSample = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

/** The SLAM run of MRPT's sample log, made once for all tests here: its output folder. */
const std::string& sampleMapFolder()
{
	static const std::string folder = [] {
		const std::string out = (fs::temp_directory_path() / ("pmslam-global-" + std::to_string(::getpid()))).string();
		const auto r = run(quote(kApp) + " --quiet --out " + quote(out) + " " + quote(kSample));
		EXPECT_EQ(r.exitCode, 0) << r.output;
		return out;
	}();
	return folder;
}

struct Scan
{
	pmslam::LogEvent event;
	std::optional<mrpt::math::TPose2D> odometry;
};

std::vector<Scan> sampleScans()
{
	auto reader = pmslam::LogReader::open(kSample);
	pmslam::OdometrySelector odo;
	std::vector<Scan> scans;
	for (pmslam::LogEvent ev; reader->next(ev);)
		if (ev.kind == pmslam::LogEvent::Kind::Odometry)
			odo.takeReading(ev);
		else
			scans.push_back({ev, odo.forScan(ev)});
	return scans;
}

class GlobalLocalization : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		if (!fs::exists(kSample)) GTEST_SKIP() << kSample << " not installed (comes with mrpt-common)";
	}
	static void TearDownTestSuite() { fs::remove_all(sampleMapFolder()); }
};
}  // namespace

// From starts spread over the whole log, the start is found where the SLAM run put that scan, from
// a map file alone (the scans of a robot switched on anywhere in the mapped building).
TEST_F(GlobalLocalization, FindsTheStartFromScansAnywhereOnTheLog)
{
	const auto map = pmslam::loadPriorMap(sampleMapFolder());
	const auto slam = pmslam::loadTrajectory(sampleMapFolder() + "/trajectory.txt");
	const auto scans = sampleScans();
	ASSERT_EQ(scans.size(), slam.size());
	const pmslam::SlamConfig cfg = pmslam::parseSlamConfig("", "defaults");
#ifdef PMSLAM_SANITIZE
	const std::size_t starts = 4;  // each start is a whole-map search: slow under the sanitizers
#else
	const std::size_t starts = 12;
#endif
	std::size_t found = 0;
	for (std::size_t k = 0; k < starts; ++k)
	{
		const std::size_t s0 = (scans.size() - 150) * k / starts;
		pmslam::GlobalLocalizer g(map.grid, cfg.matcher, cfg.mapping.grid.scan);
		for (std::size_t s = s0; s < scans.size() && g.state() == pmslam::GlobalLocalizer::State::Searching; ++s)
			g.addScan(*scans[s].event.scan, scans[s].odometry);
		ASSERT_EQ(g.state(), pmslam::GlobalLocalizer::State::Found) << "start scan " << s0;
		const auto p = g.best()->origin;
		const double d = std::hypot(p.x - slam[s0].x, p.y - slam[s0].y);
		const double yaw = std::abs(mrpt::math::wrapToPi(p.phi - slam[s0].yaw));
		EXPECT_LT(d, 0.3) << "start scan " << s0;
		EXPECT_LT(yaw, 5 * M_PI / 180) << "start scan " << s0;
		found += d < 0.3 && yaw < 5 * M_PI / 180;
	}
	EXPECT_EQ(found, starts);
}

// pm-slam-app --localize without --initial-pose, on the three forms of the same map: the trajectory is
// the SLAM run's, and the run says where it found the start.
TEST_F(GlobalLocalization, PmSlamAppLocalisesOnAFolderAYamlAndASimpleMapWithoutAStartPose)
{
	const auto slam = pmslam::loadTrajectory(sampleMapFolder() + "/trajectory.txt");
	pmslam::testing::ScratchDir dir("global-app");
	for (const std::string& map : std::vector<std::string>{sampleMapFolder(), sampleMapFolder() + "/map.yaml",
								  sampleMapFolder() + "/map.simplemap.gz"})
	{
		const std::string out = dir.path("loc");
		const auto r = run(quote(kApp) + " --localize " + quote(map) + " --out " + quote(out) + " " + quote(kSample));
		ASSERT_EQ(r.exitCode, 0) << map << "\n" << r.output;
		EXPECT_NE(r.output.find("global localisation: start found at"), std::string::npos) << r.output;
		EXPECT_NE(r.output.find("tracking: ok"), std::string::npos) << r.output;
		const auto loc = pmslam::loadTrajectory(out + "/trajectory.txt");
		ASSERT_EQ(loc.size(), slam.size()) << map;
		double sum = 0;
		for (std::size_t i = 0; i < slam.size(); ++i) sum += std::hypot(slam[i].x - loc[i].x, slam[i].y - loc[i].y);
		EXPECT_LT(sum / double(slam.size()), 0.1) << map;
	}
}

// --initial-pose is a hint: given one metres and tens of degrees wrong, the tracker loses the robot
// within seconds (its matches rejected, or crossing the map's walls), the whole map is searched as for
// an unknown start, and every scan, those reported while lost included, ends where the SLAM run had it.
// The run says it was found again and does not call its tracking "ok".
TEST_F(GlobalLocalization, PmSlamAppFindsTheRobotAgainFromAWrongStartPose)
{
	const auto slam = pmslam::loadTrajectory(sampleMapFolder() + "/trajectory.txt");
	pmslam::testing::ScratchDir dir("global-again");
	for (const std::string hint : {"2.5,1.5,120", "-1,0.5,-60"})
	{
		const std::string out = dir.path("loc");
		const auto r = run(quote(kApp) + " --localize " + quote(sampleMapFolder()) + " --initial-pose=" + hint +
						   " --out " + quote(out) + " " + quote(kSample));
		ASSERT_EQ(r.exitCode, 0) << hint << "\n" << r.output;
		EXPECT_NE(r.output.find("the robot found again 1 times"), std::string::npos) << r.output;
		EXPECT_NE(r.output.find("tracking: recovered"), std::string::npos) << r.output;
		const auto loc = pmslam::loadTrajectory(out + "/trajectory.txt");
		ASSERT_EQ(loc.size(), slam.size()) << hint;
		double worst = 0;
		for (std::size_t i = 0; i < slam.size(); ++i)
			worst = std::max(worst, std::hypot(slam[i].x - loc[i].x, slam[i].y - loc[i].y));
		EXPECT_LT(worst, 0.1) << hint;
	}
}

// A start pose the user gave is a hint, not a fact: the first scans are searched on the whole map too. Along a
// corridor a start metres off, turned round, finds a look-alike that fits every scan (the corridor seen the other
// way); tracked from there the run said "tracking: ok" 3-6 m off. Each wrong start here did so before the check
// (at 10 Hz too, where the robot placed right then jumped back: its velocity was still the one from the wrong
// start to the right place, D47).
TEST(GivenStartPose, IsCheckedOnTheWholeMap)
{
	pmslam::testing::ScratchDir dir("start-check");
	const auto world = pmslam::testing::corridorsWorld();
	const auto path = pmslam::testing::LoopPath::forWorld("corridors", 0.5);
	const auto log = [&](double dt) {	 // 9 s along a corridor, a 270-degree lidar alone
		std::vector<mrpt::math::TPose2D> truth;
		for (double t = 0; t < 9.0; t += dt) truth.push_back(path.at(0.5 * t));
		pmslam::testing::RawlogSpec spec;
		spec.beams = 1081, spec.aperture = 1.5 * M_PI, spec.odometry = false, spec.dt = dt;
		const std::string file = dir.path("corridor-" + std::to_string(int(1 / dt)) + "hz.rawlog");
		pmslam::testing::writeRawlog(file, world, truth, truth, spec);
		return file;
	};
	const std::string fast = log(0.025), slow = log(0.1), map = dir.path("map");
	auto r = run(quote(kApp) + " --quiet --out " + quote(map) + " " + quote(fast));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto mapped = pmslam::loadTrajectory(map + "/trajectory.txt");	// the truth, in the map's frame
	for (const std::string& scans : {fast, slow})
		for (const std::string hint : {"0,0,0", "4.4,0.4,-130", "2.2,2.5,130", "0.1,-1.8,-10"})
		{
			const std::string out = dir.path("loc");
			r = run(quote(kApp) + " --localize " + quote(map) + " --initial-pose=" + hint + " --out " + quote(out) +
					" " + quote(scans));
			ASSERT_EQ(r.exitCode, 0) << hint << "\n" << r.output;
			const bool right = hint == "0,0,0";
			EXPECT_NE(r.output.find(right ? "tracking: ok" : "tracking: recovered"), std::string::npos) << r.output;
			EXPECT_NE(r.output.find(right ? "found again 0 times" : "found again 1 times"), std::string::npos)
				<< r.output;
			const auto loc = pmslam::loadTrajectory(out + "/trajectory.txt");
			double worst = 0;
			for (const auto& p : loc)
				for (const auto& q : mapped)
					if (std::abs(p.timestamp - q.timestamp) < 1e-3) worst = std::max(worst, std::hypot(p.x - q.x, p.y - q.y));
			EXPECT_LT(worst, 0.1) << hint << " " << scans;
		}
}

// The scans are of another building: no place explains them, or none clearly. The run says so and
// exits 3; it never tracks from a guess or reports "tracking: ok".
TEST_F(GlobalLocalization, OnAMapOfAnotherBuildingItSaysSoAndTracksNothing)
{
	pmslam::testing::ScratchDir dir("global-wrong");
	// A map of a room the sample log never saw.
	const auto path = pmslam::testing::roomPath(120);
	const std::string roomLog =
		dir.write("room.clf", pmslam::testing::carmenLog(pmslam::testing::furnishedRoom(), path, path, {}));
	auto r = run(quote(kApp) + " --quiet --out " + quote(dir.path("room")) + " " + quote(roomLog));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	r = run(quote(kApp) + " --localize " + quote(dir.path("room")) + " --out " + quote(dir.path("loc")) + " " +
			quote(kSample));
	EXPECT_EQ(r.exitCode, 3) << r.output;
	EXPECT_TRUE(r.output.find("global localisation: UNDECIDED") != std::string::npos ||
				r.output.find("global localisation: NOT FOUND") != std::string::npos)
		<< r.output;
	EXPECT_EQ(r.output.find("tracking: ok"), std::string::npos) << r.output;
	EXPECT_FALSE(fs::exists(dir.path("loc") + "/trajectory.txt"));
}

// A map the program cannot read is one line naming it and what was expected.
TEST(PriorMap, UnreadableMapsAreOneLineErrors)
{
	pmslam::testing::ScratchDir dir("prior-map");
	for (const std::string& bad : {dir.path("none.yaml"), dir.dir.string(), dir.write("x.gridmap.gz", "garbage")})
	{
		try
		{
			pmslam::loadPriorMap(bad);
			ADD_FAILURE() << bad << " loaded";
		}
		catch (const pmslam::PriorMapError& e)
		{
			const std::string what = e.what();
			EXPECT_NE(what.find(bad), std::string::npos) << what;
			EXPECT_NE(what.find("expected"), std::string::npos) << what;
			EXPECT_EQ(what.find('\n'), std::string::npos) << what;
		}
	}
}
