/* pm-slam-app — said loudly: where tracking was lost. While running, the moment the scans see new ground
 * only (inserted at the odometry pose from there); at the end, every stretch without an accepted match
 * longer than a few seconds of log, the longest of which decides exit status 3 (--max-untracked). */
#pragma once

#include <cstddef>

#include "ProgressLine.h"
#include "ScanObserver.h"

namespace pmslam_app
{
// A stretch without an accepted match longer than this (s of log) is warned about.
constexpr double kWarnUntrackedSeconds = 3.0;

/** Warns once per stretch of scans inserted on new ground. */
class NewGroundWarning : public ScanObserver
{
   public:
	explicit NewGroundWarning(pmslam::ProgressLine& progress) : m_progress(progress) {}
	void onScan(const ScanStep& step) override;

   private:
	pmslam::ProgressLine& m_progress;
	bool m_onNewGround = false;
};

struct UntrackedSpans
{
	double longest = 0;	 ///< s of log
	std::size_t warned = 0;	 ///< spans over kWarnUntrackedSeconds
};

/** Warns about each span of the run without an accepted match over kWarnUntrackedSeconds. */
UntrackedSpans reportUntrackedSpans(const pmslam::PerfectMatchSlam& slam);

}  // namespace pmslam_app
