// SlamConfig: the documented defaults, overrides, and clear errors for bad keys and values.
#include <gtest/gtest.h>
#include <pmslam/slam/SlamConfig.h>

#include <cmath>
#include <fstream>
#include <map>
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

std::string readFile(const std::string& path)
{
	std::ifstream in(path);
	std::stringstream ss;
	ss << in.rdbuf();
	return ss.str();
}

// config/default.ini and docs/configuration.md are what the key descriptors make: neither can drift
// from the code (after changing a key: build/bin/pm-slam-config > config/default.ini and
// build/bin/pm-slam-config --markdown > docs/configuration.md).
TEST(SlamConfig, CommittedFilesAreWhatTheDescriptorsMake)
{
	const auto defaults = parseSlamConfig("", "defaults");
	EXPECT_EQ(readFile(PMSLAM_SOURCE_DIR "/config/default.ini"), pmslam::configAsIni(defaults, false))
		<< "config/default.ini is stale: build/bin/pm-slam-config > config/default.ini";
	EXPECT_EQ(readFile(PMSLAM_SOURCE_DIR "/docs/configuration.md"), pmslam::configAsMarkdown())
		<< "docs/configuration.md is stale: build/bin/pm-slam-config --markdown > docs/configuration.md";
	// default.ini holds the basic keys only, few enough to read; loading it changes nothing.
	const std::string ini = readFile(PMSLAM_SOURCE_DIR "/config/default.ini");
	std::size_t keys = 0;
	std::istringstream lines(ini);
	for (std::string l; std::getline(lines, l);) keys += !l.empty() && l[0] != ';' && l[0] != '[';
	EXPECT_GE(keys, 10u);
	EXPECT_LE(keys, 25u);
	EXPECT_EQ(pmslam::configAsIni(parseSlamConfig(ini, "default.ini"), true), pmslam::configAsIni(defaults, true));
	// Every key is documented, each once.
	const std::string md = pmslam::configAsMarkdown();
	for (const auto& k : pmslam::configKeys())
		EXPECT_NE(md.find("| `" + k.key.name + "`"), std::string::npos) << k.section << "." << k.key.name;
}

namespace
{
/** A valid value for `k` other than `now`, and one out of its range (empty when it has no bound). */
std::vector<std::string> otherValues(const pmslam::ConfigKey& k, const std::string& now)
{
	using pmslam::config::Kind;
	if (k.key.kind == Kind::Bool) return {now == "true" ? "false" : "true"};
	if (k.key.kind == Kind::Word)
	{
		std::vector<std::string> out;
		for (const auto& w : k.key.words)
			if (w != now) out.push_back(w);
		return out;
	}
	const double v = std::stod(now), lo = k.key.range.lo, hi = k.key.range.hi;
	std::vector<double> tries = {v * 1.5, v + 1, v * 0.5, v - 1, (lo + hi) / 2, lo + 1, hi - 1, 0.3, 1, 2};
	std::vector<std::string> out;
	for (double t : tries)
	{
		if (k.key.kind == Kind::Integer) t = std::round(t);
		if (!std::isfinite(t) || t == v || !k.key.range.contains(t) || (k.key.kind == Kind::Integer && t < 0)) continue;
		std::ostringstream ss;
		ss.precision(12);
		ss << t;
		out.push_back(ss.str());
	}
	return out;
}

std::map<std::string, std::string> valuesOf(const std::string& ini)
{
	std::map<std::string, std::string> out;
	std::string section;
	std::istringstream lines(ini);
	for (std::string l; std::getline(lines, l);)
	{
		if (l.empty() || l[0] == ';') continue;
		if (l[0] == '[')
			section = l.substr(1, l.size() - 2);
		else
			out[section + "." + l.substr(0, l.find(" = "))] = l.substr(l.find(" = ") + 3);
	}
	return out;
}
}  // namespace

