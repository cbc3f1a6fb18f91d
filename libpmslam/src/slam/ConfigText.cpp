/* pmslam — the configuration as text for people: config/default.ini and docs/configuration.md
 * (SlamConfig.h). Both are made from the key descriptors, so they cannot drift from the code; a
 * test compares the committed files with what this writes. */
#include <pmslam/slam/SlamConfig.h>

#include <sstream>

namespace pmslam
{
namespace
{
/** "(m; 0..1)", "(true or false)", "(one of a, b)". */
std::string unitAndRange(const config::Key<SlamConfig>& k)
{
	switch (k.kind)
	{
		case config::Kind::Bool: return "true or false";
		case config::Kind::Word:
		{
			std::string s = "one of ";
			for (std::size_t i = 0; i < k.words.size(); ++i) s += (i ? ", " : "") + k.words[i];
			return s;
		}
		default:
		{
			const std::string range = k.range.text();
			if (k.unit.empty()) return range;
			return range == "any" ? k.unit : range + " " + k.unit;
		}
	}
}
/** `text` as INI comment lines of at most ~100 characters. */
std::string commentLines(const std::string& text)
{
	std::string out, line = ";";
	std::istringstream words(text);
	for (std::string w; words >> w;)
	{
		if (line.size() > 1 && line.size() + 1 + w.size() > 100) out += line + "\n", line = ";";
		line += " " + w;
	}
	return out + line + "\n";
}
}  // namespace

std::string configAsIni(const SlamConfig& c, bool all)
{
	std::ostringstream out;
	out << "; pmslam - configuration of pm-slam-app: " << (all ? "every key" : "the keys a user sets for a robot or a log")
		<< ", with their values.\n"
		   "; docs/configuration.md documents every key, the algorithm's constants too; any key works in an INI file\n"
		   "; and with --set SECTION.KEY=VALUE. Unknown sections or keys and malformed values are errors (exit 2).\n"
		   "; Written by pm-slam-config"
		<< (all ? " --all" : " (the committed config/default.ini: pm-slam-config > config/default.ini)") << ".\n";
	std::string section;
	for (const auto& k : configKeys())
	{
		if (!all && k.key.level != config::Level::Basic) continue;
		if (k.section != section) out << "\n[" << (section = k.section) << "]\n";
		out << commentLines(k.key.doc + " (" + unitAndRange(k.key) + ")");
		out << k.key.name << " = " << config::valueText(k.key, c) << "\n";
	}
	return out.str();
}

std::string configAsMarkdown()
{
	const SlamConfig defaults;
	std::ostringstream out;
	out << "# Configuration\n\n"
		   "Every key of pm-slam-app's INI configuration, made by `pm-slam-config --markdown` from the key\n"
		   "descriptors in the code (a test checks this file is up to date). **Basic** keys are what a user sets\n"
		   "for a robot or a log; they are the keys of [`config/default.ini`](../config/default.ini). **Expert**\n"
		   "keys are the algorithm's constants: they work in any INI file and with `--set SECTION.KEY=VALUE`,\n"
		   "and [decisions.md](decisions.md) says why each default is what it is. Values out of range, unknown\n"
		   "keys and sections are errors (exit status 2) naming the closest valid key. Angles are in degrees\n"
		   "(`_deg`), lengths in metres, times in seconds.\n";
	std::string section;
	for (const auto& k : configKeys())
	{
		if (k.section != section)
			out << "\n## [" << (section = k.section) << "]\n\n| key | default | allowed | level | what it does |\n"
				<< "|---|---|---|---|---|\n";
		std::string name = "`" + k.key.name + "`";
		for (const auto& a : k.key.aliases) name += " (old name: `" + a + "`)";
		out << "| " << name << " | " << config::valueText(k.key, defaults) << " | " << unitAndRange(k.key) << " | "
			<< (k.key.level == config::Level::Basic ? "basic" : "expert") << " | " << k.key.doc << " |\n";
	}
	out << "\n## Removed keys\n\nAn INI file that names one of these still loads: the key is ignored, with a note.\n\n"
		   "| key | instead |\n|---|---|\n";
	for (const auto& r : removedConfigKeys())
		out << "| `[" << r.section << "] " << r.name << "` | " << r.why << " |\n";
	out << "\n## MRPT icp-slam files\n\n"
		   "An MRPT `icp-slam` configuration (an `[ICP]` section or icp-slam's own keys) maps the same log: its\n"
		   "`localizationLinDistance` / `localizationAngDistance` are read as `matchLinDistance` /\n"
		   "`matchAngDistance_deg`, its `insertionLinDistance` / `insertionAngDistance` as `mapInsertLinDistance` /\n"
		   "`mapInsertAngDistance_deg`, its grid `resolution` as `resolution`, `rawlog_file` as the log and\n"
		   "`logOutput_dir` as the output folder; what pmslam does not use is named in one note.\n";
	return out.str();
}

}  // namespace pmslam
