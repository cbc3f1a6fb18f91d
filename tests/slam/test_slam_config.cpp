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
