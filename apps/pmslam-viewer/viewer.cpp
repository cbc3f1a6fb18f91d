/* libpmslam-viewer.so — pm-slam-app's --gui window (MRPT CDisplayWindow), a plugin so
 * that headless runs never load MRPT's GUI stack (see apps/pm-slam-app/LiveViewer.h). */
#include <mrpt/gui/CDisplayWindow.h>
#include <mrpt/img/CImage.h>

#include <exception>
#include <iostream>

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

	__attribute__((visibility("default"))) void pmslam_viewer_wait_for_key(void* window)
	{
		if (window) (*static_cast<mrpt::gui::CDisplayWindow::Ptr*>(window))->waitForKey();
	}

	__attribute__((visibility("default"))) void pmslam_viewer_close(void* window)
	{
		delete static_cast<mrpt::gui::CDisplayWindow::Ptr*>(window);
	}
}
