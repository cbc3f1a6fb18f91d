/* pm-slam-app — --live: how the SLAM keeps up with its sensors (see LiveStatistics.h). */
#include "LiveStatistics.h"

#include <mrpt/core/Clock.h>
#include <mrpt/system/datetime.h>
#include <pmslam/util/RunStatistics.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "SlamRun.h"

namespace pmslam_app
{
LiveStatistics::LiveStatistics(const Input& input, const Options& options, pmslam::ProgressLine& progress)
	: m_input(input), m_options(options), m_progress(progress)
{
}

void LiveStatistics::onScan(const ScanStep& s)
{
	if (s.event.scan->timestamp != INVALID_TIMESTAMP)
		m_latencyMs.push_back(1e3 * mrpt::system::timeDifference(s.event.scan->timestamp, mrpt::Clock::now()));
	warnAboutDrops(s.event.timestamp);
	m_progress.updateText([&] { return progressText(s); });
}

void LiveStatistics::warnAboutDrops(double timestamp)
{
	const auto c = m_input.pending()->counts();
	// Falling behind the sensors: said at once, then at most every 5 s while it goes on.
	if (c.droppedScans > m_droppedWarned &&
		std::chrono::steady_clock::now() - m_lastDropWarning > std::chrono::seconds(5))
	{
		m_progress.clear();
		std::fprintf(stderr,
					 "pm-slam-app: warning: at t=%.3f the SLAM fell behind the sensors: %zu scans dropped "
					 "unprocessed so far (the oldest pending; at most --max-pending %zu wait)\n",
					 timestamp, c.droppedScans, m_options.maxPending);
		m_droppedWarned = c.droppedScans;
		m_lastDropWarning = std::chrono::steady_clock::now();
	}
}

std::string LiveStatistics::progressText(const ScanStep& s) const
{
	const auto c = m_input.pending()->counts();
	const auto& traj = s.run.trajectory();
	std::vector<double> recent(m_latencyMs.end() - std::min<std::size_t>(m_latencyMs.size(), 400), m_latencyMs.end());
	double deg = std::round(mrpt::RAD2DEG(traj.back().yaw));
	if (deg == 0) deg = 0;	// not "-0"
	char b[256];
	std::snprintf(b, sizeof b,
				  "received %zu scans, processed %zu, dropped %zu; latency p50 %.1f ms, p99 %.1f ms; "
				  "pose %.2f %.2f %.0f deg",
				  c.scans, traj.size(), c.droppedScans, pmslam::percentile(recent, 0.5),
				  pmslam::percentile(recent, 0.99), traj.back().x, traj.back().y, deg);
	return b;
}

void LiveStatistics::printSummary(std::size_t processed) const
{
	const auto c = m_input.pending()->counts();
	std::printf("  live: %zu objects received (%zu scans) from %s; %zu scans processed, %zu dropped because the "
				"SLAM was behind (at most %zu pending); latency from a scan's timestamp to its pose: p50 %.1f ms, "
				"p99 %.1f ms, max %.1f ms\n",
				c.received, c.scans, m_options.live.c_str(), processed, c.droppedScans, m_options.maxPending,
				pmslam::percentile(m_latencyMs, 0.5), pmslam::percentile(m_latencyMs, 0.99),
				m_latencyMs.empty() ? 0.0 : *std::max_element(m_latencyMs.begin(), m_latencyMs.end()));
	if (const auto* recorder = m_input.recorder())
		std::printf("  recorded %zu objects to %s%s\n", recorder->objects(), m_options.record.c_str(),
					m_input.recordFailed() ? " (INCOMPLETE: writing failed)"
					: c.droppedScans		? " (it holds the dropped scans too: an offline run on it maps them)"
											: " (pm-slam-app on it reproduces this trajectory)");
}

}  // namespace pmslam_app
