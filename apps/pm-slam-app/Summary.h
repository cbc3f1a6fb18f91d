/* pm-slam-app — the end of a run: the summary on stdout (unless --quiet) and the exit status. */
#pragma once

#include <cstddef>

#include "Input.h"
#include "LiveStatistics.h"
#include "Options.h"
#include "RunLoop.h"
#include "SlamRun.h"
#include "TimingLog.h"
#include "Tracking.h"

namespace pmslam_app
{
/** What the summary reports beside the SLAM's own counters. */
struct RunFacts
{
	const Input& input;
	const SlamRun& run;
	const TimingLog& timing;
	const LiveStatistics* live;	 // --live only
	UntrackedSpans untracked;
	bool trackingLost;
	std::size_t snapshots;
	double finishSeconds, wallSeconds;	// the final loop closure; the whole run
	double releasedMB;	// start-up library pages given back
};

void printSummary(const Options& options, const RunFacts& facts);

/** 0 done, 1 failed while running, 130 interrupted, 3 tracking lost for more than --max-untracked (said on
 * stderr). */
int exitStatus(const Options& options, const RunEnd& end, const RunFacts& facts);

}  // namespace pmslam_app
