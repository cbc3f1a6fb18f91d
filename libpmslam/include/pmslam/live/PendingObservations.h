/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * PendingObservations: what live sensors delivered and the SLAM has not taken
 * yet. Sensor threads push(); the SLAM thread pop()s in arrival order.
 *
 * Never behind: at most `maxPendingScans` laser scans wait. A scan arriving
 * when that many are pending drops the oldest pending scan (counted), so a
 * SLAM that fell behind catches up on the newest data instead of queueing
 * without bound; odometry and other objects are small and never dropped, but
 * bounded too (8× the scans), oldest first.
 *
 * Everything received is also handed, in arrival order and under the same
 * lock as the queue, to `onReceived` (--record): the recording holds the
 * objects in the order the SLAM saw them.
 *
 * Sensor threads report events (disconnects, reconnections) with note(); the
 * SLAM thread prints them between scans (takeNotes()), so they never garble
 * its progress line.
 */
#pragma once

#include <mrpt/serialization/CSerializable.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

namespace pmslam
{
class PendingObservations
{
   public:
	explicit PendingObservations(std::size_t maxPendingScans = 20);

	/** Called under the lock for every object received, before it is queued (dropped or not). */
	std::function<void(const mrpt::serialization::CSerializable::Ptr&)> onReceived;

	/** From a sensor thread: one object, in the order the sensor produced it. */
	void push(const mrpt::serialization::CSerializable::Ptr& obj);
	/** The oldest pending object; waits up to `wait` for one. False if none came (or closed and empty). */
	bool pop(mrpt::serialization::CSerializable::Ptr& obj, std::chrono::milliseconds wait);
	/** No sensor will push again: pop() returns false once empty, without waiting. */
	void close();
	bool closed() const;

	/** A one-line event from a sensor thread, for the SLAM thread to print. */
	void note(const std::string& message);
	std::vector<std::string> takeNotes();

	struct Counts
	{
		std::size_t received = 0;  ///< objects pushed
		std::size_t scans = 0;	///< of which laser scans (or 3D observations)
		std::size_t droppedScans = 0;  ///< scans dropped unprocessed because too many were pending
		std::size_t droppedOther = 0;  ///< other objects dropped (odometry, ...)
		std::size_t pending = 0;  ///< waiting now
	};
	Counts counts() const;
	std::size_t maxPendingScans() const { return m_maxScans; }

   private:
	static bool isScan(const mrpt::serialization::CSerializable& obj);

	const std::size_t m_maxScans;
	mutable std::mutex m_mutex;
	std::condition_variable m_cv;
	std::deque<std::pair<mrpt::serialization::CSerializable::Ptr, bool>> m_queue;  // object, is a scan
	std::size_t m_pendingScans = 0;
	Counts m_counts;
	bool m_closed = false;
	std::vector<std::string> m_notes;
};

}  // namespace pmslam
