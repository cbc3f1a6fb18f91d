/* pm-slam-app — what watches the run scan by scan: the progress line, the live statistics, the timing
 * file, the snapshots, the --gui window (and, in pm-slam-app-instrumented, the test hooks). The run loop
 * (RunLoop.h) hands each of them every scan, in the order given. */
#pragma once

#include <pmslam/io/LogReader.h>
#include <pmslam/slam/PerfectMatchSlam.h>

namespace pmslam_app
{
class SlamRun;

/** One scan just processed: the log's event, the SLAM's result, and the run (its trajectory ends with
 * the scan's pose). */
struct ScanStep
{
	const pmslam::LogEvent& event;
	const pmslam::PerfectMatchSlam::ScanResult& result;
	const SlamRun& run;
};

class ScanObserver
{
   public:
	virtual ~ScanObserver() = default;
	virtual void onScan(const ScanStep& step) = 0;
};

}  // namespace pmslam_app
