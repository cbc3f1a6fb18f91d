/* libpmslam-viewer.so — pm-slam-app's --gui window (MRPT CDisplayWindow), a plugin so
 * that headless runs never load MRPT's GUI stack (see apps/pm-slam-app/LiveViewer.h). */
#include <mrpt/gui/CDisplayWindow.h>
#include <mrpt/img/CImage.h>

#include <chrono>
#include <exception>
#include <iostream>
#include <thread>

extern "C"
{
	__attribute__((visibility("default"))) void* pmslam_viewer_open(const char* title)
	{
		try
		{
			return new mrpt::gui::CDisplayWindow::Ptr(mrpt::gui::CDisplayWindow::Create(title));
		}
		catch (const std::exception& e)
		{
			std::cerr << "pm-slam-app: warning: cannot open the window: " << e.what() << "\n";
			return nullptr;
		}
	}

	__attribute__((visibility("default"))) void pmslam_viewer_show(void* window, const mrpt::img::CImage* image)
	{
		if (window && image) (*static_cast<mrpt::gui::CDisplayWindow::Ptr*>(window))->showImage(*image);
	}

	/** Until a key is pressed in the window, it is closed, or stop(context) returns non-zero. Not MRPT's
	 * waitForKey(): that also returns on input at the program's stdin, at once when stdin is no terminal
	 * (a pipe, /dev/null), so the final map could not be looked at. */
	__attribute__((visibility("default"))) void pmslam_viewer_wait(void* window, int (*stop)(void*), void* context)
	{
		if (!window) return;
		auto& w = *static_cast<mrpt::gui::CDisplayWindow::Ptr*>(window);
		w->clearKeyHitFlag();
		while (w->isOpen() && !w->keyHit() && !(stop && stop(context)))
			std::this_thread::sleep_for(std::chrono::milliseconds(20));
	}

	__attribute__((visibility("default"))) void pmslam_viewer_close(void* window)
	{
		delete static_cast<mrpt::gui::CDisplayWindow::Ptr*>(window);
	}
}
