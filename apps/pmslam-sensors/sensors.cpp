/* libpmslam-sensors.so — pm-slam-app's --live sensors: MRPT's own drivers (mrpt-hwdrivers), configured as for
 * rawlog-grabber, each polled in its own thread. A plugin, so that log runs never load the driver stack
 * (see apps/pm-slam-app/LiveSensors.h for the contract).
 *
 * Every section of SENSORS.ini but [global] is a sensor: `driver` names its CGenericSensor class, the other keys are
 * the driver's own (process_rate, IP_DIR, ...). A sensor is connected once it delivered its first observation:
 * MRPT's laser drivers report a failed connection in their log, not by throwing. One that stays silent for
 * `silence` seconds (or throws, or reports ssError) is torn down and created anew, with a growing pause between tries.
 */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/system/COutputLogger.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;
using PushFn = void (*)(void* ctx, const mrpt::serialization::CSerializable::Ptr* obj);
using NoteFn = void (*)(void* ctx, const char* message);

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string oneLine(std::string s)
{
	for (char& c : s)
		if (c == '\n' || c == '\r' || c == '\t') c = ' ';
	while (!s.empty() && s.back() == ' ') s.pop_back();
	const auto b = s.find_first_not_of(' ');
	s = b == std::string::npos ? std::string() : s.substr(b);
	return s.size() > 240 ? s.substr(0, 237) + "..." : s;
}

class Hub;

struct Sensor
{
	std::string section, driver;
	std::thread thread;
	// Start-up: set by the thread, read by start() under the hub's mutex.
	bool connected = false;
	std::string lastError;
};

class Hub
{
   public:
	Hub(const std::string& ini, void* ctx, PushFn push, NoteFn note, double connectTimeout, double silence)
		: m_ini(ini), m_ctx(ctx), m_push(push), m_note(note), m_connectTimeout(connectTimeout), m_silence(silence)
	{
	}

	~Hub() { stop(); }

	/** Empty on success, else the one-line error. */
	std::string start()
	{
		std::vector<std::string> sections;
		m_cfg.getAllSections(sections);
		for (const auto& s : sections)
		{
			if (s == "global" || s.empty()) continue;  // rawlog-grabber's own settings
			const std::string driver = m_cfg.read_string(s, "driver", "");
			if (driver.empty())
				return m_ini + ": [" + s + "]: no 'driver' key (expected e.g. driver = CHokuyoURG, the MRPT sensor class)";
			if (!mrpt::hwdrivers::CGenericSensor::createSensorPtr(driver))
				return m_ini + ": [" + s + "]: driver = " + driver + ": not a sensor class of MRPT's hwdrivers";
			auto sensor = std::make_unique<Sensor>();
			sensor->section = s;
			sensor->driver = driver;
			m_sensors.push_back(std::move(sensor));
		}
		if (m_sensors.empty()) return m_ini + ": no sensor section (expected [NAME] sections with driver = ...)";
		// Configuration errors show at once: one trial load per sensor, before any thread.
		for (const auto& s : m_sensors)
		{
			auto probe = mrpt::hwdrivers::CGenericSensor::createSensorPtr(s->driver);
			try
			{
				probe->loadConfig(m_cfg, s->section);
			}
			catch (const std::exception& e)
			{
				return m_ini + ": [" + s->section + "] (" + s->driver + "): " + oneLine(lastMessage(e.what()));
			}
			if (!(probe->getProcessRate() > 0))
				return m_ini + ": [" + s->section + "]: process_rate must be set (Hz, > 0), as for rawlog-grabber";
		}
		const auto t0 = Clock::now();
		for (auto& s : m_sensors) s->thread = std::thread([this, p = s.get()] { run(*p); });
		// Until every sensor delivered its first observation, or the time is up.
		std::unique_lock<std::mutex> lock(m_mutex);
		m_cv.wait_for(lock, std::chrono::duration<double>(m_connectTimeout), [&] {
			return std::all_of(m_sensors.begin(), m_sensors.end(), [](const auto& s) { return s->connected; });
		});
		for (const auto& s : m_sensors)
			if (!s->connected)
			{
				char b[64];
				std::snprintf(b, sizeof b, "%.0f", since(t0));
				const std::string why = s->lastError.empty() ? "" : " (last driver message: " + s->lastError + ")";
				lock.unlock();
				stop();
				return m_ini + ": [" + s->section + "] (" + s->driver + "): no data within " + b +
					   " s: is the sensor connected and powered, and are its address keys right?" + why;
			}
		return {};
	}

	void stop()
	{
		m_stop = true;
		m_cv.notify_all();
		for (auto& s : m_sensors)
			if (s->thread.joinable()) s->thread.join();
	}

	bool load()
	{
		try
		{
			m_cfg.setFileName(m_ini);
			return true;
		}
		catch (const std::exception&)
		{
			return false;
		}
	}

   private:
	static std::string lastMessage(const std::string& what)
	{
		// MRPT exceptions carry a stack of "file:line: ..." frames; the message is the useful part.
		std::string best;
		std::size_t pos = 0;
		while (pos < what.size())
		{
			auto end = what.find('\n', pos);
			if (end == std::string::npos) end = what.size();
			std::string l = oneLine(what.substr(pos, end - pos));
			if (l.rfind("Message:", 0) == 0) l = oneLine(l.substr(8));
			if (!l.empty() && l.find("=====") == std::string::npos && l.rfind("[", 0) != 0) best = l;
			pos = end + 1;
		}
		return best.empty() ? oneLine(what) : best;
	}

