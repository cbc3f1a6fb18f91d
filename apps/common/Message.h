/* pmslam apps — one prefix per message.
 *
 * The library words some of its exceptions for a program that prints them bare ("pmslam: log file
 * 'x' does not exist"); a program of apps/ names itself first ("pm-slam-app: ..."), so it drops the
 * library's name: a message carries one prefix, the program's.
 */
#pragma once

#include <string>

namespace pmslam_app
{
inline std::string withoutLibraryPrefix(const std::string& text)
{
	const std::string prefix = "pmslam: ";
	return text.rfind(prefix, 0) == 0 ? text.substr(prefix.size()) : text;
}

}  // namespace pmslam_app
