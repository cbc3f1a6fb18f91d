/* pm-slam-app — the run: every event of the input through the SLAM, each scan shown to the observers,
 * until the input ends, --max-scans is reached or a stop is asked for. */
#pragma once

#include <pmslam/io/LogReader.h>

#include <string>
#include <vector>

#include "ScanObserver.h"
#include "SlamRun.h"

namespace pmslam_app
{
struct RunEnd
{
	bool failed = false;
	std::string failure;  ///< what failed (failed only)
};

/** `live`: the reader sees a stop itself (it stops the sensors, then hands over what they delivered),
 * so the loop goes on until the reader ends. An exception ends the run as failed: what was computed
 * stays, to be written. */
RunEnd runLoop(pmslam::LogReader& reader, SlamRun& run, const std::vector<ScanObserver*>& observers, bool live,
			   std::size_t maxScans);

}  // namespace pmslam_app
