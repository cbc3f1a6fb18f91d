/* pm-slam-app — --gui (see GuiView.h). */
#include "GuiView.h"

#include <mrpt/poses/CPose2D.h>
#include <pmslam/io/MapExport.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <vector>

#include "Options.h"
#include "SlamRun.h"
#include "StopSignal.h"

namespace pmslam_app
{
namespace
{
// The view's longest side (pixels): a larger map is shown shrunk (each pixel its block's darkest cell).
constexpr int kGuiMaxSide = 1600;
}  // namespace

GuiView::GuiView(const std::string& log, const pmslam::ScanPointsOptions& scanOptions) : m_scanOptions(scanOptions)
{
	if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
	{
		say("warning: --gui needs a display (DISPLAY is not set); running headless");
		return;
	}
	m_window = std::make_unique<LiveViewer>("pm-slam-app: " + log);
	if (!m_window->isOpen())
	{
		say("warning: --gui: " + m_window->error() + "; running headless");
		m_window.reset();
	}
}

void GuiView::onScan(const ScanStep& s)
{
	if (!m_window || std::chrono::steady_clock::now() - m_last <= m_period) return;
	const auto renderStart = std::chrono::steady_clock::now();
	// The current scan's returns, placed at the pose SLAM gave it.
	const auto& traj = s.run.trajectory();
	std::vector<mrpt::math::TPoint2D> scanInMap;
	const mrpt::poses::CPose2D pose(traj.back().x, traj.back().y, traj.back().yaw);
	for (const auto& p : pmslam::scanToPoints(*s.event.scan, m_scanOptions).hits)
	{
		double wx, wy;
		pose.composePoint(p.x, p.y, wx, wy);
		scanInMap.emplace_back(wx, wy);
	}
	// With loop closure: the trajectory as the graph has it now, and the closures in blue.
	m_window->show(pmslam::renderMap(s.run.slam().grid(), s.run.corrected(traj), scanInMap, s.run.loopLinks(), kGuiMaxSide));
	m_last = std::chrono::steady_clock::now();
	// The view takes at most a tenth of the time: a large map is redrawn less often, and a live
	// run never falls behind its sensors for the window's sake.
	m_period = std::max<std::chrono::steady_clock::duration>(std::chrono::milliseconds(500), 10 * (m_last - renderStart));
}

void GuiView::showFinalAndWait(const SlamRun& run)
{
	if (!m_window) return;
	m_window->show(pmslam::renderMap(run.slam().grid(), run.trajectory(), {}, run.loopLinks(), kGuiMaxSide));
	std::cout << "Close the window or press a key in it to exit." << std::endl;
	const unsigned stops = stopCount();
	m_window->waitUntilClosed([stops] { return stopCount() != stops; });
	m_window.reset();
}

}  // namespace pmslam_app