// Each key reaches its own field: set to another valid value, exactly its own line of the dump
// changes (two keys sharing a field, or a key writing the wrong one, change two); the dump reads back
// as the same configuration; a value past either bound is refused naming the key.
TEST(SlamConfig, EveryKeyGoesWhereItSaysAndKeepsItsRange)
{
	const auto base = valuesOf(pmslam::configAsIni(parseSlamConfig("", "defaults"), true));
	ASSERT_EQ(base.size(), pmslam::configKeys().size());
	for (const auto& k : pmslam::configKeys())
	{
		const std::string id = k.section + "." + k.key.name;
		bool applied = false;
		for (const auto& value : otherValues(k, base.at(id)))
		{
			pmslam::SlamConfig c;
			try
			{
				c = parseSlamConfig("", "t", {id + "=" + value});
			}
			catch (const ConfigError&)
			{
				continue;  // a value another key must agree with (searchRadius <= maxSearchRadius): try the next
			}
			const std::string dumped = pmslam::configAsIni(c, true);
			const auto now = valuesOf(dumped);
			for (const auto& [name, v] : now)
			{
				if (name != id)
				{
					EXPECT_EQ(v, base.at(name)) << "setting " << id << " changed " << name;
				}
			}
			EXPECT_NE(now.at(id), base.at(id)) << id;
			const bool numeric = k.key.kind == pmslam::config::Kind::Number || k.key.kind == pmslam::config::Kind::Integer;
			if (numeric)
				EXPECT_NEAR(std::stod(now.at(id)), std::stod(value), 1e-9 * (1 + std::abs(std::stod(value)))) << id;
			else
				EXPECT_EQ(now.at(id), value) << id;
			EXPECT_EQ(pmslam::configAsIni(parseSlamConfig(dumped, "dump"), true), dumped) << id;
			applied = true;
			break;
		}
		EXPECT_TRUE(applied) << "no other valid value found for " << id;
		for (const double bound : {k.key.range.lo, k.key.range.hi})
		{
			if (!std::isfinite(bound) || k.key.kind == pmslam::config::Kind::Bool) continue;
			const double outside = bound == k.key.range.lo ? bound - 1 : bound + 1;
			if (k.key.kind == pmslam::config::Kind::Integer && outside < 0) continue;  // "-1" is not a count at all
			std::ostringstream ss;
			ss << outside;
			const auto e = errorOf("", {id + "=" + ss.str()});
			EXPECT_NE(e.find(k.key.name), std::string::npos) << id << " = " << outside << ": " << e;
			EXPECT_NE(e.find("expected"), std::string::npos) << id << " = " << outside << ": " << e;
		}
	}
}

// The matching thresholds' old names (they said "insertion" and meant "when a scan is matched") still
// work, with a note; naming both is an error; a removed key is a note, not an error.
TEST(SlamConfig, OldNamesAndRemovedKeysStillLoad)
{
	const auto c = parseSlamConfig("[MappingApplication]\ninsertionLinDistance = 0.2\ninsertionAngDistance_deg = 4\n"
								   "matchAtLeastEvery = 0\n[PerfectMatch]\nrpropPatience = 5\n",
								   "old.ini");
	EXPECT_NEAR(c.mapping.matchLinDistance, 0.2, 1e-12);
	EXPECT_NEAR(c.mapping.matchAngDistance, mrpt::DEG2RAD(4.0), 1e-12);
	ASSERT_EQ(c.notes.size(), 2u);
	EXPECT_NE(c.notes[0].find("insertionLinDistance as matchLinDistance"), std::string::npos) << c.notes[0];
	EXPECT_NE(c.notes[1].find("matchAtLeastEvery"), std::string::npos) << c.notes[1];
	EXPECT_NE(c.notes[1].find("rpropPatience"), std::string::npos) << c.notes[1];
	const auto both = errorOf("[MappingApplication]\ninsertionLinDistance = 0.2\nmatchLinDistance = 0.1\n");
	EXPECT_NE(both.find("insertionLinDistance is the old name of matchLinDistance"), std::string::npos) << both;
	EXPECT_TRUE(parseSlamConfig("[MappingApplication]\nmatchLinDistance = 0.2\n", "new.ini").notes.empty());
}

