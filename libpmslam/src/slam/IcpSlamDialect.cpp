/* pmslam — reading MRPT icp-slam INI files (see IcpSlamDialect.h). */
#include "IcpSlamDialect.h"

#include <pmslam/slam/SlamConfig.h>

#include <algorithm>
#include <cstdlib>
#include <set>

namespace pmslam::detail
{
namespace
{
// [MappingApplication] keys of MRPT's icp-slam that pmslam has no use for: display, logging, the
// choice of maps (pmslam always keeps its own grid) and ICP's acceptance threshold (a different
// score from PM's goodness).
const std::set<std::string> kIgnoredKeys = {
	"CAMERA_3DSCENE_FOLLOWS_ROBOT", "LOG_FREQUENCY", "SAVE_3D_SCENE", "SAVE_POSE_LOG", "SHOW_LASER_SCANS_3D",
	"SHOW_PROGRESS_3D_REAL_TIME", "SHOW_PROGRESS_3D_REAL_TIME_DELAY_MS", "alwaysInsertByClass", "beaconMap_count",
	"gasGrid_count", "landmarksMap_count", "likelihoodMapSelection", "matchAgainstTheGrid", "minICPgoodnessToAccept",
	"occupancyGrid_count", "octoMap_count", "pointsMap_count", "wifiGrid_count", "colourPointsMap_count",
	"weightedPointsMap_count", "heightMap_count", "reflectivityMap_count", "voxelMap_count"};
// icp-slam [MappingApplication] key -> pmslam key of the same meaning and unit, and pmslam's older
// name for that key (nullptr: none that is not also an icp-slam key).
struct Renamed
{
	const char *first, *second, *pmslamOldName;
};
const Renamed kRenamed[] = {
	{"localizationLinDistance", "matchLinDistance", nullptr},  // m: a scan is matched past this
	{"localizationAngDistance", "matchAngDistance_deg", "insertionAngDistance_deg"},  // deg
	{"insertionLinDistance", "mapInsertLinDistance", nullptr},	// m: a scan goes into the map past this
	{"insertionAngDistance", "mapInsertAngDistance_deg", nullptr},	// deg
};
const char* kOwnSections[] = {"PerfectMatch", "LoopClosure", "Log"};

std::string value(const mrpt::config::CConfigFileBase& cfg, const std::string& section, const std::string& key)
{
	// MRPT's INI files put comments after values with "//".
	std::string v = cfg.read_string(section, key, "");
	if (const auto c = v.find("//"); c != std::string::npos) v.erase(c);
	return trimBlanks(v);
}
}  // namespace

bool isIcpSlamConfig(const mrpt::config::CConfigFileBase& cfg)
{
	std::vector<std::string> sections, keys;
	cfg.getAllSections(sections);
	if (std::find(sections.begin(), sections.end(), "ICP") != sections.end()) return true;
	cfg.getAllKeys("MappingApplication", keys);
	for (const auto& k : keys)
		if (k == "localizationLinDistance" || k == "localizationAngDistance" || k == "rawlog_file" ||
			k == "logOutput_dir" || kIgnoredKeys.count(k))
			return true;
	return false;
}

std::string translateIcpSlamConfig(const mrpt::config::CConfigFileBase& cfg,
								   const std::string& source, IcpSlamTranslation& out)
{
	mrpt::config::CConfigFileMemory t;
	std::vector<std::string> sections;
	cfg.getAllSections(sections);
	std::vector<std::string> ignoredSections, ignoredKeys, read;
	for (const auto& sec : sections)
	{
		if (sec.empty()) continue;
		std::vector<std::string> keys;
		cfg.getAllKeys(sec, keys);
		if (std::find(std::begin(kOwnSections), std::end(kOwnSections), sec) != std::end(kOwnSections))
		{
			for (const auto& k : keys) t.write(sec, k, value(cfg, sec, k));
			continue;
		}
		if (sec == "MappingApplication_occupancyGrid_00_creationOpts" && !value(cfg, sec, "resolution").empty())
		{
			// The grid's cell size means the same in both programs.
			t.write("MappingApplication", "resolution", value(cfg, sec, "resolution"));
			read.push_back("[" + sec + "] resolution");
		}
		if (sec != "MappingApplication")
		{
			ignoredSections.push_back("[" + sec + "]");
			continue;
		}
		for (const auto& k : keys)
		{
			const std::string v = value(cfg, sec, k);
			const auto renamed = std::find_if(std::begin(kRenamed), std::end(kRenamed),
											  [&](const auto& r) { return k == r.first; });
			if (renamed != std::end(kRenamed))
			{
				// In an icp-slam file insertionLinDistance is icp-slam's own (map insertion): only
				// pmslam's other names can clash.
				for (const char* pmslamName : {renamed->second, renamed->pmslamOldName})
					if (pmslamName && std::find(keys.begin(), keys.end(), pmslamName) != keys.end())
						throw ConfigError(source + ": [MappingApplication] " + k + " (icp-slam's name) and " +
										  pmslamName + " (pmslam's) both set the same threshold: keep one");
				t.write(sec, renamed->second, v);
				read.push_back(k + " as " + renamed->second);
			}
			else if (k == "rawlog_file")
				out.logFile = v;
			else if (k == "logOutput_dir")
				out.outputDir = v;
			else if (k == "rawlog_offset")
			{
				char* end = nullptr;
				const long n = std::strtol(v.c_str(), &end, 10);
				if (end == v.c_str() || *end || n != 0)
					throw ConfigError(source + ": [MappingApplication] rawlog_offset = '" + v +
									  "': pmslam maps the whole log (expected 0; cut the log with rawlog-edit instead)");
			}
			else if (kIgnoredKeys.count(k))
				ignoredKeys.push_back(k);
			else
				t.write(sec, k, v);	 // a pmslam key (or a typo, which validation names)
		}
	}
	out.note = source + " is an icp-slam configuration:";
	if (!read.empty())
	{
		out.note += " read ";
		for (std::size_t i = 0; i < read.size(); ++i) out.note += (i ? ", " : "") + read[i];
		out.note += ";";
	}
	if (!ignoredSections.empty() || !ignoredKeys.empty())
	{
		out.note += " not used by pmslam:";
		for (const auto& s : ignoredSections) out.note += " " + s;
		if (!ignoredKeys.empty())
		{
			out.note += ignoredSections.empty() ? " " : "; [MappingApplication] ";
			for (std::size_t i = 0; i < ignoredKeys.size(); ++i) out.note += (i ? ", " : "") + ignoredKeys[i];
		}
	}
	return t.getContent();
}
}  // namespace pmslam::detail
