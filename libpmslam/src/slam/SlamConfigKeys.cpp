/* pmslam — every key of a SLAM run, by section (SlamConfig.h): the structs' own keys composed, and
 * the [Log] keys, which configure the log reader and the odometry source. */
#include <pmslam/slam/SlamConfig.h>

namespace pmslam
{
namespace
{
using S = SlamConfig;
using config::Level;

const char* toText(OdometrySource s)
{
	switch (s)
	{
		case OdometrySource::Auto: return "auto";
		case OdometrySource::Scan: return "scan";
		case OdometrySource::Events: return "events";
	}
	return "?";
}

OdometrySource odometrySourceFrom(const std::string& v)
{
	return v == "scan" ? OdometrySource::Scan : v == "events" ? OdometrySource::Events : OdometrySource::Auto;
}

std::vector<config::Key<S>> logKeys()
{
	using config::closed;
	return {
		config::number<S>("noReturnRange", "m", config::above(0), Level::Basic,
						  "Carmen logs: readings at or beyond this are \"no return\" (intel and fr079 write ~81.9 m, "
						  "aces saturates at 50) (D11).",
						  [](auto& c) -> auto& { return c.log.noReturnRange; }),
		config::word<S>(
			"odometrySource", {"auto", "scan", "events"}, Level::Basic,
			"Odometry predicting each scan: auto (the scan's own if it has one, else the latest reading), scan "
			"(only the scan's own), events (only odometry readings and rawlog actions) (D40).",
			[](auto& c) -> auto& { return c.odometrySource; }, toText, odometrySourceFrom),
		config::number<S>("sliceMinHeight", "m", config::Range{}, Level::Basic,
						  "3D lidars and depth cameras: points above this height (robot frame) form the 2D scan (D41)...",
						  [](auto& c) -> auto& { return c.log.slice.minHeight; }),
		config::number<S>("sliceMaxHeight", "m", config::Range{}, Level::Basic, "...up to this height (D41).",
						  [](auto& c) -> auto& { return c.log.slice.maxHeight; }),
		config::degrees<S>("sliceResolution_deg", closed(0.05, 10), Level::Basic, "Angular step of the slice's beams (D41).",
						   [](auto& c) -> auto& { return c.log.slice.resolution; }),
		config::number<S>("sliceMaxRange", "m", {0, 1000, true, false}, Level::Basic,
						  "Points of the slice farther than this are left out (D41).",
						  [](auto& c) -> auto& { return c.log.slice.maxRange; }),
	};
}

std::vector<ConfigKey> makeKeys()
{
	std::vector<ConfigKey> all;
	auto add = [&](const char* section, std::vector<config::Key<S>> keys) {
		for (auto& k : keys) all.push_back({section, std::move(k)});
	};
	add("PerfectMatch",
		config::lift<S>(PerfectMatchMatcher::TConfigParams::keys(), [](auto& c) -> auto& { return c.matcher; }));
	add("MappingApplication", config::lift<S>(MapBuilderOptions::keys(), [](auto& c) -> auto& { return c.mapping; }));
	add("LoopClosure", config::lift<S>(LoopClosureOptions::keys(), [](auto& c) -> auto& { return c.loopClosure; }));
	add("Log", logKeys());
	return all;
}
}  // namespace

const std::vector<ConfigKey>& configKeys()
{
	static const std::vector<ConfigKey> k = makeKeys();
	return k;
}

const std::vector<RemovedConfigKey>& removedConfigKeys()
{
	// Off by default and used by no test or benchmark: each did nothing unless set.
	static const std::vector<RemovedConfigKey> k = {
		{"PerfectMatch", "rpropPatience", "RPROP stops on its step sizes"},
		{"PerfectMatch", "useInitialCovarianceAsPrior", "AlignPDF matches without a prior, as CICP does"},
		{"MappingApplication", "ignoreUnexploredPoints", "every return takes part in the match"},
		{"MappingApplication", "matchAtLeastEvery", "matchWhenScanChanged follows a robot moved unseen by odometry"},
		{"MappingApplication", "odometryPriorSigmaXY", "matches have no fixed odometry prior"},
		{"MappingApplication", "odometryPriorSigmaPhi_deg", "matches have no fixed odometry prior"},
		{"MappingApplication", "joinHitsCloserThan", "each return marks its own cell"},
		{"MappingApplication", "freeCarveLength", "beams carve free space from the sensor"},
	};
	return k;
}

std::vector<std::string> knownConfigKeys()
{
	std::vector<std::string> out;
	for (const auto& k : configKeys()) out.push_back(k.section + "." + k.key.name);
	return out;
}

}  // namespace pmslam
