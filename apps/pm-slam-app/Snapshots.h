/* pm-slam-app — --snapshot-every S: pose.txt, trajectory.txt and the map (map.png; map.pgm + map.yaml
 * unless localising) written every S seconds of wall time while running, each atomically, so that
 * another program can watch a long or live run. */
#pragma once

#include <chrono>
#include <cstddef>

#include "Options.h"
#include "ProgressLine.h"
#include "ScanObserver.h"

namespace pmslam_app
{
class Snapshots : public ScanObserver
{
   public:
	Snapshots(const Options& options, pmslam::ProgressLine& progress);
	void onScan(const ScanStep& step) override;
	std::size_t written() const { return m_written; }

   private:
	void write(const SlamRun& run);

	const Options& m_options;
	pmslam::ProgressLine& m_progress;
	std::chrono::steady_clock::time_point m_last = std::chrono::steady_clock::now();
	std::size_t m_written = 0;
};

}  // namespace pmslam_app
