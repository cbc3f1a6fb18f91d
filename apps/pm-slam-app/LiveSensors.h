/* pm-slam-app — --live: the sensors of a rawlog-grabber SENSORS.ini, feeding a PendingObservations.
 *
 * MRPT's drivers (mrpt-hwdrivers, with libusb, libpcap, OpenNI2, ... behind it) live in a plugin,
 * libpmslam-sensors.so (next to the executable, or in LIBDIR/pmslam), dlopen()ed only for --live: a run on
 * a log never maps them. The plugin polls each sensor in its own thread and hands every observation to
 * PendingObservations::push (the queue that drops the oldest scans when the SLAM falls behind).
 */
#pragma once

#include <pmslam/live/PendingObservations.h>

#include <string>

namespace pmslam_app
{
class LiveSensors
{
   public:
	/** Starts every sensor of `ini` and waits until each delivered data (at most connectTimeout s). A sensor
	 * silent for `silence` s while running is reconnected. Throws std::runtime_error with one line naming
	 * the file and section on failure (unknown driver, bad key, no data). */
	LiveSensors(const std::string& ini, pmslam::PendingObservations& sink, double connectTimeout, double silence);
	~LiveSensors();
	LiveSensors(const LiveSensors&) = delete;
	LiveSensors& operator=(const LiveSensors&) = delete;

	/** Stops and joins the sensor threads (also done by the destructor). Returns how many were stuck inside
	 * their driver and left running: the process should then end with std::_Exit once its outputs are written. */
	std::size_t stop();

   private:
	void* m_library = nullptr;
	void* m_hub = nullptr;
	std::size_t (*m_stop)(void*) = nullptr;
	std::size_t m_stuck = 0;
};

}  // namespace pmslam_app
