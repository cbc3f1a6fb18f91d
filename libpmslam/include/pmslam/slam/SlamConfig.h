/* pmslam — the whole configuration of a SLAM run, from INI text.
 *
 * Sections (all optional; see config/default.ini for every key and default):
 *   [PerfectMatch]        the matcher (PerfectMatchMatcher::TConfigParams)
 *   [MappingApplication]  the builder and its grid (MapBuilderOptions)
 *   [Log]                 how logs are read (LogReaderOptions, odometry source)
 * An MRPT icp-slam file (an [ICP] section or icp-slam's own keys) is read in pmslam's terms: its
 * localizationLin/AngDistance are the matching thresholds (insertionLinDistance,
 * insertionAngDistance_deg), its insertionLin/AngDistance the map insertion ones
 * (mapInsertLinDistance, mapInsertAngDistance_deg), its grid resolution the grid's; rawlog_file and
 * logOutput_dir are kept for the program; [ICP], the other maps' sections and the display and
 * logging keys are ignored and named in a note (SlamConfig::notes); rawlog_offset other than 0 is an
 * error (pmslam maps the whole log).
 * Unknown sections and keys, values of the wrong type and values out of range
 * are errors (ConfigError, one line naming section, key and what was expected,
 * with the closest valid key as a suggestion): a typo must not silently fall
 * back to a default.
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

/** Every valid "Section.key", for documentation and suggestions. */
std::vector<std::string> knownConfigKeys();

}  // namespace pmslam
