/* pm-slam-app — what a run leaves in --out: the trajectories, the pose graph, the timing and the map
 * (see --help). */
#pragma once

#include <pmslam/io/Trajectory.h>

#include <string>
#include <vector>

#include "SlamRun.h"
#include "TimingLog.h"

namespace pmslam_app
{
/** Every file name pm-slam-app writes into --out, in any run. */
const std::vector<std::string>& allOutputNames();

/** The files a run writes at its end: localising writes no map of its own (the map is the fixed
 * prior one) and no online trajectory; without loop closure there is no graph. */
std::vector<std::string> finalOutputNames(bool localizing, bool loopClosure);

/** Writes them into `dir`, `header` first in each text file; a mapping run also its session (session.ini, in
 * which `log` names this run's part, after the parts of a session it continued). Throws on failure. */
void writeOutputs(const std::string& dir, const SlamRun& run, const pmslam::Trajectory& online, const TimingLog& timing,
				  const std::string& header, bool localizing, const std::string& log);

}  // namespace pmslam_app
