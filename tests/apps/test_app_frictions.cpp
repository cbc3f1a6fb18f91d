// The frictions a newcomer met with the programs of apps/, each fixed and kept fixed: an option's value after
// '=' (--initial-pose=0.19,0.57,0 was "unknown option"), the --out folder (an empty one left behind by a refused
// run; an earlier run's graph.graph beside a new --localize trajectory), and one prefix per message
// ("pm-slam-app: pmslam: ..."). The --gui window that closed at once is tests/apps/test_gui.cpp's.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <pmslam/io/MapExport.h>

#include <algorithm>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;

namespace
{
const std::string kBin = PMSLAM_BINARY_DIR "/bin/";
const std::string kIcpConfig = PMSLAM_SOURCE_DIR "/config/icp-slam-tuned.ini";

RunResult program(const std::string& name, const std::string& args) { return run(quote(kBin + name) + " " + args); }
RunResult app(const std::string& args) { return program("pm-slam-app", "--no-progress " + args); }

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

/** A small valid Carmen log of the furnished room (FLASER lines, odometry = truth). */
std::string roomCarmen(std::size_t n)
{
	const auto truth = roomPath(n);
	return carmenLog(furnishedRoom(), truth, truth, CarmenLogSpec{});
}

std::vector<std::string> linesWith(const std::string& text, const std::string& what)
{
	std::vector<std::string> found;
	std::istringstream in(text);
	for (std::string l; std::getline(in, l);)
		if (contains(l, what)) found.push_back(l);
	return found;
}
}  // namespace

// ---------------------------------------------------------------- --opt=value

TEST(OptionValues, PmSlamAppTakesEveryValueAfterAnEqualsSignToo)
{
	ScratchDir d("friction-equals");
	const auto log = d.write("room.clf", roomCarmen(60));
	const auto r = app("--out=" + quote(d.path("slam")) + " --max-scans=40 --set=Log.odometrySource=auto " + quote(log));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	EXPECT_EQ(countDataLines(d.dir / "slam" / "trajectory.txt"), 40u);
	// The newcomer's command: localising on that map, the start pose given with '='.
	const auto loc = app("--localize=" + quote(d.path("slam/map.gridmap.gz")) + " --initial-pose=0.19,0.57,0 --out=" +
						 quote(d.path("loc")) + " " + quote(log));
	ASSERT_EQ(loc.exitCode, 0) << loc.output;
	EXPECT_TRUE(contains(loc.output, "localised on")) << loc.output;
	EXPECT_EQ(countDataLines(d.dir / "loc" / "trajectory.txt"), 60u);
	// A bad value is named as the option's, and an option without a value takes none.
	const auto bad = app("--max-scans=many " + quote(log));
	EXPECT_EQ(bad.exitCode, 2);
	EXPECT_TRUE(contains(bad.output, "--max-scans 'many': expected a whole number")) << bad.output;
	const auto flag = app("--quiet=1 " + quote(log));
	EXPECT_EQ(flag.exitCode, 2);
	EXPECT_TRUE(contains(flag.output, "unknown option '--quiet=1'")) << flag.output;
}

TEST(OptionValues, TheOtherAppsTakeThemAfterAnEqualsSignToo)
{
	ScratchDir d("friction-equals-apps");
	const auto log = d.write("room.clf", roomCarmen(120));
	const auto fault = program("pm-fault-inject", "--fault=dropout --count=1 --scans=10 --seed=3 " + quote(log) + " " +
													  quote(d.path("faulted.clf")));
	ASSERT_EQ(fault.exitCode, 0) << fault.output;
	EXPECT_TRUE(contains(fault.output, "fault dropout at")) << fault.output;
	EXPECT_EQ(countDataLines(d.dir / "faulted.clf"), countDataLines(log) - 10);

	const auto icp = program("pm-icp-slam", "--config=" + quote(kIcpConfig) + " --out=" + quote(d.path("icp")) +
												" --max-scans=30 --quiet " + quote(log));
	ASSERT_EQ(icp.exitCode, 0) << icp.output;
	EXPECT_EQ(countDataLines(d.dir / "icp" / "trajectory.txt"), 30u);

	// pm-relation-check reads --max-dt=-1 as the option (and refuses the value), not as a file name.
	const auto rel = program("pm-relation-check", "--max-dt=-1 " + quote(log) + " " + quote(log));
	EXPECT_EQ(rel.exitCode, 2);
	EXPECT_TRUE(contains(rel.output, "usage: pm-relation-check")) << rel.output;
}

// ---------------------------------------------------------------- the --out folder

