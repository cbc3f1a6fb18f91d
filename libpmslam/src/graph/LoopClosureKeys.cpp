/* pmslam — the [LoopClosure] keys: LoopClosureOptions as configuration data (ConfigKeys.h). */
#include <pmslam/graph/LoopClosure.h>

#include <stdexcept>

namespace pmslam
{
namespace
{
using L = LoopClosureOptions;
using config::Level;

std::vector<config::Key<L>> makeKeys()
{
	using config::above;
	using config::atLeast;
	using config::closed;
	const config::Range fraction = closed(0, 1);
	return {
		config::flag<L>("enabled", Level::Basic, "Loop closure on a pose graph (the back-end); false: the front-end alone (D23).",
						[](auto& o) -> auto& { return o.enabled; }),
		config::number<L>("minTravel", "m", above(0), Level::Expert,
						  "Path driven between a keyframe and a loop candidate, at least (D25).",
						  [](auto& o) -> auto& { return o.minTravel; }),
		config::number<L>("searchRadius", "m", atLeast(0), Level::Expert,
						  "Candidate window right after a closure (the position's uncertainty) (D25).",
						  [](auto& o) -> auto& { return o.searchRadius; }),
		config::number<L>("searchRadiusPerMeter", "m/m", atLeast(0), Level::Expert,
						  "Growth of the window per metre driven since the last closure (the drift) (D25).",
						  [](auto& o) -> auto& { return o.searchRadiusPerMeter; }),
		config::number<L>("maxSearchRadius", "m", closed(0, 20), Level::Expert,
						  "The widest candidate window (at least searchRadius) (D25).",
						  [](auto& o) -> auto& { return o.maxSearchRadius; }),
		config::degrees<L>("searchAngle_deg", atLeast(0), Level::Expert, "Heading window right after a closure (D25).",
						   [](auto& o) -> auto& { return o.searchAngle; }),
		config::degrees<L>("searchAnglePerMeter_deg", atLeast(0), Level::Expert,
						   "Growth of the heading window per metre driven (deg/m) (D25).",
						   [](auto& o) -> auto& { return o.searchAnglePerMeter; }),
		config::degrees<L>("maxSearchAngle_deg", closed(0, 180), Level::Expert,
						   "The widest heading window (at least searchAngle_deg) (D25).",
						   [](auto& o) -> auto& { return o.maxSearchAngle; }),
		config::number<L>("detectEvery", "m", atLeast(0), Level::Expert, "Path driven between two detection attempts.",
						  [](auto& o) -> auto& { return o.detectEvery; }),
		config::number<L>("localMapExtent", "m", {0, 100, true, false}, Level::Expert,
						  "Path on either side of a candidate keyframe in its local map (D26).",
						  [](auto& o) -> auto& { return o.localMapExtent; }),
		config::number<L>("minGoodness", "", fraction, Level::Expert,
						  "A loop match must score at least this against the local map (mean likelihood) (D27).",
						  [](auto& o) -> auto& { return o.minGoodness; }),
		config::number<L>("minInlierFraction", "", fraction, Level::Expert,
						  "...with at least this share of its points within the distance map's reach (D27).",
						  [](auto& o) -> auto& { return o.minInlierFraction; }),
		config::number<L>("ambiguityMargin", "", fraction, Level::Expert,
						  "A distinct pose scoring within this of the best makes the match ambiguous (dropped) (D27).",
						  [](auto& o) -> auto& { return o.ambiguityMargin; }),
		config::number<L>("maxUnexploredFraction", "", fraction, Level::Expert,
						  "At most this share of the scan may land where the local map saw nothing (D27).",
						  [](auto& o) -> auto& { return o.maxUnexploredFraction; }),
		config::number<L>("maxInFreeSpace", "", fraction, Level::Expert,
						  "At most this share of the scan may land where the local map saw free space, not counting returns the "
						  "keyframes just before saw through (D27).",
						  [](auto& o) -> auto& { return o.maxInFreeSpace; }),
		config::count<L>("agreeingMatches", "", closed(1, 20), Level::Expert,
						 "Verified matches that must agree before a loop is accepted (more in windows over 4 m) (D28).",
						 [](auto& o) -> auto& { return o.agreeingMatches; }),
		config::number<L>("agreeWindow", "m", above(0), Level::Expert, "Path over which agreeing matches are looked for (D28).",
						  [](auto& o) -> auto& { return o.agreeWindow; }),
		config::number<L>("agreeLinear", "m", above(0), Level::Expert,
						  "Two matches agree when they imply the same relative pose within this (D28)...",
						  [](auto& o) -> auto& { return o.agreeLinear; }),
		config::degrees<L>("agreeAngular_deg", above(0), Level::Expert, "...and this (D28).",
						   [](auto& o) -> auto& { return o.agreeAngular; }),
		config::number<L>("informationScale", "", above(0), Level::Expert,
						  "Loop edge covariance = informationScale x (match Hessian)^-1 (D24).",
						  [](auto& o) -> auto& { return o.informationScale; }),
		config::number<L>("odometrySigmaLinear", "m", above(0), Level::Expert,
						  "Floor of a consecutive-keyframe edge's position sigma (D24)...",
						  [](auto& o) -> auto& { return o.odometrySigmaLinear; }),
		config::number<L>("odometrySigmaPerMeter", "m/m", atLeast(0), Level::Expert,
						  "...plus this per metre between the keyframes (D24).",
						  [](auto& o) -> auto& { return o.odometrySigmaPerMeter; }),
		config::degrees<L>("odometrySigmaAngular_deg", above(0), Level::Expert,
						   "Floor of a consecutive-keyframe edge's heading sigma (D24)...",
						   [](auto& o) -> auto& { return o.odometrySigmaAngular; }),
		config::number<L>("odometrySigmaPerRadian", "rad/rad", atLeast(0), Level::Expert,
						  "...plus this per radian turned between the keyframes (D24).",
						  [](auto& o) -> auto& { return o.odometrySigmaPerRadian; }),
		config::count<L>("optimizeEvery", "keyframes", atLeast(1), Level::Expert,
						 "Keyframes between optimisations while loop edges keep coming (D32).",
						 [](auto& o) -> auto& { return o.optimizeEvery; }),
		config::number<L>("rebuildAbove", "m", atLeast(0), Level::Expert,
						  "Once a keyframe moved more than this since it was put into the map, the map follows "
						  "the graph (D33)...",
						  [](auto& o) -> auto& { return o.rebuildAbove; }),
		config::number<L>("reinsertAbove", "m", atLeast(0), Level::Expert,
						  "...re-inserting every keyframe that moved more than this (at most rebuildAbove) (D33).",
						  [](auto& o) -> auto& { return o.reinsertAbove; }),
		config::flag<L>("background", Level::Basic,
						"Run the back-end on a second thread (false: inline; the same results either way) (D35).",
						[](auto& o) -> auto& { return o.background; }),
		config::number<L>("revisitMinOverlap", "", atLeast(0), Level::Expert,
						  "A keyframe gets a revisit edge to an earlier visit seeing this share of its scan "
						  "(above 1: no revisit edges) (D30).",
						  [](auto& o) -> auto& { return o.revisitMinOverlap; }),
		config::number<L>("revisitBelowTypical", "", fraction, Level::Expert,
						  "...when its match explains the scan within this of the recent keyframes' median (D30).",
						  [](auto& o) -> auto& { return o.revisitBelowTypical; }),
		config::number<L>("globalSearchEvery", "m", atLeast(0), Level::Expert,
						  "Path between whole-map loop searches while the stretch since lost tracking is unanchored; 0: none (D46).",
						  [](auto& o) -> auto& { return o.globalSearchEvery; }),
	};
}

/** What one key's range cannot say: keys that must agree with each other. */
void checkTogether(const L& o, const std::string& s)
{
	auto need = [&](bool ok, const std::string& what) {
		if (!ok) throw std::invalid_argument("[" + s + "] " + what);
	};
	need(o.maxSearchRadius >= o.searchRadius,
		 "searchRadius, maxSearchRadius: expected searchRadius <= maxSearchRadius (m)");
	need(o.maxSearchAngle >= o.searchAngle,
		 "searchAngle_deg, maxSearchAngle_deg: expected searchAngle_deg <= maxSearchAngle_deg");
	need(o.reinsertAbove <= o.rebuildAbove, "rebuildAbove, reinsertAbove: expected reinsertAbove <= rebuildAbove (m)");
}
}  // namespace

const std::vector<config::Key<L>>& L::keys()
{
	static const std::vector<config::Key<L>> k = makeKeys();
	return k;
}

void L::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	config::load(keys(), *this, c, s);
	checkTogether(*this, s);
}

void L::dumpToTextStream(std::ostream& out) const { config::dump(keys(), *this, out); }

}  // namespace pmslam
