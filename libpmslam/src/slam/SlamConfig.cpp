/* pmslam — configuration loading and validation (see SlamConfig.h). */
#include <mrpt/config/CConfigFileMemory.h>
#include <pmslam/slam/SlamConfig.h>
#include <pmslam/util/TextCase.h>

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

/** How much of `word` a candidate shares at its two ends (a typo or an insertion in the middle
 * keeps both: maxRange -> maxHitRange), then the edit distance. Lower is closer. */
std::pair<long, std::size_t> distance(const std::string& word, const std::string& candidate)
{
	const std::string w = lowerCase(word), c = lowerCase(candidate);
	std::size_t prefix = 0, suffix = 0;
	while (prefix < w.size() && prefix < c.size() && w[prefix] == c[prefix]) ++prefix;
	while (suffix < w.size() && suffix < c.size() && w[w.size() - 1 - suffix] == c[c.size() - 1 - suffix]) ++suffix;
	const std::size_t shared = std::min(w.size(), prefix + suffix);
	return {-static_cast<long>(shared), editDistance(word, candidate)};
}

std::string closest(const std::string& word, const std::vector<std::string>& candidates)
{
	std::string best;
	std::pair<long, std::size_t> bestD{1, 0};
	for (const auto& c : candidates)
		if (const auto d = distance(word, c); best.empty() || d < bestD) bestD = d, best = c;
	return best;
}

/** The valid key closest to `key` met in [section]: a key of that section, or "Section.key" of
 * another when that one is closer (MappingApplication.sigma -> PerfectMatch.sigma). */
std::string suggestKey(const std::string& section, const std::string& key)
{
	std::string best;
	std::pair<long, std::size_t> bestD{1, 0};
	bool bestSameSection = false;
	for (const auto& k : configKeys())
	{
		const auto d = distance(key, k.key.name);
		const bool same = k.section == section;
		if (best.empty() || d < bestD || (d == bestD && same && !bestSameSection))
			best = same ? k.key.name : k.section + "." + k.key.name, bestD = d, bestSameSection = same;
	}
	return best;
}

using detail::trimBlanks;

std::vector<std::string> knownSections()
{
	std::vector<std::string> out;
	for (const auto& k : configKeys())
		if (std::find(out.begin(), out.end(), k.section) == out.end()) out.push_back(k.section);
	return out;
}

const ConfigKey* findKey(const std::string& section, const std::string& name)
{
	for (const auto& k : configKeys())
		if (k.section == section && k.key.name == name) return &k;
	return nullptr;
}

const ConfigKey* findByAlias(const std::string& section, const std::string& alias)
{
	for (const auto& k : configKeys())
		if (k.section == section && std::find(k.key.aliases.begin(), k.key.aliases.end(), alias) != k.key.aliases.end())
			return &k;
	return nullptr;
}

const RemovedConfigKey* findRemoved(const std::string& section, const std::string& name)
{
	for (const auto& r : removedConfigKeys())
		if (section == r.section && name == r.name) return &r;
	return nullptr;
}

/** Every section and key of `cfg` is known (an older name or a removed key gets a note in `notes`);
 * throws ConfigError naming the first that is not, with the closest valid one. */
void checkNames(const mrpt::config::CConfigFileBase& cfg, const std::string& source, std::vector<std::string>& notes)
{
	std::vector<std::string> sections;
	cfg.getAllSections(sections);
	const auto valid = knownSections();
	std::vector<std::string> renamed, removed;
	for (const auto& sec : sections)
	{
		if (sec.empty()) continue;
		if (std::find(valid.begin(), valid.end(), sec) == valid.end())
			throw ConfigError(source + ": unknown section [" + sec + "] (did you mean [" + closest(sec, valid) + "]?)");
		std::vector<std::string> keys;
		cfg.getAllKeys(sec, keys);
		for (const auto& key : keys)
		{
			if (findKey(sec, key)) continue;
			if (const auto* k = findByAlias(sec, key))
			{
				if (cfg.keyExists(sec, k->key.name))
					throw ConfigError(source + ": [" + sec + "] " + key + " is the old name of " + k->key.name +
									  ", which is set too: keep one");
				renamed.push_back("[" + sec + "] " + key + " as " + k->key.name);
			}
			else if (const auto* r = findRemoved(sec, key))
				removed.push_back("[" + sec + "] " + key + " (" + r->why + ")");
			else
				throw ConfigError(source + ": unknown key '" + key + "' in [" + sec + "] (did you mean '" +
								  suggestKey(sec, key) + "'?)");
		}
	}
	auto note = [&](const std::string& what, const std::vector<std::string>& items) {
		if (items.empty()) return;
		std::string line = source + ": " + what;
		for (std::size_t i = 0; i < items.size(); ++i) line += (i ? "; " : " ") + items[i];
		notes.push_back(line);
	};
	note("read under its new name:", renamed);
	note("ignored, no longer a key:", removed);
}

}  // namespace

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

/** "SECTION.KEY=VALUE" (blanks around each part allowed) written into `cfg`. */
void applyOverride(mrpt::config::CConfigFileMemory& cfg, const std::string& o)
{
	const auto eq = o.find('=');
	const std::string name = trimBlanks(o.substr(0, eq)), dotted = eq == std::string::npos ? "" : name;
	const auto dot = dotted.find('.');
	if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == dotted.size())
		throw ConfigError("--set '" + o + "': expected SECTION.KEY=VALUE, e.g. PerfectMatch.sigma=0.05");
	cfg.write(trimBlanks(dotted.substr(0, dot)), trimBlanks(dotted.substr(dot + 1)), trimBlanks(o.substr(eq + 1)));
}

/** [Log]: the log reader's keys and the odometry source. */
void loadLogSection(const mrpt::config::CConfigFileBase& cfg, SlamConfig& c)
{
	std::vector<config::Key<SlamConfig>> keys;
	for (const auto& k : configKeys())
		if (k.section == "Log") keys.push_back(k.key);
	config::load(keys, c, cfg, "Log");
	if (!(c.log.slice.minHeight < c.log.slice.maxHeight))
		throw std::invalid_argument("[Log] sliceMinHeight, sliceMaxHeight: expected sliceMinHeight < sliceMaxHeight (m)");
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
	for (const auto& o : overrides) applyOverride(cfg, o);
	const std::string where = overrides.empty() ? sourceName : sourceName + " (with --set overrides)";
	checkNames(cfg, where, c.notes);
	try
	{
		c.matcher.loadFromConfigFile(cfg, "PerfectMatch");
		c.mapping.loadFromConfigFile(cfg, "MappingApplication");
		c.loopClosure.loadFromConfigFile(cfg, "LoopClosure");
		loadLogSection(cfg, c);
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