	void note(const Sensor& s, const std::string& what)
	{
		m_note(m_ctx, ("sensor [" + s.section + "] (" + s.driver + "): " + what).c_str());
	}

	bool sleepFor(double seconds)
	{
		std::unique_lock<std::mutex> lock(m_mutex);
		return !m_cv.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return m_stop.load(); });
	}

	void run(Sensor& s)
	{
		double pause = 0.5;	 // between connection attempts, doubling to 5 s
		bool everConnected = false;
		auto lostAt = Clock::now();
		while (!m_stop)
		{
			auto sensor = mrpt::hwdrivers::CGenericSensor::createSensorPtr(s.driver);
			// The driver's own warnings and errors become notes, once each until it connects.
			std::string lastLog;
			if (auto* logger = dynamic_cast<mrpt::system::COutputLogger*>(sensor.get()))
			{
				logger->logging_enable_console_output = false;
				logger->logRegisterCallback([&](std::string_view msg, mrpt::system::VerbosityLevel level,
												std::string_view, const mrpt::Clock::time_point&) {
					if (level < mrpt::system::LVL_WARN) return;
					const std::string m = oneLine(std::string(msg));
					if (m.empty() || m == lastLog) return;
					lastLog = m;
					{
						std::lock_guard<std::mutex> lock(m_mutex);
						s.lastError = m;
					}
					if (everConnected) note(s, m);
				});
			}
			bool failed = false;
			std::string why;
			try
			{
				sensor->loadConfig(m_cfg, s.section);
				sensor->initialize();
			}
			catch (const std::exception& e)
			{
				failed = true;
				why = lastMessage(e.what());
			}
			const double period = 1.0 / std::max(1e-3, sensor->getProcessRate());
			auto lastData = Clock::now();
			auto next = Clock::now();
			bool gotData = false;
			while (!failed && !m_stop)
			{
				try
				{
					sensor->doProcess();
				}
				catch (const std::exception& e)
				{
					why = lastMessage(e.what());
					break;
				}
				if (sensor->getState() == mrpt::hwdrivers::CGenericSensor::ssError)
				{
					why = "the driver reports an error" + (lastLog.empty() ? std::string() : ": " + lastLog);
					break;
				}
				mrpt::hwdrivers::CGenericSensor::TListObservations objs;
				sensor->getObservations(objs);
				for (const auto& [t, obj] : objs)
				{
					(void)t;
					if (!obj) continue;
					if (!gotData)
					{
						gotData = true;
						if (everConnected)
						{
							char b[64];
							std::snprintf(b, sizeof b, "reconnected after %.1f s", since(lostAt));
							note(s, b);
						}
						everConnected = true;
						pause = 0.5;
						{
							std::lock_guard<std::mutex> lock(m_mutex);
							s.connected = true;
						}
						m_cv.notify_all();
					}
					m_push(m_ctx, &obj);
					lastData = Clock::now();
				}
				if (since(lastData) > m_silence)
				{
					char b[64];
					std::snprintf(b, sizeof b, "no data for %.1f s", since(lastData));
					why = b;
					break;
				}
				next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period));
				if (next < Clock::now()) next = Clock::now();
				std::unique_lock<std::mutex> lock(m_mutex);
				if (m_cv.wait_until(lock, next, [&] { return m_stop.load(); })) break;
			}
			if (m_stop) break;
			if (gotData) lostAt = Clock::now();
			if (everConnected)
				note(s, (gotData ? "connection lost (" : "reconnection failed (") + oneLine(why) + "): retrying");
			else if (!why.empty())
			{
				std::lock_guard<std::mutex> lock(m_mutex);
				s.lastError = oneLine(why);
			}
			sensor.reset();	 // closes the device before the next attempt
			if (!sleepFor(pause)) break;
			pause = std::min(5.0, 2 * pause);
		}
	}

	std::string m_ini;
	mrpt::config::CConfigFile m_cfg;
	void* m_ctx;
	PushFn m_push;
	NoteFn m_note;
	double m_connectTimeout, m_silence;
	std::vector<std::unique_ptr<Sensor>> m_sensors;
	std::mutex m_mutex;
	std::condition_variable m_cv;
	std::atomic<bool> m_stop{false};
};

}  // namespace

extern "C"
{
	/** Starts the sensors of `ini`; on failure returns null with the one-line reason in `error`. */
	__attribute__((visibility("default"))) void* pmslam_sensors_start(const char* ini, void* ctx, PushFn push,
																	   NoteFn note, double connectTimeout,
																	   double silence, char* error, size_t errorSize)
	{
		auto hub = std::make_unique<Hub>(ini, ctx, push, note, connectTimeout, silence);
		std::string err = hub->load() ? hub->start() : std::string(ini) + ": cannot read the file";
		if (err.empty()) return hub.release();
		std::snprintf(error, errorSize, "%s", err.c_str());
		return nullptr;
	}

	__attribute__((visibility("default"))) void pmslam_sensors_stop(void* hub) { delete static_cast<Hub*>(hub); }
}
