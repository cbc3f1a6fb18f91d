/* pm-slam-app — the --gui window plugin loader (see LiveViewer.h). */
#include "LiveViewer.h"

#include <dlfcn.h>

#include <filesystem>
#include <vector>

namespace pmslam_app
{
namespace
{
std::filesystem::path executableDir()
{
	std::error_code ec;
	const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
	return ec ? std::filesystem::path(".") : exe.parent_path();
}
}  // namespace

LiveViewer::LiveViewer(const std::string& title)
{
	const auto dir = executableDir();
	const std::vector<std::filesystem::path> candidates = {dir / "libpmslam-viewer.so",
														   dir / PMSLAM_VIEWER_RELATIVE_TO_BIN / "libpmslam-viewer.so"};
	std::string tried;
	for (const auto& c : candidates)
	{
		tried += (tried.empty() ? "" : ", ") + c.lexically_normal().string();
		if ((m_library = ::dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL))) break;
	}
	if (!m_library)
	{
		m_error = "the window plugin libpmslam-viewer.so was not found (tried " + tried + ")";
		return;
	}
	using OpenFn = void* (*)(const char*);
	const auto open = reinterpret_cast<OpenFn>(::dlsym(m_library, "pmslam_viewer_open"));
	m_show = reinterpret_cast<void (*)(void*, const mrpt::img::CImage*)>(::dlsym(m_library, "pmslam_viewer_show"));
	m_close = reinterpret_cast<void (*)(void*)>(::dlsym(m_library, "pmslam_viewer_close"));
	m_wait = reinterpret_cast<void (*)(void*, int (*)(void*), void*)>(::dlsym(m_library, "pmslam_viewer_wait"));
	if (!open || !m_show || !m_close || !m_wait)
	{
		m_error = "libpmslam-viewer.so lacks the pmslam_viewer_* entry points";
		return;
	}
	m_window = open(title.c_str());
	if (!m_window) m_error = "the window could not be opened";
}

LiveViewer::~LiveViewer()
{
	if (m_window) m_close(m_window);
	// The library stays loaded: GUI toolkits keep threads and atexit handlers in it.
}

void LiveViewer::waitUntilClosed(const std::function<bool()>& stop)
{
	if (!m_window) return;
	m_wait(
		m_window, [](void* f) { return int((*static_cast<const std::function<bool()>*>(f))()); },
		const_cast<std::function<bool()>*>(&stop));
}

void LiveViewer::show(const mrpt::img::CImage& image)
{
	if (m_window) m_show(m_window, &image);
}

}  // namespace pmslam_app
