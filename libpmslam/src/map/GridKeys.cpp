/* pmslam — the grid's [MappingApplication] keys: OccupancyGridUpdateOptions as configuration data (ConfigKeys.h). */
#include <pmslam/map/OccupancyDistanceGridMap.h>

namespace pmslam
{
namespace
{
using G = OccupancyGridUpdateOptions;
using config::Level;

std::vector<config::Key<G>> makeKeys()
{
	using config::atLeast;
	using config::closed;
	using config::open;
	return {
		config::number<G>("resolution", "m", closed(0.005, 2), Level::Basic, "Grid cell side (D5).",
						  [](auto& o) -> auto& { return o.resolution; }),
		config::number<G>("maxDistance", "m", config::above(0), Level::Expert,
						  "Truncation of the distance map: the likelihood field's reach (more than resolution, "
						  "at most 10 m) (D4).",
						  [](auto& o) -> auto& { return o.maxDistance; }),
		config::number<G>("hitProbability", "", open(0.5, 1), Level::Expert,
						  "Inverse sensor model: occupancy probability of a return's cell (D9).",
						  [](auto& o) -> auto& { return o.hitProbability; }),
		config::number<G>("missProbability", "", open(0, 0.5), Level::Expert,
						  "Inverse sensor model: occupancy probability of a cell a beam passes through (D9).",
						  [](auto& o) -> auto& { return o.missProbability; }),
		config::number<G>("clampProbability", "", open(0.5, 1), Level::Expert,
						  "Bound on the evidence either way, so the map can still change when the world does (D9).",
						  [](auto& o) -> auto& { return o.clampProbability; }),
		config::number<G>("freeCarveMarginBeforeHit", "m", closed(0, 10), Level::Expert,
						  "Free space stops this far before each return (0 = up to the return's cell): a wall seen "
						  "at a grazing angle stays solid (D10).",
						  [](auto& o) -> auto& { return o.freeCarveMarginBeforeHit; }),
		config::number<G>("minRange", "m", atLeast(0), Level::Basic,
						  "Returns closer than this are ignored (self-hits, dust) (D11).",
						  [](auto& o) -> auto& { return o.scan.minRange; }),
		config::number<G>("maxHitRange", "m", atLeast(0), Level::Basic,
						  "Returns farther than this only carve free space (0 = no limit): past the range where "
						  "the lidar's noise is what sigma models (D11).",
						  [](auto& o) -> auto& { return o.scan.maxHitRange; }),
		config::number<G>("noReturnCarveRange", "m", atLeast(0), Level::Basic,
						  "\"No return\" beams carve free space up to this distance (0 = not at all) (D11).",
						  [](auto& o) -> auto& { return o.scan.noReturnCarveRange; }),
	};
}
}  // namespace

const std::vector<config::Key<G>>& G::keys()
{
	static const std::vector<config::Key<G>> k = makeKeys();
	return k;
}

void G::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) { config::load(keys(), *this, c, s); }

void G::dumpToTextStream(std::ostream& out) const { config::dump(keys(), *this, out); }

}  // namespace pmslam
