/* pm-slam-config — prints pm-slam-app's configuration, made from the key descriptors (SlamConfig.h).
 *
 *   pm-slam-config [--config FILE] [--set SECTION.KEY=VALUE]... [--all | --markdown]
 *
 * Without options: the basic keys with their defaults, which is config/default.ini. With --config and
 * --set: the configuration a run with them would use (after the same checks: exit 2 and one line on a
 * bad key or value). --all: every key, expert ones too. --markdown: docs/configuration.md. */
#include <pmslam/slam/SlamConfig.h>

#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace
{
const char* const kUsage =
	"usage: pm-slam-config [--config FILE] [--set SECTION.KEY=VALUE]... [--all | --markdown]\n"
	"Prints pm-slam-app's configuration as INI: the basic keys (config/default.ini), --all every key;\n"
	"--markdown prints docs/configuration.md.\n";

struct Args
{
	std::string config;
	std::vector<std::string> sets;
	bool all = false, markdown = false;
};

/** The value of option `name` at argv[i] ("--name VALUE" or "--name=VALUE"), or nullptr if argv[i] is not it. */
const char* valueOf(const char* name, int argc, char** argv, int& i)
{
	const std::size_t n = std::strlen(name);
	if (std::strncmp(argv[i], name, n) != 0) return nullptr;
	if (argv[i][n] == '=') return argv[i] + n + 1;
	if (argv[i][n] != '\0') return nullptr;
	if (i + 1 >= argc) throw std::invalid_argument(std::string(name) + " needs a value");
	return argv[++i];
}

Args parse(int argc, char** argv)
{
	Args a;
	for (int i = 1; i < argc; ++i)
	{
		const std::string arg = argv[i];
		if (arg == "--all")
			a.all = true;
		else if (arg == "--markdown")
			a.markdown = true;
		else if (arg == "--help" || arg == "-h")
		{
			std::cout << kUsage;
			std::exit(0);
		}
		else if (const char* v = valueOf("--config", argc, argv, i))
			a.config = v;
		else if (const char* s = valueOf("--set", argc, argv, i))
			a.sets.push_back(s);
		else
			throw std::invalid_argument("unknown option '" + arg + "'");
	}
	return a;
}
}  // namespace

int main(int argc, char** argv)
{
	try
	{
		const Args a = parse(argc, argv);
		if (a.markdown)
		{
			std::cout << pmslam::configAsMarkdown();
			return 0;
		}
		const pmslam::SlamConfig c = pmslam::loadSlamConfig(a.config, a.sets);
		for (const auto& n : c.notes) std::cerr << "pm-slam-config: note: " << n << "\n";
		std::cout << pmslam::configAsIni(c, a.all);
		return 0;
	}
	catch (const pmslam::ConfigError& e)
	{
		std::cerr << "pm-slam-config: " << e.what() << "\n";
		return 2;
	}
	catch (const std::exception& e)
	{
		std::cerr << "pm-slam-config: " << e.what() << "\n" << kUsage;
		return 2;
	}
}
