/* pmslam — reading MRPT icp-slam INI files (private to SlamConfig).
 *
 * An MRPT user's icp-slam configuration maps the same log with pmslam: the keys of
 * [MappingApplication] that mean the same in both programs are read with that meaning, under
 * pmslam's names (icp-slam's localization* thresholds are when a scan is matched, its insertion*
 * thresholds when it goes into the map; rawlog_file and logOutput_dir are the log and the output
 * folder); what pmslam does not use ([ICP], the other maps' sections, display and logging keys)
 * is ignored, and named in one note; a key that cannot mean what the file says is an error.
 */
#pragma once

#include <mrpt/config/CConfigFileMemory.h>

#include <string>
#include <vector>

namespace pmslam::detail
{
/** `s` without leading and trailing blanks (space, tab, CR, LF): how both INI readers take a value. */
inline std::string trimBlanks(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r\n");
	if (b == std::string::npos) return "";
	return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

/** True for an icp-slam file: an [ICP] section, or icp-slam's own [MappingApplication] keys. */
bool isIcpSlamConfig(const mrpt::config::CConfigFileBase& cfg);

struct IcpSlamTranslation
{
	std::string logFile, outputDir;	 // rawlog_file, logOutput_dir (empty: not given)
	std::string note;  // what was ignored and how the thresholds were read, one line
};

/** The pmslam configuration (INI text) an icp-slam file means (pmslam's own sections are kept as
 * they are). Throws ConfigError (naming `source`) for a key pmslam cannot honour. */
std::string translateIcpSlamConfig(const mrpt::config::CConfigFileBase& cfg,
														const std::string& source, IcpSlamTranslation& out);
}  // namespace pmslam::detail
