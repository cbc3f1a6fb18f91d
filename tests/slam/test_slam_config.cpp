// SlamConfig: the documented defaults, overrides, and clear errors for bad keys and values.
#include <gtest/gtest.h>
#include <pmslam/slam/SlamConfig.h>

#include <fstream>
#include <sstream>

using pmslam::ConfigError;
using pmslam::parseSlamConfig;

namespace
{
std::string errorOf(const std::string& ini, const std::vector<std::string>& sets = {})
{
	try
	{
		parseSlamConfig(ini, "test.ini", sets);
	}
	catch (const ConfigError& e)
	{
		return e.what();
	}
	return "";
}
}  // namespace

TEST(SlamConfig, DefaultIniDocumentsEveryKeyWithItsDefault)
{
	std::ifstream in(PMSLAM_SOURCE_DIR "/config/default.ini");
	ASSERT_TRUE(in) << "config/default.ini missing";
	std::stringstream ss;
	ss << in.rdbuf();
	const std::string text = ss.str();
	// Every valid key appears in the documented file...
	for (const auto& key : pmslam::knownConfigKeys())
	{
		const std::string name = key.substr(key.find('.') + 1);
		EXPECT_NE(text.find("\n" + name + " = "), std::string::npos) << key << " is not documented in default.ini";
	}
	// ...and the file's values are the built-in defaults.
	const auto fromFile = parseSlamConfig(text, "default.ini");
	const auto builtIn = parseSlamConfig("", "defaults");
	std::ostringstream a, b;
	fromFile.matcher.dumpToTextStream(a);
	fromFile.mapping.dumpToTextStream(a);
	builtIn.matcher.dumpToTextStream(b);
	builtIn.mapping.dumpToTextStream(b);
	EXPECT_EQ(a.str(), b.str());
	EXPECT_EQ(fromFile.log.noReturnRange, builtIn.log.noReturnRange);
}

TEST(SlamConfig, OverridesApply)
{
	const auto c = parseSlamConfig("[PerfectMatch]\nsigma = 0.1\n", "t.ini",
								   {"PerfectMatch.sigma=0.2", "MappingApplication.insertionAngDistance_deg=10",
									"PerfectMatch.optimizer=GaussNewton", "Log.odometrySource=events"});
	EXPECT_DOUBLE_EQ(c.matcher.sigma, 0.2);
	EXPECT_NEAR(c.mapping.insertionAngDistance, 10 * M_PI / 180, 1e-12);
	EXPECT_EQ(c.matcher.optimizer, pmslam::PerfectMatchMatcher::Optimizer::GaussNewton);
	EXPECT_EQ(c.odometrySource, pmslam::OdometrySource::Events);
}

TEST(SlamConfig, UnknownKeyIsNamedWithASuggestion)
{
	const auto e = errorOf("[PerfectMatch]\nsigmma = 0.1\n");
	EXPECT_NE(e.find("unknown key 'sigmma'"), std::string::npos) << e;
	EXPECT_NE(e.find("did you mean 'sigma'"), std::string::npos) << e;
	EXPECT_NE(e.find("test.ini"), std::string::npos) << e;
}

TEST(SlamConfig, UnknownSectionIsNamedWithASuggestion)
{
	const auto e = errorOf("[PerfectMach]\nsigma = 0.1\n");
	EXPECT_NE(e.find("unknown section [PerfectMach]"), std::string::npos) << e;
	EXPECT_NE(e.find("[PerfectMatch]"), std::string::npos) << e;
}

TEST(SlamConfig, WrongTypeAndOutOfRangeValuesAreRejected)
{
	auto e = errorOf("[PerfectMatch]\nsigma = abc\n");
	EXPECT_NE(e.find("sigma = 'abc': expected a number"), std::string::npos) << e;
	e = errorOf("[PerfectMatch]\nmaxIterations = 2.5\n");
	EXPECT_NE(e.find("expected a whole number"), std::string::npos) << e;
	e = errorOf("[PerfectMatch]\nsigma = -1\n");
	EXPECT_NE(e.find("sigma"), std::string::npos) << e;
	EXPECT_NE(e.find("expected a value in"), std::string::npos) << e;
	e = errorOf("[PerfectMatch]\noptimizer = Newton\n");
	EXPECT_NE(e.find("expected one of RPROP, GaussNewton, LevenbergMarquardt"), std::string::npos) << e;
	e = errorOf("[MappingApplication]\nhitProbability = 0.3\n");
	EXPECT_NE(e.find("hitProbability"), std::string::npos) << e;
	e = errorOf("[MappingApplication]\nkeepSimpleMap = maybe\n");
	EXPECT_NE(e.find("expected true or false"), std::string::npos) << e;
	e = errorOf("[Log]\nodometrySource = wheels\n");
	EXPECT_NE(e.find("expected one of auto, scan, events"), std::string::npos) << e;
}

