/* libpmslam-sensors.so — pm-slam-app's --live sensors: MRPT's own drivers (mrpt-hwdrivers), configured as for
 * rawlog-grabber, each polled in its own thread. A plugin, so that log runs never load the driver stack
 * (see apps/pm-slam-app/LiveSensors.h for the contract).
 *
 * Every section of SENSORS.ini but [global] is a sensor: `driver` names its CGenericSensor class, the other keys are
 * the driver's own (process_rate, IP_DIR, ...). A sensor is connected once it delivered its first observation:
 * MRPT's laser drivers report a failed connection in their log, not by throwing. One that stays silent for
 * `silence` seconds (or throws, or reports ssError) is torn down and created anew, with a growing pause between tries.
 *
 * A driver call that blocks (MRPT 2.5's CHokuyoURG after a sensor was unplugged for a while, CLMS100Eth's
 * initialize() on garbage) cannot be interrupted: a watchdog abandons that thread — whatever it returns later is
 * discarded — and starts the driver anew in a fresh one. Threads still blocked at the end are reported as stuck.
 *
 * Two defects of MRPT 2.5's CLMS100Eth are mended here, measured against an emulator that speaks the LMS1xx
 * telegram (tests/support/lidar_emulator): it labels the scans left-to-right (rightToLeft = false), but an LMS1xx
 * sends its points in increasing angle, counter-clockwise seen from above (as SICK documents and ROS's LMS1xx
 * driver reads them), so every scan would be mirrored; and once its connection drops it returns empty scans forever
 * instead of reconnecting. Scans with fewer than 2 beams are not data: a sensor sending only those is silent.
 */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/system/COutputLogger.h>
#include <pmslam/util/ExceptionText.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
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

struct Worker
{
	std::thread thread;
	bool finished = false;	// under the hub's mutex
};

struct Sensor
{
	std::string section, driver;
	std::vector<std::unique_ptr<Worker>> workers;  // the current one last; earlier ones abandoned
	unsigned generation = 0;  // of the current worker; an abandoned worker's data are discarded
	bool connected = false;	// delivered data once
	std::string lastError;
	Clock::time_point lastData = Clock::now();	// the last observation delivered (by any worker)
	Clock::time_point busySince{};	// the current worker entered a driver call then (epoch: not inside one)
	double busyLimit = 0;  // s that call may take
	double startSeconds = -1;  // how long the driver's start (loadConfig + initialize) took when it worked
};

class Hub
{
   public:
	Hub(const std::string& ini, void* ctx, PushFn push, NoteFn note, double connectTimeout, double silence)
		: m_ini(ini), m_ctx(ctx), m_push(push), m_note(note), m_connectTimeout(connectTimeout), m_silence(silence)
	{
	}