TEST(OutFolder, ARunRefusedBeforeWritingAnythingLeavesNoFolderItCreatedBehind)
{
	ScratchDir d("friction-out-refused");
	// The log opens, but holds no scan: found only once it was read, after --out was checked.
	const auto noScans = d.write("notes.clf", "hello\nPARAM only\n");
	const auto r = app("--out " + quote(d.path("new/out")) + " " + quote(noScans));
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_TRUE(contains(r.output, "no laser scan")) << r.output;
	EXPECT_FALSE(fs::exists(d.dir / "new")) << "the folders pm-slam-app created must go again";
	// A prior map without any obstacle: refused once loaded, after --out was checked.
	mrpt::maps::COccupancyGridMap2D blank(-5, 5, -5, 5, 0.05);
	pmslam::saveGridMapGz(blank, d.path("blank.gridmap.gz"));
	const auto log = d.write("room.clf", roomCarmen(20));
	const auto loc = app("--localize " + quote(d.path("blank.gridmap.gz")) + " --out " + quote(d.path("loc")) + " " + quote(log));
	EXPECT_EQ(loc.exitCode, 2) << loc.output;
	EXPECT_FALSE(fs::exists(d.dir / "loc"));
	// A folder that was there before stays, even when empty.
	fs::create_directories(d.dir / "mine");
	EXPECT_EQ(app("--out " + quote(d.path("mine")) + " " + quote(noScans)).exitCode, 2);
	EXPECT_TRUE(fs::is_directory(d.dir / "mine"));
}

TEST(OutFolder, AnEarlierRunsOutputsThisRunDoesNotWriteAreRemovedAndNamed)
{
	ScratchDir d("friction-out-stale");
	const auto log = d.write("room.clf", roomCarmen(60));
	const fs::path out = d.dir / "out";
	ASSERT_EQ(app("--quiet --out " + quote(out.string()) + " " + quote(log)).exitCode, 0);
	ASSERT_TRUE(fs::exists(out / "graph.graph"));  // loop closure is on by default
	ASSERT_TRUE(fs::exists(out / "trajectory_online.txt"));
	std::ofstream(out / "pose.txt") << "1000 0 0 0\n";	 // an earlier --snapshot-every run's
	std::ofstream(out / "notes.txt") << "the user's own\n";
	// Localising on that run's map, into the same folder: no graph, no online trajectory, no map of its own.
	const auto r = app("--quiet --localize " + quote((out / "map.gridmap.gz").string()) + " --out " + quote(out.string()) +
					   " " + quote(log));
	ASSERT_EQ(r.exitCode, 0) << r.output;
	for (const char* stale : {"graph.graph", "trajectory_online.txt", "map.pgm", "map.yaml", "map.simplemap.gz", "pose.txt"})
		EXPECT_FALSE(fs::exists(out / stale)) << stale;
	for (const char* kept : {"trajectory.txt", "timing.txt", "map.png", "notes.txt"}) EXPECT_TRUE(fs::exists(out / kept)) << kept;
	EXPECT_TRUE(fs::exists(out / "map.gridmap.gz")) << "the map this run localised on is never removed";
	// Said in one line naming them.
	const auto said = linesWith(r.output, "removed from");
	ASSERT_EQ(said.size(), 1u) << r.output;
	for (const char* stale : {"graph.graph", "trajectory_online.txt", "map.simplemap.gz", "pose.txt"})
		EXPECT_TRUE(contains(said[0], stale)) << said[0];
	EXPECT_FALSE(contains(said[0], "notes.txt"));
	// A run that writes everything again removes nothing and says nothing.
	const auto again = app("--quiet --out " + quote(out.string()) + " " + quote(log));
	ASSERT_EQ(again.exitCode, 0) << again.output;
	EXPECT_FALSE(contains(again.output, "removed from")) << again.output;
}

// ---------------------------------------------------------------- one prefix per message

TEST(Messages, ALibraryMessageCarriesTheProgramsPrefixOnly)
{
	ScratchDir d("friction-prefix");
	const std::string missing = d.path("no-such-log.clf");
	const auto slam = app("--out " + quote(d.path("out")) + " " + quote(missing));
	EXPECT_EQ(slam.exitCode, 2);
	EXPECT_EQ(slam.output.rfind("pm-slam-app: log file '" + missing + "' does not exist", 0), 0u) << slam.output;
	const auto icp = program("pm-icp-slam", "--config " + quote(kIcpConfig) + " --out " + quote(d.path("icp")) + " " + quote(missing));
	EXPECT_EQ(icp.exitCode, 2);
	EXPECT_EQ(icp.output.rfind("pm-icp-slam: log file '" + missing + "' does not exist", 0), 0u) << icp.output;
	EXPECT_FALSE(fs::exists(d.dir / "icp")) << "the log is checked before --out is created";
	const auto rel = program("pm-relation-check", quote(missing) + " " + quote(missing));
	EXPECT_EQ(rel.exitCode, 2);
	for (const auto* r : {&slam, &icp, &rel}) EXPECT_FALSE(contains(r->output, "pmslam:")) << r->output;
}
