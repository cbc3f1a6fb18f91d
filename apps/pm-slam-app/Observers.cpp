/* pm-slam-app — everything that watches a run (see Observers.h). */
#include "Observers.h"

namespace pmslam_app
{
Observers::Observers(const Options& options, const Input& input, pmslam::ProgressLine& line, const Hooks& hooks,
					 GuiView* gui)
	: live(options.isLive() ? std::make_unique<LiveStatistics>(input, options, line) : nullptr),
	  progress(line),
	  newGround(line),
	  snapshots(options, line)
{
	for (const auto& h : hooks.observers) inOrder.push_back(h.get());
	inOrder.push_back(live ? static_cast<ScanObserver*>(live.get()) : &progress);
	inOrder.insert(inOrder.end(), {&newGround, &timing, &snapshots});
	if (gui && gui->isOpen()) inOrder.push_back(gui);
}

}  // namespace pmslam_app