TEST(SlamConfig, MalformedOverrideAndMissingFile)
{
	EXPECT_NE(errorOf("", {"sigma=0.1"}).find("expected SECTION.KEY=VALUE"), std::string::npos);
	EXPECT_NE(errorOf("", {"PerfectMatch.sigmaa=0.1"}).find("did you mean 'sigma'"), std::string::npos);
	try
	{
		pmslam::loadSlamConfig("/nonexistent/pmslam.ini");
		FAIL() << "no error for a missing file";
	}
	catch (const ConfigError& e)
	{
		EXPECT_NE(std::string(e.what()).find("/nonexistent/pmslam.ini: cannot open"), std::string::npos) << e.what();
	}
}

// MRPT icp-slam files: read in pmslam's terms, what pmslam does not use named in a note.
TEST(SlamConfig, IcpSlamFileIsReadWithItsMeaning)
{
	const std::string ini = R"([ICP]
maxIterations    = 80    // ICP only
[MappingApplication]
rawlog_file=../../datasets/some.rawlog
rawlog_offset=0
logOutput_dir=LOG_ICP-SLAM
LOG_FREQUENCY=50			// display
SHOW_PROGRESS_3D_REAL_TIME=1
localizationLinDistance	= 0.2	// meters
localizationAngDistance	= 5	// degrees
insertionLinDistance	= 1.2
insertionAngDistance	= 45.0
minICPgoodnessToAccept	= 0.40
pointsMap_count=1
[MappingApplication_pointsMap_00_insertOpts]
minDistBetweenLaserPoints   = 0.05
[MappingApplication_occupancyGrid_00_creationOpts]
resolution = 0.1
)";
	const pmslam::SlamConfig c = parseSlamConfig(ini, "my-icp-slam.ini");
	EXPECT_NEAR(c.mapping.insertionLinDistance, 0.2, 1e-12);  // icp-slam's "localization" = when a scan is matched
	EXPECT_NEAR(c.mapping.insertionAngDistance, mrpt::DEG2RAD(5.0), 1e-12);
	EXPECT_NEAR(c.mapping.mapInsertLinDistance, 1.2, 1e-12);	// its "insertion" = when it goes into the map
	EXPECT_NEAR(c.mapping.mapInsertAngDistance, mrpt::DEG2RAD(45.0), 1e-12);
	EXPECT_NEAR(c.mapping.grid.resolution, 0.1, 1e-12);
	EXPECT_EQ(c.icpSlamLogFile, "../../datasets/some.rawlog");
	EXPECT_EQ(c.icpSlamOutputDir, "LOG_ICP-SLAM");
	ASSERT_EQ(c.notes.size(), 1u);
	for (const char* named : {"[ICP]", "[MappingApplication_pointsMap_00_insertOpts]", "LOG_FREQUENCY",
							  "minICPgoodnessToAccept", "localizationLinDistance as insertionLinDistance"})
		EXPECT_NE(c.notes[0].find(named), std::string::npos) << named << " not in: " << c.notes[0];
	// Untouched keys keep pmslam's defaults; --set uses pmslam's names.
	EXPECT_EQ(c.mapping.minGoodness, pmslam::MapBuilderOptions().minGoodness);
	const pmslam::SlamConfig o = parseSlamConfig(ini, "my-icp-slam.ini", {"MappingApplication.insertionLinDistance=0.05"});
	EXPECT_NEAR(o.mapping.insertionLinDistance, 0.05, 1e-12);
	// A pmslam file is not taken for one.
	EXPECT_TRUE(parseSlamConfig("[MappingApplication]\ninsertionLinDistance = 0.3\n", "p.ini").notes.empty());
	EXPECT_NEAR(parseSlamConfig("[MappingApplication]\ninsertionLinDistance = 0.3\n", "p.ini").mapping.insertionLinDistance, 0.3, 1e-12);
}

TEST(SlamConfig, IcpSlamFileWithWhatPmslamCannotHonourIsAnError)
{
	const std::string both = errorOf("[ICP]\n[MappingApplication]\nlocalizationAngDistance = 5\ninsertionAngDistance_deg = 2\n");
	EXPECT_NE(both.find("localizationAngDistance"), std::string::npos) << both;
	EXPECT_NE(both.find("insertionAngDistance_deg"), std::string::npos) << both;
	const std::string offset = errorOf("[ICP]\n[MappingApplication]\nrawlog_offset = 10\n");
	EXPECT_NE(offset.find("rawlog_offset"), std::string::npos) << offset;
	EXPECT_NE(offset.find("whole log"), std::string::npos) << offset;
	// A typo is still named with a suggestion.
	const std::string typo = errorOf("[ICP]\n[MappingApplication]\nminGodness = 0.5\n");
	EXPECT_NE(typo.find("minGodness"), std::string::npos) << typo;
	EXPECT_NE(typo.find("minGoodness"), std::string::npos) << typo;
}

// MRPT's own demo file, as installed (mrpt-apps): parses, and names MRPT's sample log.
TEST(SlamConfig, MrptIcpSlamDemoFileParses)
{
	const std::string path = "/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini";
	if (!std::ifstream(path)) GTEST_SKIP() << path << " not installed (package mrpt-apps)";
	const pmslam::SlamConfig c = pmslam::loadSlamConfig(path);
	EXPECT_NE(c.icpSlamLogFile.find("one_loop_only.rawlog"), std::string::npos);
	EXPECT_FALSE(c.notes.empty());
}
