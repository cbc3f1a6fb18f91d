/* pm-slam-app — what a run leaves in --out (see Outputs.h). */
#include "Outputs.h"

#include <pmslam/io/MapExport.h>
#include <pmslam/slam/Session.h>

#include <filesystem>

namespace pmslam_app
{
const std::vector<std::string>& allOutputNames()
{
	// pose.txt: --snapshot-every's newest pose.
	static const std::vector<std::string> names = {"trajectory.txt", "trajectory_online.txt", "graph.graph", "timing.txt",
												   "map.png",		 "map.pgm",				  "map.yaml",	 "map.gridmap.gz",
												   "map.simplemap.gz", "pose.txt", "session.ini"};
	return names;
}

std::vector<std::string> finalOutputNames(bool localizing, bool loopClosure)
{
	std::vector<std::string> names = {"trajectory.txt", "timing.txt", "map.png"};
	if (!localizing)
		names.insert(names.end(), {"trajectory_online.txt", "map.pgm", "map.yaml", "map.gridmap.gz", "map.simplemap.gz",
								   "session.ini"});
	if (loopClosure) names.push_back("graph.graph");
	return names;
}

namespace
{
/** A mapping run's poses after those of the sessions it continued (if any). */
pmslam::Trajectory everySession(const SlamRun& run, const pmslam::Trajectory& own)
{
	if (!run.session()) return own;
	pmslam::Trajectory all = run.earlierSessions();
	all.insert(all.end(), own.begin(), own.end());
	return all;
}
}  // namespace

void writeOutputs(const std::string& dir, const SlamRun& run, const pmslam::Trajectory& online, const TimingLog& timing,
				  const std::string& header, bool localizing, const std::string& log)
{
	namespace fs = std::filesystem;
	const auto at = [&](const char* name) { return (fs::path(dir) / name).string(); };
	const auto& slam = run.slam();
	const auto& traj = run.trajectory();
	std::vector<pmslam::SessionPart> parts;
	if (run.session()) parts = run.earlierParts();
	parts.push_back({log, traj.size(), slam.scansInserted()});
	const std::string sessions = localizing ? "" : "\n" + pmslam::sessionPartsComment(parts);
	pmslam::saveTrajectory(at("trajectory.txt"), everySession(run, traj),
						   header + sessions + "\nposes of the robot base in the map frame (m, m, rad)" +
							   (slam.loopClosure() ? ", after loop closure (the final pose graph)" : ""));
	if (!localizing)
		pmslam::saveTrajectory(at("trajectory_online.txt"), everySession(run, online),
							   header + sessions +
								   "\neach pose as known when its scan was processed (before later loop closures)");
	if (slam.loopClosure()) slam.outputGraph().writeGraphFile(at("graph.graph"));
	timing.write(at("timing.txt"), header);
	const auto& grid = slam.grid();
	pmslam::saveMapPng(grid, traj, at("map.png"), run.loopLinks());
	if (localizing) return;	 // the map is the fixed prior map: only the path over it is new
	pmslam::saveMapPgmYaml(grid, at("map.pgm"), at("map.yaml"));
	pmslam::saveGridMapGz(grid, at("map.gridmap.gz"));
	slam.saveSimpleMapGz(at("map.simplemap.gz"));
	pmslam::saveSessionIndex(dir, grid.updateOptions().resolution, parts);	// last: the session is complete
}

}  // namespace pmslam_app
