/* pm-slam-app — the run (see RunLoop.h). */
#include "RunLoop.h"

#include "StopSignal.h"

namespace pmslam_app
{
RunEnd runLoop(pmslam::LogReader& reader, SlamRun& run, const std::vector<ScanObserver*>& observers, bool live,
			   std::size_t maxScans)
{
	try
	{
		pmslam::LogEvent ev;
		while ((live || !stopRequested()) && reader.next(ev))
		{
			const auto* r = run.process(ev);
			if (!r) continue;
			for (auto* o : observers) o->onScan({ev, *r, run});
			if (maxScans && run.trajectory().size() >= maxScans) break;
		}
	}
	catch (const std::exception& e)
	{
		return {true, e.what()};
	}
	return {};
}

}  // namespace pmslam_app
