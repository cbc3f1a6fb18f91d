/* pm-slam-app — timing.txt (see TimingLog.h). */
#include "TimingLog.h"

#include <pmslam/io/AtomicFile.h>

#include <cstdio>
#include <ostream>

namespace pmslam_app
{
int trackingState(const pmslam::PerfectMatchSlam::ScanResult& r)
{
	return r.reanchored ? 4 : r.rejected ? 3 : r.relocalized ? 2 : r.matched ? 0 : 1;
}

void TimingLog::onScan(const ScanStep& s)
{
	const auto& r = s.result;
	m_scans.push_back({s.event.timestamp, r.matchMs, r.updateMs, r.backendWaitMs, r.matched, r.inserted,
					   r.info.nIterations, r.info.goodness, trackingState(r), r.wideSearch});
}

std::vector<double> TimingLog::frontEndMs() const
{
	std::vector<double> total;
	total.reserve(m_scans.size());
	for (const auto& t : m_scans) total.push_back(t.matchMs + t.updateMs);
	return total;
}

double TimingLog::backendWaitMs() const
{
	double ms = 0;
	for (const auto& t : m_scans) ms += t.backendMs;
	return ms;
}

void TimingLog::write(const std::string& path, const std::string& header) const
{
	pmslam::writeFileAtomically(path, [&](std::ostream& out) {
		out << "# " << header
			<< "\n# timestamp match_ms update_ms total_ms matched inserted iterations goodness tracking wide_search"
			   "\n# tracking: 0 matched, 1 odometry only (moved less than the insertion thresholds), 2 matched after"
			   " the wide search moved it (re-localised), 3 match rejected (odometry only), 4 lost on new ground:"
			   " inserted at the odometry pose; backend_wait_ms: waiting for the loop-closure back-end (not in total_ms)\n";
		char line[200];
		for (const auto& t : m_scans)
		{
			std::snprintf(line, sizeof line, "%.6f %.4f %.4f %.4f %d %d %u %.4f %d %d %.4f\n", t.timestamp, t.matchMs,
						  t.updateMs, t.matchMs + t.updateMs, int(t.matched), int(t.inserted), t.iterations, t.goodness,
						  t.tracking, int(t.wideSearch), t.backendMs);
			out << line;
		}
	});
}

}  // namespace pmslam_app
