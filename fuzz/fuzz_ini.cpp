// libFuzzer target: pmslam::parseSlamConfig on arbitrary INI text and --set
// overrides. The input is the INI text, then optionally a NUL byte followed by
// newline-separated overrides. Anything may be rejected, with a ConfigError
// only; whatever is accepted must pass the checks of the configuration.
#include <pmslam/slam/SlamConfig.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
	const std::string input(reinterpret_cast<const char*>(data), size);
	const std::size_t nul = input.find('\0');
	const std::string text = input.substr(0, nul);
	std::vector<std::string> overrides;
	if (nul != std::string::npos)
	{
		std::size_t pos = nul + 1;
		while (pos <= input.size() && overrides.size() < 16)
		{
			std::size_t nl = input.find('\n', pos);
			if (nl == std::string::npos) nl = input.size();
			overrides.push_back(input.substr(pos, nl - pos));
			pos = nl + 1;
		}
	}
	try
	{
		const pmslam::SlamConfig c = pmslam::parseSlamConfig(text, "fuzz.ini", overrides);
		if (!(c.log.noReturnRange > 0) || !std::isfinite(c.log.noReturnRange))
			pmslam::fuzz::fail("accepted a noReturnRange that is not a finite range > 0");
		if (!std::isfinite(c.matcher.sigma) || !(c.matcher.sigma > 0)) pmslam::fuzz::fail("accepted sigma <= 0");
		if (!(c.mapping.grid.resolution > 0) || !std::isfinite(c.mapping.grid.resolution))
			pmslam::fuzz::fail("accepted a grid resolution <= 0");
	}
	catch (const pmslam::ConfigError& e)
	{
		if (std::string(e.what()).empty()) pmslam::fuzz::fail("empty ConfigError");
	}
	return 0;
}
