/* pm-slam-app — --gui: the map, the current scan and the trajectory in a window while running (at most
 * a tenth of the time goes to it), and at the end the final map, shown until the window is closed or a
 * key is pressed in it. Without a display, or without the window plugin, the run goes on headless with
 * a warning. */
#pragma once

#include <pmslam/sensor/ScanPoints.h>

#include <chrono>
#include <memory>
#include <string>

#include "LiveViewer.h"
#include "ScanObserver.h"

namespace pmslam_app
{
class GuiView : public ScanObserver
{
   public:
	/** Opens the window (title: `log`); `scanOptions` place a scan's returns as the map has them. */
	GuiView(const std::string& log, const pmslam::ScanPointsOptions& scanOptions);
	bool isOpen() const { return m_window != nullptr; }
	void onScan(const ScanStep& step) override;
	/** Shows the final map and trajectory, then waits until the window is closed, a key is pressed in
	 * it or a stop signal arrives. */
	void showFinalAndWait(const SlamRun& run);

   private:
	pmslam::ScanPointsOptions m_scanOptions;
	std::unique_ptr<LiveViewer> m_window;
	std::chrono::steady_clock::time_point m_last = std::chrono::steady_clock::now();
	std::chrono::steady_clock::duration m_period = std::chrono::milliseconds(500);
};

}  // namespace pmslam_app
