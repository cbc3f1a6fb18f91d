/* pm-slam-app — timing.txt: per scan the milliseconds spent and the tracking state. */
#pragma once

#include <string>
#include <vector>

#include "ScanObserver.h"

namespace pmslam_app
{
struct ScanTiming
{
	double timestamp, matchMs, updateMs, backendMs;
	bool matched, inserted;
	unsigned iterations;
	double goodness;
	int tracking;  // 0 matched, 1 not matched (below the insertion thresholds), 2 matched after a wide search moved it, 3 rejected, 4 new ground
	bool wideSearch;
};

/** The tracking state timing.txt gives a scan (see ScanTiming::tracking). */
int trackingState(const pmslam::PerfectMatchSlam::ScanResult& r);

class TimingLog : public ScanObserver
{
   public:
	void onScan(const ScanStep& step) override;
	const std::vector<ScanTiming>& scans() const { return m_scans; }
	/** Front-end milliseconds per scan (match + map update). */
	std::vector<double> frontEndMs() const;
	/** All the waits for the loop-closure back-end (ms). */
	double backendWaitMs() const;
	/** Writes timing.txt (atomically); throws on failure. */
	void write(const std::string& path, const std::string& header) const;

   private:
	std::vector<ScanTiming> m_scans;
};

}  // namespace pmslam_app
