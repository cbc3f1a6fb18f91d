/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * Case-insensitive name tests: file names are matched by their extension whatever its case (MAP.YAML,
 * Log.CLF), the configuration's keys by their spelling. Header-only, ASCII only (every name tested is).
 */
#pragma once

#include <algorithm>
#include <cctype>
#include <string>

namespace pmslam
{
inline std::string lowerCase(std::string s)
{
	std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
	return s;
}

/** True when `s` ends with `tail` (given in lower case), ignoring the case of `s`. */
inline bool endsWithIgnoringCase(const std::string& s, const std::string& tail)
{
	return s.size() >= tail.size() && lowerCase(s.substr(s.size() - tail.size())) == tail;
}
}  // namespace pmslam
