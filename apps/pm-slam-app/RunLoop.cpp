/* pm-slam-app — the run (see RunLoop.h). */
#include "RunLoop.h"

#include "StopSignal.h"

namespace pmslam_app
{
RunEnd runLoop(pmslam::LogReader& reader, SlamRun& run, const std::vector<ScanObserver*>& observers, bool live,
			   std::size_t maxScans)
{
	// Each event through the SLAM, each scan's result to the observers; false at --max-scans.
	auto step = [&](const pmslam::LogEvent& ev) {
		const auto* r = run.process(ev);
		if (!r) return true;
		for (auto* o : observers) o->onScan({ev, *r, run});
		return !(maxScans && run.trajectory().size() >= maxScans);
	};
	try
	{
		pmslam::LogEvent ev;
		std::vector<pmslam::LogEvent> held;	 // while the start is searched (--localize without a start pose)
		bool more = true;
		while (more && (live || !stopRequested()) && reader.next(ev))
		{
			if (!run.findingStart())
			{
				more = step(ev);
				continue;
			}
			held.push_back(ev);
			if (!run.offerForStart(ev))
			{
				more = !run.startUndecided();
				continue;
			}
			for (std::size_t i = 0; more && i < held.size(); ++i) more = step(held[i]);  // from the first scan, now placed
			held.clear();
		}
	}
	catch (const std::exception& e)
	{
		return {true, e.what()};
	}
	return {};
}

}  // namespace pmslam_app
