/* pm-slam-app — where the scans come from: a log file, a log still being written (--follow), or live
 * sensors (--live, optionally saved with --record). */
#pragma once

#include <pmslam/io/LogReader.h>
#include <pmslam/io/RawlogRecorder.h>
#include <pmslam/live/PendingObservations.h>

#include <atomic>
#include <memory>
#include <string>

#include "LiveSensors.h"
#include "Options.h"

namespace pmslam_app
{
class Input
{
   public:
	Input();
	~Input();
	/** Opens the input the options name (the sensors are started and have delivered data when it
	 * returns). Throws std::runtime_error (or pmslam::LogError) with one line on failure; a sensor thread
	 * may then be stuck in its driver, using this object: end with std::_Exit, not by destroying it. */
	void open(const Options& options, const pmslam::LogReaderOptions& readerOptions);
	Input(const Input&) = delete;
	Input& operator=(const Input&) = delete;

	pmslam::LogReader& reader() { return *m_reader; }
	const pmslam::LogReader& reader() const { return *m_reader; }
	/** --live: the queue between the sensor threads and the SLAM (else null). */
	const pmslam::PendingObservations* pending() const { return m_pending.get(); }
	/** --record (else null). */
	const pmslam::RawlogRecorder* recorder() const { return m_recorder.get(); }
	bool recordFailed() const { return m_recordFailed; }

	/** Nothing arrives any more: stops the sensors and closes the recording (errors said on stderr).
	 * Returns how many sensor threads were stuck inside their driver (the process must then end with
	 * std::_Exit once its outputs are written). */
	std::size_t finish();

   private:
	void openLive(const Options& options, const pmslam::LogReaderOptions& readerOptions);
	void startRecording(const std::string& path);

	std::unique_ptr<pmslam::PendingObservations> m_pending;
	std::unique_ptr<pmslam::RawlogRecorder> m_recorder;
	std::string m_recordPath;
	std::atomic<bool> m_recordFailed{false};
	std::unique_ptr<LiveSensors> m_sensors;
	std::unique_ptr<pmslam::LogReader> m_reader;
};

}  // namespace pmslam_app
