/* pmslam apps — the command line as words, each option's value in its own word.
 *
 * Every option that takes a value accepts it both as the next word ("--out DIR") and after an
 * equals sign ("--out=DIR"), as GNU programs do; a newcomer types either. The apps' parsers see the
 * first form only: splitOptionValues() turns "--opt=value" into "--opt", "value" for the options
 * named as taking a value. Any other word stays whole, so that "--quiet=1" is still refused as an
 * unknown option, and the words after "--" are never split. Header-only: each program in apps/ is
 * built from its own folder.
 */
#pragma once

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

namespace pmslam_app
{
inline std::vector<std::string> splitOptionValues(int argc, char** argv, std::initializer_list<const char*> withValue)
{
	std::vector<std::string> words;
	bool optionsEnded = false;
	for (int i = 1; i < argc; ++i)
	{
		const std::string w = argv[i];
		optionsEnded = optionsEnded || w == "--";
		const auto eq = w.find('=');
		const bool split = !optionsEnded && w.rfind("--", 0) == 0 && eq != std::string::npos &&
						   std::any_of(withValue.begin(), withValue.end(),
									   [&](const char* name) { return w.compare(0, eq, name) == 0; });
		if (split)
		{
			words.push_back(w.substr(0, eq));
			words.push_back(w.substr(eq + 1));
		}
		else
			words.push_back(w);
	}
	return words;
}

}  // namespace pmslam_app
