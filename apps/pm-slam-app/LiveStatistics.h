/* pm-slam-app — --live: how the SLAM keeps up with its sensors. The latency from each scan's timestamp
 * (the driver's clock) to its pose, the scans dropped because the SLAM fell behind (warned about at once,
 * then at most every 5 s while it goes on), the progress line's text, and the summary's line. */
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "Input.h"
#include "ProgressLine.h"
#include "ScanObserver.h"

namespace pmslam_app
{
class LiveStatistics : public ScanObserver
{
   public:
	LiveStatistics(const Input& input, const Options& options, pmslam::ProgressLine& progress);
	void onScan(const ScanStep& step) override;
	/** The summary's "live:" line (and the recording's), on stdout. */
	void printSummary(std::size_t processed) const;

   private:
	void warnAboutDrops(double timestamp);
	std::string progressText(const ScanStep& step) const;

	const Input& m_input;
	const Options& m_options;
	pmslam::ProgressLine& m_progress;
	std::vector<double> m_latencyMs;
	std::size_t m_droppedWarned = 0;
	std::chrono::steady_clock::time_point m_lastDropWarning = std::chrono::steady_clock::now() - std::chrono::hours(1);
};

}  // namespace pmslam_app
