/* pmslam — the whole configuration of a SLAM run, from INI text.
 *
 * Sections (all optional): [PerfectMatch] the matcher, [MappingApplication] the builder and its
 * grid, [LoopClosure] the back-end, [Log] how logs are read. Every key is one descriptor
 * (ConfigKeys.h) in the struct it configures; configKeys() lists them all with their section, and
 * loading, checking, suggestions, config/default.ini (basic keys) and docs/configuration.md (every
 * key) all come from that list (pm-slam-config prints both files).
 * An MRPT icp-slam file (an [ICP] section or icp-slam's own keys) is read in pmslam's terms
 * (IcpSlamDialect.h). Older key names are read under their new names, and removed keys are
 * ignored, each with a note (SlamConfig::notes). Unknown sections and keys, values of the wrong
 * type and values out of range are errors (ConfigError, one line naming section, key and what
 * was expected, with the closest valid key, in any section, as a suggestion): a typo must not
 * silently fall back to a default.
 */
#pragma once

#include <pmslam/slam/PerfectMatchSlam.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace pmslam
{
class ConfigError : public std::runtime_error
{
   public:
	using std::runtime_error::runtime_error;
};

/** Which odometry predicts each scan's pose. */
enum class OdometrySource
{
	Auto,  ///< the odometry written with the scan (Carmen FLASER) if any, else the latest odometry reading
	Scan,  ///< only the odometry written with the scan
	Events	///< only odometry readings (ODOM lines, CObservationOdometry, rawlog actions)
};

struct SlamConfig
{
	PerfectMatchMatcher::TConfigParams matcher;
	MapBuilderOptions mapping;
	LoopClosureOptions loopClosure;
	LogReaderOptions log;
	OdometrySource odometrySource = OdometrySource::Auto;
	/** From an MRPT icp-slam file (read in pmslam's terms, see below): its rawlog_file and
	 * logOutput_dir (empty when not given), for a program to use when the command line names none. */
	std::string icpSlamLogFile, icpSlamOutputDir;
	/** One-line notes for the user (what of an icp-slam file was read how, and what was ignored). */
	std::vector<std::string> notes;
};

/** Loads `iniPath` (empty: defaults only), then applies overrides "SECTION.KEY=VALUE".
 * Throws ConfigError. `sourceName` names the text in messages. */
SlamConfig loadSlamConfig(const std::string& iniPath, const std::vector<std::string>& overrides = {});
SlamConfig parseSlamConfig(const std::string& iniText, const std::string& sourceName,
						   const std::vector<std::string>& overrides = {});

/** One INI key of a SLAM run: its section and its descriptor over the whole SlamConfig. */
struct ConfigKey
{
	std::string section;
	config::Key<SlamConfig> key;
};
/** Every key, in the order of config/default.ini and docs/configuration.md. */
const std::vector<ConfigKey>& configKeys();

/** A key that no longer exists: an INI naming it gets a note, not an error. */
struct RemovedConfigKey
{
	const char* section;
	const char* name;
	const char* why;
};
const std::vector<RemovedConfigKey>& removedConfigKeys();

/** Every valid "Section.key", for documentation and suggestions. */
std::vector<std::string> knownConfigKeys();

/** `c` as INI text with each key's one-line doc: the basic keys (config/default.ini is this for
 * the defaults), or every key with `all`. */
std::string configAsIni(const SlamConfig& c, bool all);
/** docs/configuration.md: every key with its default, unit, range, level and doc. */
std::string configAsMarkdown();

}  // namespace pmslam