	~Hub() { stop(); }	 // only once no thread is stuck (see pmslam_sensors_stop)

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
				return m_ini + ": [" + s->section + "] (" + s->driver + "): " + pmslam::exceptionSummary(e.what());
			}
			if (!(probe->getProcessRate() > 0))
				return m_ini + ": [" + s->section + "]: process_rate must be set (Hz, > 0), as for rawlog-grabber";
		}
		const auto t0 = Clock::now();
		{
			std::lock_guard<std::mutex> lock(m_mutex);
			for (auto& s : m_sensors) launch(*s);
		}
		m_watchdog = std::thread([this] { watch(); });
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
				const std::string msg = m_ini + ": [" + s->section + "] (" + s->driver + "): no data within " + b +
										" s: is the sensor connected and powered, and are its address keys right?" + why;
				lock.unlock();
				m_stuck = stop();
				return msg;
			}
		return {};
	}

	/** Stops the threads; returns how many are stuck inside their driver: those are detached, and the hub
	 * must then outlive them. */
	std::size_t stop()
	{
		{
			std::lock_guard<std::mutex> lock(m_mutex);
			if (m_stopped) return m_stuck;
			m_stopped = true;
			m_stop = true;
		}
		m_cv.notify_all();
		if (m_watchdog.joinable()) m_watchdog.join();
		std::unique_lock<std::mutex> lock(m_mutex);
		auto allFinished = [&] {
			for (const auto& s : m_sensors)
				for (const auto& w : s->workers)
					if (!w->finished) return false;
			return true;
		};
		m_cv.wait_for(lock, std::chrono::seconds(3), allFinished);
		std::size_t stuck = 0;
		for (auto& s : m_sensors)
			for (auto& w : s->workers)
			{
				if (!w->thread.joinable()) continue;
				if (w->finished)
				{
					lock.unlock();
					w->thread.join();
					lock.lock();
				}
				else
				{
					w->thread.detach();
					++stuck;
				}
			}
		m_stuck = stuck;
		return stuck;
	}

	std::size_t stuck() const { return m_stuck; }

   private:
	void note(const Sensor& s, const std::string& what)
	{
		m_note(m_ctx, ("sensor [" + s.section + "] (" + s.driver + "): " + what).c_str());
	}

	/** Starts a worker for `s` (under m_mutex); any earlier worker is abandoned. */
	void launch(Sensor& s)
	{
		const unsigned gen = ++s.generation;
		s.busySince = Clock::time_point{};
		auto w = std::make_unique<Worker>();
		Worker* wp = w.get();
		s.workers.push_back(std::move(w));
		wp->thread = std::thread([this, &s, gen, wp] {
			run(s, gen);
			std::lock_guard<std::mutex> lock(m_mutex);
			wp->finished = true;
			m_cv.notify_all();
		});
	}

	/** Abandons a worker blocked in one driver call for longer than the silence allows, and starts anew. */
	void watch()
	{
		std::unique_lock<std::mutex> lock(m_mutex);
		while (!m_cv.wait_for(lock, std::chrono::milliseconds(250), [&] { return m_stop.load(); }))
			for (auto& s : m_sensors)
			{
				if (s->busySince == Clock::time_point{} || since(s->busySince) < s->busyLimit) continue;
				char b[200];
				std::snprintf(b, sizeof b,
							  "no data for %.1f s (a driver call has not returned for %.1f s): left behind, the driver "
							  "is started anew",
							  since(s->lastData), since(s->busySince));
				if (s->connected) note(*s, b);
				launch(*s);
			}
	}

	bool current(const Sensor& s, unsigned gen)
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		return s.generation == gen && !m_stop;
	}

	/** Runs `f` as one driver call that may take `limit` s, watched: false if this worker was abandoned. */
	template <class F>
	bool driverCall(Sensor& s, unsigned gen, double limit, F&& f)
	{
		{
			std::lock_guard<std::mutex> lock(m_mutex);
			if (s.generation != gen) return false;
			s.busySince = Clock::now();
			s.busyLimit = limit;
		}
		f();
		std::lock_guard<std::mutex> lock(m_mutex);
		if (s.generation != gen) return false;
		s.busySince = Clock::time_point{};
		return true;
	}

	bool sleepFor(double seconds)
	{
		std::unique_lock<std::mutex> lock(m_mutex);
		return !m_cv.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return m_stop.load(); });
	}

	/** The driver's own warnings and errors become notes (each once in a row) once it delivered data; the
	 * latest is returned (kept up to date) for the messages of a failure. */
	std::shared_ptr<std::string> captureLog(mrpt::hwdrivers::CGenericSensor& sensor, Sensor& s, unsigned gen)
	{
		auto lastLog = std::make_shared<std::string>();
		auto* logger = dynamic_cast<mrpt::system::COutputLogger*>(&sensor);
		if (!logger) return lastLog;
		logger->logging_enable_console_output = false;
		logger->logRegisterCallback([this, &s, gen, lastLog](std::string_view msg, mrpt::system::VerbosityLevel level,
															 std::string_view, const mrpt::Clock::time_point&) {
			if (level < mrpt::system::LVL_WARN) return;
			const std::string m = oneLine(std::string(msg));
			if (m.empty() || m == *lastLog) return;
			*lastLog = m;
			bool tell = false;
			{
				std::lock_guard<std::mutex> lock(m_mutex);
				if (s.generation != gen) return;
				s.lastError = m;
				tell = s.connected;
			}
			if (tell) note(s, m);
		});
		return lastLog;
	}

	/** The first data of a (re)connection: the sensor is connected (a reconnection is said). False when a
	 * newer worker has the sensor. */
	bool connected(Sensor& s, unsigned gen, double startTook)
	{
		bool wasConnected = false;
		double silent = 0;
		{
			std::lock_guard<std::mutex> lock(m_mutex);
			if (s.generation != gen) return false;
			wasConnected = s.connected;
			s.connected = true;
			silent = since(s.lastData);
			if (s.startSeconds < 0) s.startSeconds = startTook;
		}
		m_cv.notify_all();
		if (wasConnected)
		{
			char b[64];
			std::snprintf(b, sizeof b, "reconnected after %.1f s without data", silent);
			note(s, b);
		}
		return true;
	}

	void run(Sensor& s, unsigned gen)
	{
		double pause = 0.5;	 // between connection attempts, doubling to 5 s
		while (current(s, gen))
		{
			auto sensor = mrpt::hwdrivers::CGenericSensor::createSensorPtr(s.driver);
			const auto lastLog = captureLog(*sensor, s, gen);
			std::string why;
			bool ok = true;
			// Starting may take long (CLMS100Eth: 15 s), so the first start has all of --connect-timeout; a
			// restart as long as the first took, with a margin (CHokuyoURG's may hang); a poll must return
			// within a few sensor periods.
			double startLimit = m_connectTimeout;
			{
				std::lock_guard<std::mutex> lock(m_mutex);
				if (s.startSeconds >= 0) startLimit = std::max(5.0, 2 * s.startSeconds + 2);
			}
			const auto startedAt = Clock::now();
			if (!driverCall(s, gen, startLimit, [&] {
					try
					{
						sensor->loadConfig(m_cfg, s.section);
						sensor->initialize();
					}
					catch (const std::exception& e)
					{
						ok = false;
						why = pmslam::exceptionSummary(e.what());
					}
				}))
				return;	 // abandoned: a newer worker has the sensor
			const double startTook = since(startedAt);
			const double period = 1.0 / std::max(1e-3, sensor->getProcessRate());
			auto lastData = Clock::now();
			auto next = Clock::now();
			bool gotData = false;
			while (ok && current(s, gen))
			{
				mrpt::hwdrivers::CGenericSensor::TListObservations objs;
				bool threw = false;
				if (!driverCall(s, gen, std::max(3.0, 2 * m_silence), [&] {
						try
						{
							sensor->doProcess();
							sensor->getObservations(objs);
						}
						catch (const std::exception& e)
						{
							threw = true;
							why = pmslam::exceptionSummary(e.what());
						}
					}))
					return;
				if (threw) break;
				if (sensor->getState() == mrpt::hwdrivers::CGenericSensor::ssError && objs.empty())
				{
					why = "the driver reports an error" + (lastLog->empty() ? std::string() : ": " + *lastLog);
					break;
				}
				for (const auto& [t, obj] : objs)
				{
					(void)t;
					if (!obj) continue;
					if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obj))
					{
						if (scan->getScanSize() < 2) continue;	// not data (CLMS100Eth after a disconnect)
						if (s.driver == "CLMS100Eth") scan->rightToLeft = true;	 // see the top of this file
					}
					if (!gotData)
					{
						gotData = true;
						if (!connected(s, gen, startTook)) return;
						pause = 0.5;
					}
					{
						std::lock_guard<std::mutex> lock(m_mutex);
						if (s.generation != gen || m_stop) return;
						s.lastData = lastData = Clock::now();
					}
					m_push(m_ctx, &obj);
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
			if (!current(s, gen)) break;
			bool wasConnected = false;
			{
				std::lock_guard<std::mutex> lock(m_mutex);
				wasConnected = s.connected;
				if (!why.empty()) s.lastError = why;
			}
			if (wasConnected)
				note(s, (gotData ? "connection lost (" : "reconnection failed (") + why + "): retrying");
			// Closes the device before the next attempt (a destructor that talks to a dead device may hang too).
			if (!driverCall(s, gen, 5.0, [&] { sensor.reset(); })) return;
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
	bool m_stopped = false;
	std::size_t m_stuck = 0;
	std::thread m_watchdog;
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
		if (hub->stuck()) hub.release();  // a detached thread still uses it: left to the process's exit
		return nullptr;
	}

	/** Stops and frees the hub; returns how many sensor threads were stuck in their driver (then the hub is
	 * left allocated for them, and the caller should end the process without static destructors). */
	__attribute__((visibility("default"))) size_t pmslam_sensors_stop(void* hub)
	{
		auto* h = static_cast<Hub*>(hub);
		const std::size_t stuck = h->stop();
		if (!stuck) delete h;
		return stuck;
	}
}
