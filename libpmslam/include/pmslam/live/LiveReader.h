/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * LiveReader: the LogReader of a live run. It takes the objects that sensor
 * threads left in a PendingObservations, oldest first, and turns them into
 * LogEvent with the same ObservationEvents conversion as RawlogReader — so
 * the SLAM loop is the same for a log and a robot, and a --record'ed run
 * replays offline to the same trajectory.
 *
 * next() waits for data. When stopRequested() becomes true (Ctrl-C) it calls
 * stopSources() once — which must stop the sensors and close the queue — and
 * then delivers what is still pending: everything received (and recorded) is
 * processed, so the recording replays to the same trajectory. It returns
 * false once the queue is closed and empty. The sensors' notes (disconnects,
 * reconnections) come out through onWarning, between events.
 */
#pragma once

#include <pmslam/io/LogReader.h>
#include <pmslam/io/ObservationEvents.h>
#include <pmslam/live/PendingObservations.h>

#include <deque>
#include <functional>
#include <memory>
#include <string>

namespace pmslam
{
class LiveReader : public LogReader
{
   public:
	/** `name` (e.g. the SENSORS.ini path) names the source in messages. */
	LiveReader(std::string name, PendingObservations& pending, std::function<bool()> stopRequested,
			   std::function<void()> stopSources, const LogReaderOptions& opts = {});

	bool next(LogEvent& ev) override;
	std::size_t estimatedScanCount() const override { return 0; }	// unknown: open-ended

   private:
	void passNotes();

	PendingObservations& m_pending;
	std::function<bool()> m_stop;
	std::function<void()> m_stopSources;
	ObservationEvents m_events;
	std::deque<LogEvent> m_queue;
	std::size_t m_objects = 0;
	bool m_done = false, m_stopping = false;
};

}  // namespace pmslam
