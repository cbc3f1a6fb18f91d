/* pm-slam-app — where tracking was lost (see Tracking.h). */
#include "Tracking.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "SlamRun.h"
#include "TimingLog.h"

namespace pmslam_app
{
void NewGroundWarning::onScan(const ScanStep& s)
{
	const bool onNewGround = trackingState(s.result) == 4;
	if (onNewGround && !m_onNewGround)
	{
		m_progress.clear();
		const auto& gaps = s.run.slam().trackingGaps();
		std::fprintf(stderr,
					 "pm-slam-app: warning: at t=%.3f, after %.1f s without an accepted match, the scans see new "
					 "ground only: inserted at the odometry pose from here, so the map grows on, but its alignment "
					 "with what was mapped before is not verified\n",
					 s.event.timestamp, gaps.empty() ? 0.0 : gaps.back().length());
	}
	m_onNewGround = onNewGround;
}

UntrackedSpans reportUntrackedSpans(const pmslam::PerfectMatchSlam& slam)
{
	UntrackedSpans u;
	for (const auto& g : slam.trackingGaps())
	{
		const double span = g.length();
		u.longest = std::max(u.longest, span);
		if (span <= kWarnUntrackedSeconds) continue;
		++u.warned;
		std::fprintf(stderr,
					 "pm-slam-app: warning: tracking lost from t=%.3f to t=%.3f (%.1f s of log, %zu rejected matches%s): "
					 "those poses follow odometry only and their scans are not in the map\n",
					 g.from, g.to, span, g.scans, g.open ? ", until the end of the log" : "");
	}
	return u;
}

}  // namespace pmslam_app
