/* pm-slam-app — everything that watches a run scan by scan, built for the options given, in the order
 * each scan is shown to them: the test hooks (pm-slam-app-instrumented only), the progress line or the
 * live statistics, the new-ground warning, the timing file, the snapshots and the --gui window. */
#pragma once

#include <memory>
#include <vector>

#include "GuiView.h"
#include "Hooks.h"
#include "Input.h"
#include "LiveStatistics.h"
#include "ProgressLine.h"
#include "Snapshots.h"
#include "TimingLog.h"
#include "Tracking.h"

namespace pmslam_app
{
struct Observers
{
	Observers(const Options& options, const Input& input, pmslam::ProgressLine& progress, const Hooks& hooks,
			  GuiView* gui);
	Observers(const Observers&) = delete;
	Observers& operator=(const Observers&) = delete;

	std::unique_ptr<LiveStatistics> live;  // --live only
	ScanProgress progress;
	NewGroundWarning newGround;
	TimingLog timing;
	Snapshots snapshots;
	std::vector<ScanObserver*> inOrder;
};

}  // namespace pmslam_app
