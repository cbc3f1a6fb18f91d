/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * exceptionSummary(): one line out of an MRPT exception's text (a "==== MRPT exception ====" block with
 * Message:, Location: and a call stack, possibly nested): the innermost message, prefixed by the outermost
 * class being deserialised. Header-only, so that the sensor plugin (apps/pmslam-sensors), which links none
 * of the library, words its drivers' errors the same way the log readers do.
 */
#pragma once

#include <sstream>
#include <string>

namespace pmslam
{
inline std::string exceptionSummary(const std::string& what)
{
	std::istringstream ss(what);
	std::string l, first, last, other;
	while (std::getline(ss, l))
	{
		const auto b = l.find_first_not_of(" \t\r");
		if (b == std::string::npos) continue;
		l = l.substr(b);
		while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
		if (l.rfind("====", 0) == 0) continue;
		if (l.rfind("Message:", 0) == 0)
		{
			l = l.substr(8);
			const auto b2 = l.find_first_not_of(" \t");
			l = b2 == std::string::npos ? std::string() : l.substr(b2);
			if (first.empty()) first = l;
			last = l;
		}
		else if (other.empty())
			other = l;
	}
	std::string best = last.empty() ? other : last;
	const std::string key = "typed object '";
	const auto k = first.find(key);
	if (k != std::string::npos && first != last)
	{
		const auto e = first.find('\'', k + key.size());
		const std::string cls = first.substr(k + key.size(), e == std::string::npos ? 0 : e - k - key.size());
		if (!cls.empty() && cls.find(' ') == std::string::npos) best = "reading " + cls + ": " + best;
	}
	if (best.size() > 200) best = best.substr(0, 197) + "...";
	return best.empty() ? std::string("unknown error") : best;
}

}  // namespace pmslam
