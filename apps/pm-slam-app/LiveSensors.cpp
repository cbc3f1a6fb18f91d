/* pm-slam-app — the --live sensor plugin loader (see LiveSensors.h). */
#include "LiveSensors.h"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>
#include <vector>

namespace pmslam_app
{
namespace
{
void pushObservation(void* ctx, const mrpt::serialization::CSerializable::Ptr* obj)
{
	static_cast<pmslam::PendingObservations*>(ctx)->push(*obj);
}
void noteEvent(void* ctx, const char* message) { static_cast<pmslam::PendingObservations*>(ctx)->note(message); }
}  // namespace

LiveSensors::LiveSensors(const std::string& ini, pmslam::PendingObservations& sink, double connectTimeout,
						 double silence)
{
	std::error_code ec;
	if (!std::filesystem::is_regular_file(ini, ec))
		throw std::runtime_error("--live " + ini + ": no such file (expected a rawlog-grabber sensor INI file)");
	const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
	const auto dir = ec ? std::filesystem::path(".") : exe.parent_path();
	const std::vector<std::filesystem::path> candidates = {dir / "libpmslam-sensors.so",
														   dir / PMSLAM_PLUGIN_RELATIVE_TO_BIN / "libpmslam-sensors.so"};
	std::string tried, dlError;
	for (const auto& c : candidates)
	{
		tried += (tried.empty() ? "" : ", ") + c.lexically_normal().string();
		if ((m_library = ::dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL))) break;
		if (const char* e = ::dlerror(); e && std::filesystem::exists(c)) dlError = std::string(": ") + e;
	}
	if (!m_library)
		throw std::runtime_error("--live: the sensor plugin libpmslam-sensors.so could not be loaded (tried " + tried +
								 ")" + dlError);
	using StartFn = void* (*)(const char*, void*, void (*)(void*, const mrpt::serialization::CSerializable::Ptr*),
							  void (*)(void*, const char*), double, double, char*, size_t);
	const auto start = reinterpret_cast<StartFn>(::dlsym(m_library, "pmslam_sensors_start"));
	m_stop = reinterpret_cast<std::size_t (*)(void*)>(::dlsym(m_library, "pmslam_sensors_stop"));
	if (!start || !m_stop) throw std::runtime_error("--live: libpmslam-sensors.so lacks the pmslam_sensors_* entry points");
	char error[1024] = "";
	m_hub = start(ini.c_str(), &sink, &pushObservation, &noteEvent, connectTimeout, silence, error, sizeof error);
	if (!m_hub) throw std::runtime_error(error);
}

std::size_t LiveSensors::stop()
{
	if (m_hub) m_stuck = m_stop(m_hub);
	m_hub = nullptr;
	return m_stuck;
}

LiveSensors::~LiveSensors()
{
	stop();
	// The library stays loaded: drivers may keep static state and atexit handlers in it.
}

}  // namespace pmslam_app
