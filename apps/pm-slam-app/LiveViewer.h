/* pm-slam-app — the --gui window, loaded only when asked for.
 *
 * MRPT's GUI library drags in wxWidgets, GTK and OpenGL: linking it into the app
 * costs every headless run ~23 MB of resident memory for nothing. The window
 * lives in a small plugin (libpmslam-viewer.so, next to the executable or in
 * LIBDIR/pmslam) that is dlopen()ed when --gui is given; without it, or without
 * a display, the run goes on headless with a warning.
 */
#pragma once

#include <mrpt/img/CImage.h>

#include <functional>
#include <string>

namespace pmslam_app
{
class LiveViewer
{
   public:
	/** Opens the window; on failure `error()` says why and show() does nothing. */
	explicit LiveViewer(const std::string& title);
	~LiveViewer();
	LiveViewer(const LiveViewer&) = delete;
	LiveViewer& operator=(const LiveViewer&) = delete;

	bool isOpen() const { return m_window != nullptr; }
	const std::string& error() const { return m_error; }
	void show(const mrpt::img::CImage& image);
	/** Blocks until a key is pressed in the window, the window is closed, or `stop` says so (polled a few
	 * times a second). Only the window counts: not the terminal (MRPT's own waitForKey() also returns on
	 * input at stdin, so it returned at once when stdin was no terminal). */
	void waitUntilClosed(const std::function<bool()>& stop);

   private:
	void* m_library = nullptr;
	void* m_window = nullptr;
	void (*m_show)(void*, const mrpt::img::CImage*) = nullptr;
	void (*m_close)(void*) = nullptr;
	void (*m_wait)(void*, int (*)(void*), void*) = nullptr;
	std::string m_error;
};

}  // namespace pmslam_app
