/* pmslam — configuration loading and validation (see SlamConfig.h). */
#include <mrpt/config/CConfigFileMemory.h>
#include <pmslam/slam/SlamConfig.h>

#include "IcpSlamDialect.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pmslam
{
namespace
{
enum class Type
{
	Number,
	Integer,
	Bool,
	Word
};
struct Key
{
	const char* section;
	const char* name;
	Type type;
};
// The one list of valid keys: loading, validation and suggestions all use it.
const Key kKeys[] = {
	{"PerfectMatch", "optimizer", Type::Word},
	{"PerfectMatch", "robustKernel", Type::Word},
	{"PerfectMatch", "sigma", Type::Number},
	{"PerfectMatch", "maxIterations", Type::Integer},
	{"PerfectMatch", "rpropInitialStepXY", Type::Number},
	{"PerfectMatch", "rpropInitialStepPhi", Type::Number},
	{"PerfectMatch", "rpropIncrease", Type::Number},
	{"PerfectMatch", "rpropDecrease", Type::Number},
	{"PerfectMatch", "rpropMaxStepXY", Type::Number},
	{"PerfectMatch", "rpropMaxStepPhi", Type::Number},
	{"PerfectMatch", "rpropRefineIterations", Type::Integer},
	{"PerfectMatch", "rpropPatience", Type::Integer},
	{"PerfectMatch", "minStepXY", Type::Number},
	{"PerfectMatch", "minStepPhi", Type::Number},
	{"PerfectMatch", "decimation", Type::Integer},
	{"PerfectMatch", "maxDistance", Type::Number},
	{"PerfectMatch", "occupiedThreshold", Type::Number},
	{"PerfectMatch", "useInitialCovarianceAsPrior", Type::Bool},
	{"MappingApplication", "insertionLinDistance", Type::Number},
	{"MappingApplication", "insertionAngDistance_deg", Type::Number},
	{"MappingApplication", "minGoodness", Type::Number},
	{"MappingApplication", "mapInsertLinDistance", Type::Number},
	{"MappingApplication", "mapInsertAngDistance_deg", Type::Number},
	{"MappingApplication", "mapInsertBelowInliers", Type::Number},
	{"MappingApplication", "minPoints", Type::Integer},
	{"MappingApplication", "minOverlapGoodness", Type::Number},
	{"MappingApplication", "ignoreUnexploredPoints", Type::Bool},
	{"MappingApplication", "degenerateBelow", Type::Number},
	{"MappingApplication", "wideSearchBelowGoodness", Type::Number},
	{"MappingApplication", "wideSearchLinear", Type::Number},
	{"MappingApplication", "wideSearchAngular_deg", Type::Number},
	{"MappingApplication", "relocalizeAfterGap", Type::Number},
	{"MappingApplication", "relocalizeAfterJump", Type::Number},
	{"MappingApplication", "relocalizeSpeed", Type::Number},
	{"MappingApplication", "relocalizeTurnRate_deg", Type::Number},
	{"MappingApplication", "relocalizeMaxLinear", Type::Number},
	{"MappingApplication", "relocalizeOdometryError", Type::Number},
	{"MappingApplication", "relocalizeAmbiguity", Type::Number},
	{"MappingApplication", "newGroundUnexplored", Type::Number},
	{"MappingApplication", "newGroundAfter", Type::Number},
	{"MappingApplication", "matchAtLeastEvery", Type::Number},
	{"MappingApplication", "matchWhenScanChanged", Type::Number},
	{"MappingApplication", "odometryPriorSigmaXY", Type::Number},
	{"MappingApplication", "odometryPriorSigmaPhi_deg", Type::Number},
	{"MappingApplication", "odometryToScanTime", Type::Bool},
	{"MappingApplication", "odometrySmoothing", Type::Bool},
	{"MappingApplication", "odometrySmoothingLag", Type::Integer},
	{"MappingApplication", "scanLatency", Type::Number},
	{"MappingApplication", "keepSimpleMap", Type::Bool},
	{"MappingApplication", "resolution", Type::Number},
	{"MappingApplication", "maxDistance", Type::Number},
	{"MappingApplication", "hitProbability", Type::Number},
	{"MappingApplication", "missProbability", Type::Number},
	{"MappingApplication", "clampProbability", Type::Number},
	{"MappingApplication", "joinHitsCloserThan", Type::Number},
	{"MappingApplication", "freeCarveLength", Type::Number},
	{"MappingApplication", "freeCarveMarginBeforeHit", Type::Number},
	{"MappingApplication", "minRange", Type::Number},
	{"MappingApplication", "maxHitRange", Type::Number},
	{"MappingApplication", "noReturnCarveRange", Type::Number},
	{"LoopClosure", "enabled", Type::Bool},
	{"LoopClosure", "minTravel", Type::Number},
	{"LoopClosure", "searchRadius", Type::Number},
	{"LoopClosure", "searchRadiusPerMeter", Type::Number},
	{"LoopClosure", "maxSearchRadius", Type::Number},
	{"LoopClosure", "searchAngle_deg", Type::Number},
	{"LoopClosure", "searchAnglePerMeter_deg", Type::Number},
	{"LoopClosure", "maxSearchAngle_deg", Type::Number},
	{"LoopClosure", "detectEvery", Type::Number},
	{"LoopClosure", "localMapExtent", Type::Number},
	{"LoopClosure", "minGoodness", Type::Number},
	{"LoopClosure", "minInlierFraction", Type::Number},
	{"LoopClosure", "ambiguityMargin", Type::Number},
	{"LoopClosure", "maxUnexploredFraction", Type::Number},
	{"LoopClosure", "maxInFreeSpace", Type::Number},
	{"LoopClosure", "agreeingMatches", Type::Integer},
	{"LoopClosure", "agreeWindow", Type::Number},
	{"LoopClosure", "agreeLinear", Type::Number},
	{"LoopClosure", "agreeAngular_deg", Type::Number},
	{"LoopClosure", "informationScale", Type::Number},
	{"LoopClosure", "odometrySigmaLinear", Type::Number},
	{"LoopClosure", "odometrySigmaPerMeter", Type::Number},
	{"LoopClosure", "odometrySigmaAngular_deg", Type::Number},
	{"LoopClosure", "odometrySigmaPerRadian", Type::Number},
	{"LoopClosure", "optimizeEvery", Type::Integer},
	{"LoopClosure", "rebuildAbove", Type::Number},
	{"LoopClosure", "reinsertAbove", Type::Number},
	{"LoopClosure", "revisitMinOverlap", Type::Number},
	{"LoopClosure", "revisitBelowTypical", Type::Number},
	{"LoopClosure", "background", Type::Bool},
	{"Log", "noReturnRange", Type::Number},
	{"Log", "odometrySource", Type::Word},
	{"Log", "sliceMinHeight", Type::Number},
	{"Log", "sliceMaxHeight", Type::Number},
	{"Log", "sliceResolution_deg", Type::Number},
	{"Log", "sliceMaxRange", Type::Number},
};

std::size_t editDistance(const std::string& a, const std::string& b)
{
	std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
	for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
	for (std::size_t i = 1; i <= a.size(); ++i)
	{
		cur[0] = i;
		for (std::size_t j = 1; j <= b.size(); ++j)
			cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1,
							   prev[j - 1] + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
		std::swap(prev, cur);
	}
	return prev[b.size()];
}

std::string closest(const std::string& word, const std::vector<std::string>& candidates)
{
	// A candidate the word is an abbreviation of ("Mapping" -> "MappingApplication") wins;
	// otherwise the smallest edit distance.
	const auto lowerCase = [](std::string s) {
		std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
		return s;
	};
	if (word.size() >= 3)
		for (const auto& c : candidates)
			if (lowerCase(c).rfind(lowerCase(word), 0) == 0) return c;
	std::string best;
	std::size_t bestD = std::string::npos;
	for (const auto& c : candidates)
		if (const auto d = editDistance(word, c); d < bestD) bestD = d, best = c;
	return best;
}

using detail::trimBlanks;

bool isNumber(const std::string& v, bool integer)
{
	if (v.empty()) return false;
	if (integer)
	{  // counts: plain digits (MRPT's read_int would read "1e3" as 1 and "-5" as a huge unsigned)
		if (v.size() > 9 || v.find_first_not_of("0123456789") != std::string::npos) return false;
		return true;
	}
	char* end = nullptr;
	const double d = std::strtod(v.c_str(), &end);
	if (end == v.c_str() || *end != '\0') return false;
	if (!std::isfinite(d)) return false;
	return !integer || d == std::floor(d);
}

bool isBool(const std::string& v)
{
	std::string l = v;
	std::transform(l.begin(), l.end(), l.begin(), [](unsigned char c) { return std::tolower(c); });
	return l == "true" || l == "false" || l == "1" || l == "0" || l == "yes" || l == "no";
}

const char* describe(Type t)
{
	switch (t)
	{
		case Type::Number: return "a number";
		case Type::Integer: return "a whole number >= 0";
		case Type::Bool: return "true or false";
		case Type::Word: return "a word";
	}
	return "?";
}

void validate(const mrpt::config::CConfigFileBase& cfg, const std::string& source)
{
	std::vector<std::string> sections, knownSections;
	cfg.getAllSections(sections);
	for (const auto& k : kKeys)
		if (std::find(knownSections.begin(), knownSections.end(), k.section) == knownSections.end())
			knownSections.push_back(k.section);
	for (const auto& sec : sections)
	{
		if (sec.empty()) continue;
		if (std::find(knownSections.begin(), knownSections.end(), sec) == knownSections.end())
			throw ConfigError(source + ": unknown section [" + sec + "] (did you mean [" + closest(sec, knownSections) +
							  "]?)");
		std::vector<std::string> keys, valid;
		cfg.getAllKeys(sec, keys);
		for (const auto& k : kKeys)
			if (sec == k.section) valid.push_back(k.name);
		for (const auto& key : keys)
		{
			const Key* spec = nullptr;
			for (const auto& k : kKeys)
				if (sec == k.section && key == k.name) spec = &k;
			if (!spec)
				throw ConfigError(source + ": unknown key '" + key + "' in [" + sec + "] (did you mean '" +
								  closest(key, valid) + "'?)");
			const std::string v = trimBlanks(cfg.read_string(sec, key, ""));
			const bool ok = spec->type == Type::Number	  ? isNumber(v, false)
							: spec->type == Type::Integer ? isNumber(v, true)
							: spec->type == Type::Bool	  ? isBool(v)
														  : !v.empty();
			if (!ok)
				throw ConfigError(source + ": [" + sec + "] " + key + " = '" + v + "': expected " +
								  describe(spec->type));
		}
	}
}

OdometrySource parseOdometrySource(const std::string& v, const std::string& source)
{
	if (v == "auto") return OdometrySource::Auto;
	if (v == "scan") return OdometrySource::Scan;
	if (v == "events") return OdometrySource::Events;
	throw ConfigError(source + ": [Log] odometrySource = '" + v + "': expected one of auto, scan, events");
}
}  // namespace

std::vector<std::string> knownConfigKeys()
{
	std::vector<std::string> out;
	for (const auto& k : kKeys) out.push_back(std::string(k.section) + "." + k.name);
	return out;
}

namespace
{
/** One line out of a (possibly multi-line) exception message. */
std::string oneLine(const std::string& what)
{
	std::string s;
	for (char ch : what) s += (ch == '\n' || ch == '\r') ? ' ' : ch;
	s = trimBlanks(s);
	if (s.size() > 200) s = s.substr(0, 197) + "...";
	return s;
}

SlamConfig parseChecked(const std::string& iniText, const std::string& sourceName,
						const std::vector<std::string>& overrides)
{
	SlamConfig c;
	std::string text = iniText;
	{
		// An MRPT icp-slam file: read in pmslam's terms (the overrides then use pmslam's names).
		const mrpt::config::CConfigFileMemory original(iniText);
		if (detail::isIcpSlamConfig(original))
		{
			detail::IcpSlamTranslation t;
			text = detail::translateIcpSlamConfig(original, sourceName, t);
			c.icpSlamLogFile = t.logFile;
			c.icpSlamOutputDir = t.outputDir;
			c.notes.push_back(t.note);
		}
	}
	mrpt::config::CConfigFileMemory cfg(text);
	for (const auto& o : overrides)
	{
		const auto eq = o.find('='), dot = o.find('.');
		if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq)
			throw ConfigError("--set '" + o + "': expected SECTION.KEY=VALUE, e.g. PerfectMatch.sigma=0.05");
		cfg.write(o.substr(0, dot), o.substr(dot + 1, eq - dot - 1), o.substr(eq + 1));
	}
	const std::string where = overrides.empty() ? sourceName : sourceName + " (with --set overrides)";
	validate(cfg, where);
	try
	{
		c.matcher.loadFromConfigFile(cfg, "PerfectMatch");
		c.mapping.loadFromConfigFile(cfg, "MappingApplication");
		c.loopClosure.loadFromConfigFile(cfg, "LoopClosure");
		c.log.noReturnRange = cfg.read_double("Log", "noReturnRange", c.log.noReturnRange);
		if (!(c.log.noReturnRange > 0)) throw std::invalid_argument("[Log] noReturnRange: expected a range > 0 m");
		auto& sl = c.log.slice;
		sl.minHeight = cfg.read_double("Log", "sliceMinHeight", sl.minHeight);
		sl.maxHeight = cfg.read_double("Log", "sliceMaxHeight", sl.maxHeight);
		sl.resolution = mrpt::DEG2RAD(cfg.read_double("Log", "sliceResolution_deg", mrpt::RAD2DEG(sl.resolution)));
		sl.maxRange = cfg.read_double("Log", "sliceMaxRange", sl.maxRange);
		if (!(sl.minHeight < sl.maxHeight))
			throw std::invalid_argument("[Log] sliceMinHeight, sliceMaxHeight: expected sliceMinHeight < sliceMaxHeight (m)");
		if (!(sl.resolution >= mrpt::DEG2RAD(0.05) && sl.resolution <= mrpt::DEG2RAD(10)))
			throw std::invalid_argument("[Log] sliceResolution_deg: expected 0.05..10 degrees");
		if (!(sl.maxRange > 0 && sl.maxRange <= 1000)) throw std::invalid_argument("[Log] sliceMaxRange: expected 0..1000 m");
		c.odometrySource = parseOdometrySource(trimBlanks(cfg.read_string("Log", "odometrySource", "auto")), where);
	}
	catch (const ConfigError&)
	{
		throw;
	}
	catch (const std::exception& e)
	{
		throw ConfigError(where + ": " + e.what());
	}
	return c;
}
}  // namespace

SlamConfig parseSlamConfig(const std::string& iniText, const std::string& sourceName,
						   const std::vector<std::string>& overrides)
{
	try
	{
		return parseChecked(iniText, sourceName, overrides);
	}
	catch (const ConfigError&)
	{
		throw;
	}
	catch (const std::exception& e)
	{  // MRPT's INI reader itself (e.g. its ${...}/$eval{...} expansion) rejected the text
		throw ConfigError(sourceName + ": " + oneLine(e.what()));
	}
}

SlamConfig loadSlamConfig(const std::string& iniPath, const std::vector<std::string>& overrides)
{
	if (iniPath.empty()) return parseSlamConfig("", "defaults", overrides);
	std::error_code ec;
	if (std::filesystem::is_directory(iniPath, ec))
		throw ConfigError(iniPath + ": is a directory (expected an INI file)");
	std::ifstream in(iniPath);
	if (!in) throw ConfigError(iniPath + ": cannot open configuration file (expected an INI file)");
	std::stringstream ss;
	ss << in.rdbuf();
	if (in.bad()) throw ConfigError(iniPath + ": cannot read configuration file (expected an INI file)");
	return parseSlamConfig(ss.str(), iniPath, overrides);
}

}  // namespace pmslam