// A key in the wrong section is named with the section it belongs to; a name with something
// inserted in its middle finds the key that has it (maxRange -> maxHitRange, not minRange).
TEST(SlamConfig, SuggestionsLookInEverySection)
{
	auto e = errorOf("[MappingApplication]\nsigma = 0.1\n");
	EXPECT_NE(e.find("did you mean 'PerfectMatch.sigma'"), std::string::npos) << e;
	e = errorOf("", {"MappingApplication.maxRange=30"});
	EXPECT_NE(e.find("did you mean 'maxHitRange'"), std::string::npos) << e;
	e = errorOf("", {"LoopClosure.enable=false"});
	EXPECT_NE(e.find("did you mean 'enabled'"), std::string::npos) << e;
	e = errorOf("", {"Log.odometrysource=scan"});
	EXPECT_NE(e.find("did you mean 'odometrySource'"), std::string::npos) << e;
}

TEST(SlamConfig, OverrideMayHaveBlanksAroundItsParts)
{
	const auto c = parseSlamConfig("", "t", {"PerfectMatch.sigma = 0.1", " LoopClosure . enabled=false "});
	EXPECT_DOUBLE_EQ(c.matcher.sigma, 0.1);
	EXPECT_FALSE(c.loopClosure.enabled);
}

TEST(SlamConfig, OverridesApply)
{
	const auto c = parseSlamConfig("[PerfectMatch]\nsigma = 0.1\n", "t.ini",
								   {"PerfectMatch.sigma=0.2", "MappingApplication.matchAngDistance_deg=10",
									"PerfectMatch.optimizer=GaussNewton", "Log.odometrySource=events"});
	EXPECT_DOUBLE_EQ(c.matcher.sigma, 0.2);
	EXPECT_NEAR(c.mapping.matchAngDistance, 10 * M_PI / 180, 1e-12);
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
	EXPECT_NEAR(c.mapping.matchLinDistance, 0.2, 1e-12);  // icp-slam's "localization" = when a scan is matched
	EXPECT_NEAR(c.mapping.matchAngDistance, mrpt::DEG2RAD(5.0), 1e-12);
	EXPECT_NEAR(c.mapping.mapInsertLinDistance, 1.2, 1e-12);	// its "insertion" = when it goes into the map
	EXPECT_NEAR(c.mapping.mapInsertAngDistance, mrpt::DEG2RAD(45.0), 1e-12);
	EXPECT_NEAR(c.mapping.grid.resolution, 0.1, 1e-12);
	EXPECT_EQ(c.icpSlamLogFile, "../../datasets/some.rawlog");
	EXPECT_EQ(c.icpSlamOutputDir, "LOG_ICP-SLAM");
	ASSERT_EQ(c.notes.size(), 1u);
	for (const char* named : {"[ICP]", "[MappingApplication_pointsMap_00_insertOpts]", "LOG_FREQUENCY",
							  "minICPgoodnessToAccept", "localizationLinDistance as matchLinDistance"})
		EXPECT_NE(c.notes[0].find(named), std::string::npos) << named << " not in: " << c.notes[0];
	// Untouched keys keep pmslam's defaults; --set uses pmslam's names.
	EXPECT_EQ(c.mapping.minGoodness, pmslam::MapBuilderOptions().minGoodness);
	const pmslam::SlamConfig o = parseSlamConfig(ini, "my-icp-slam.ini", {"MappingApplication.matchLinDistance=0.05"});
	EXPECT_NEAR(o.mapping.matchLinDistance, 0.05, 1e-12);
	// A pmslam file is not taken for one.
	EXPECT_TRUE(parseSlamConfig("[MappingApplication]\nmatchLinDistance = 0.3\n", "p.ini").notes.empty());
	EXPECT_NEAR(parseSlamConfig("[MappingApplication]\nmatchLinDistance = 0.3\n", "p.ini").mapping.matchLinDistance, 0.3, 1e-12);
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
