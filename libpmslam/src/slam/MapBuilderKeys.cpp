/* pmslam — the [MappingApplication] keys: MapBuilderOptions (and its grid's) as configuration data (ConfigKeys.h).
 * The docs say what a key does in a line; docs/decisions.md says why each default is what it is. */
#include <pmslam/slam/PerfectMatchSlam.h>

#include <stdexcept>

namespace pmslam
{
namespace
{
using M = MapBuilderOptions;
using config::Level;

std::vector<config::Key<M>> makeKeys()
{
	using config::above;
	using config::atLeast;
	using config::closed;
	const config::Range fraction = closed(0, 1);
	std::vector<config::Key<M>> k = {
		config::withAliases(
			config::number<M>("matchLinDistance", "m", closed(0, 100), Level::Basic,
							  "Match a scan once the robot moved this far since the last match (the paper: 0.01); "
							  "scans below this and matchAngDistance_deg keep the odometry pose (D6).",
							  [](auto& o) -> auto& { return o.matchLinDistance; }),
			{"insertionLinDistance"}),
		config::withAliases(config::degrees<M>("matchAngDistance_deg", closed(0, 360), Level::Basic,
											   "Match a scan once the robot turned this much since the last match "
											   "(the paper: 28.6; 2 keeps every match local) (D6).",
											   [](auto& o) -> auto& { return o.matchAngDistance; }),
							{"insertionAngDistance_deg"}),
		config::number<M>("minGoodness", "", fraction, Level::Expert,
						  "Reject a match whose goodness (mean likelihood; good matches 0.8-0.98) is below this "
						  "(0 = accept all) (D7).",
						  [](auto& o) -> auto& { return o.minGoodness; }),
		config::number<M>("mapInsertLinDistance", "m", atLeast(0), Level::Basic,
						  "Insert a matched scan into the map (a keyframe) once the robot moved this far since the "
						  "last insertion (0 with mapInsertAngDistance_deg 0: insert every matched scan) (D8).",
						  [](auto& o) -> auto& { return o.mapInsertLinDistance; }),
		config::degrees<M>("mapInsertAngDistance_deg", atLeast(0), Level::Basic,
						   "Insert a matched scan into the map once the robot turned this much since the last insertion (D8).",
						   [](auto& o) -> auto& { return o.mapInsertAngDistance; }),
		config::number<M>("mapInsertBelowInliers", "", fraction, Level::Expert,
						  "Also insert a matched scan when fewer than this share of its points are within the "
						  "distance map's reach (new ground) (D8).",
						  [](auto& o) -> auto& { return o.mapInsertBelowInliers; }),
		config::count<M>("minPoints", "", atLeast(0), Level::Expert, "Scans with fewer usable returns are not matched.",
						 [](auto& o) -> auto& { return o.minPoints; }),
		config::number<M>("minOverlapGoodness", "", fraction, Level::Expert,
						  "Accept a mostly-new-ground match when its minPoints+ points overlapping the map score at "
						  "least this (0 = off) (D13); after a logging gap, no match whose overlap scores less (D56).",
						  [](auto& o) -> auto& { return o.minOverlapGoodness; }),
		config::number<M>("degenerateBelow", "", {0, 1, false, true}, Level::Expert,
						  "A direction whose information is below this share of the largest is left to odometry "
						  "(a plain corridor, along it; 0 = off) (D19).",
						  [](auto& o) -> auto& { return o.degenerateBelow; }),
		config::number<M>("wideSearchBelowGoodness", "", fraction, Level::Expert,
						  "Run the wide correlative search when the match from the prediction scores below this "
						  "(0 = never) (D12).",
						  [](auto& o) -> auto& { return o.wideSearchBelowGoodness; }),
		config::number<M>("wideSearchLinear", "m", closed(0, 10), Level::Expert,
						  "Half-width of the wide search in x and y (D12).",
						  [](auto& o) -> auto& { return o.wideSearchLinear; }),
		config::degrees<M>("wideSearchAngular_deg", closed(0, 180), Level::Expert, "Half-width of the wide search in heading (D12).",
						   [](auto& o) -> auto& { return o.wideSearchAngular; }),
		config::number<M>("relocalizeAfterGap", "s", above(0), Level::Expert,
						  "A step between two scans longer than this is a gap: the search window grows with it (D15).",
						  [](auto& o) -> auto& { return o.relocalizeAfterGap; }),
		config::number<M>("relocalizeAfterJump", "m", above(0), Level::Expert,
						  "An odometry step between two scans longer than this is a gap too (D15).",
						  [](auto& o) -> auto& { return o.relocalizeAfterJump; }),
		config::number<M>("relocalizeSpeed", "m/s", closed(0, 10), Level::Expert,
						  "While matches are rejected, the search window grows this fast (D16).",
						  [](auto& o) -> auto& { return o.relocalizeSpeed; }),
		config::degrees<M>("relocalizeTurnRate_deg", closed(0, 360), Level::Expert,
						   "While matches are rejected, the search window's heading grows this fast (deg/s) (D16).",
						   [](auto& o) -> auto& { return o.relocalizeTurnRate; }),
		config::number<M>("relocalizeOdometryError", "", fraction, Level::Expert,
						  "After a gap the window grows by this share of the odometry's distance and turn over it (D15).",
						  [](auto& o) -> auto& { return o.relocalizeOdometryError; }),
		config::number<M>("relocalizeMaxLinear", "m", closed(0, 20), Level::Expert,
						  "The largest re-localisation window (half-width in x and y) (D16).",
						  [](auto& o) -> auto& { return o.relocalizeMaxLinear; }),
		config::number<M>("relocalizeAmbiguity", "", fraction, Level::Expert,
						  "A distinct pose scoring within this of the best leaves a re-localisation undecided "
						  "(0 = off) (D17).",
						  [](auto& o) -> auto& { return o.relocalizeAmbiguity; }),
		config::number<M>("newGroundUnexplored", "", fraction, Level::Expert,
						  "While lost, a scan with at least this share of returns in never-observed cells is "
						  "inserted at the odometry pose (0 = never) (D14).",
						  [](auto& o) -> auto& { return o.newGroundUnexplored; }),
		config::number<M>("newGroundAfter", "s", atLeast(0), Level::Expert,
						  "...once no match was accepted for this long (D14).",
						  [](auto& o) -> auto& { return o.newGroundAfter; }),
		config::number<M>("matchWhenScanChanged", "", fraction, Level::Expert,
						  "Match a scan taken with odometry standing still when more than this share of its ranges "
						  "changed by over 0.1 m (0 = never): the robot is carried or pushed (D18).",
						  [](auto& o) -> auto& { return o.matchWhenScanChanged; }),
		config::flag<M>("odometryToScanTime", Level::Expert,
						"Give the trajectory smoother odometry extrapolated to the scan's time (minus scanLatency), "
						"not the latest reading (D20).",
						[](auto& o) -> auto& { return o.odometryToScanTime; }),
		config::number<M>("scanLatency", "s", closed(0, 1), Level::Basic,
						  "The scan was taken this long before its timestamp (a SICK LMS at 38.4 kbaud: ~0.1) (D20).",
						  [](auto& o) -> auto& { return o.scanLatency; }),
		config::flag<M>("odometrySmoothing", Level::Basic,
						"Report each pose fused with the odometry increments (a fixed-lag smoother, noise learned "
						"online); the map keeps the matched poses (D21).",
						[](auto& o) -> auto& { return o.odometrySmoothing; }),
		config::count<M>("odometrySmoothingLag", "scans", closed(0, 100), Level::Expert,
						 "A reported pose is final this many scans after its scan (D21).",
						 [](auto& o) -> auto& { return o.odometrySmoothingLag; }),
		config::flag<M>("keepSimpleMap", Level::Basic,
						"Keep the inserted scans and their poses (written as map.simplemap.gz).",
						[](auto& o) -> auto& { return o.keepSimpleMap; }),
	};
	for (auto& g : config::lift<M>(OccupancyGridUpdateOptions::keys(), [](auto& o) -> auto& { return o.grid; }))
		k.push_back(std::move(g));
	return k;
}

/** What one key's range cannot say: keys that must agree with each other. */
void checkTogether(const M& o, const std::string& s)
{
	auto need = [&](bool ok, const std::string& what) {
		if (!ok) throw std::invalid_argument("[" + s + "] " + what);
	};
	need((o.mapInsertLinDistance > 0) == (o.mapInsertAngDistance > 0),
		 "mapInsertLinDistance and mapInsertAngDistance_deg: set both (> 0) or neither (0)");
	need(o.grid.maxDistance > o.grid.resolution && o.grid.maxDistance <= 10, "maxDistance: expected resolution..10 m");
}
}  // namespace

const std::vector<config::Key<M>>& M::keys()
{
	static const std::vector<config::Key<M>> k = makeKeys();
	return k;
}

void M::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	config::load(keys(), *this, c, s);
	checkTogether(*this, s);
}

void M::dumpToTextStream(std::ostream& out) const { config::dump(keys(), *this, out); }

}  // namespace pmslam
