/* pmslam — the bounded queue between live sensors and the SLAM (see PendingObservations.h). */
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <pmslam/live/PendingObservations.h>
#include <pmslam/sensor/ScanSlice.h>

#include <algorithm>

namespace pmslam
{
PendingObservations::PendingObservations(std::size_t maxPendingScans) : m_maxScans(std::max<std::size_t>(1, maxPendingScans))
{
}

bool PendingObservations::isScan(const mrpt::serialization::CSerializable& obj)
{
	if (dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obj)) return true;
	const auto* o = dynamic_cast<const mrpt::obs::CObservation*>(&obj);
	return o && isSliceable(*o);
}

void PendingObservations::push(const mrpt::serialization::CSerializable::Ptr& obj)
{
	if (!obj) return;
	const bool scan = isScan(*obj);
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		if (onReceived) onReceived(obj);
		++m_counts.received;
		if (scan) ++m_counts.scans;
		const std::size_t maxOther = 8 * m_maxScans;
		if (scan && m_pendingScans >= m_maxScans)
		{
			// The oldest pending scan goes: the SLAM is behind, the newest data matter most.
			const auto it = std::find_if(m_queue.begin(), m_queue.end(), [](const auto& e) { return e.second; });
			m_queue.erase(it);
			--m_pendingScans;
			++m_counts.droppedScans;
		}
		else if (!scan && m_queue.size() - m_pendingScans >= maxOther)
		{
			const auto it = std::find_if(m_queue.begin(), m_queue.end(), [](const auto& e) { return !e.second; });
			m_queue.erase(it);
			++m_counts.droppedOther;
		}
		m_queue.emplace_back(obj, scan);
		if (scan) ++m_pendingScans;
	}
	m_cv.notify_one();
}

bool PendingObservations::pop(mrpt::serialization::CSerializable::Ptr& obj, std::chrono::milliseconds wait)
{
	std::unique_lock<std::mutex> lock(m_mutex);
	if (!m_cv.wait_for(lock, wait, [&] { return !m_queue.empty() || m_closed; }) || m_queue.empty()) return false;
	obj = std::move(m_queue.front().first);
	if (m_queue.front().second) --m_pendingScans;
	m_queue.pop_front();
	return true;
}

void PendingObservations::close()
{
	{
		std::lock_guard<std::mutex> lock(m_mutex);
		m_closed = true;
	}
	m_cv.notify_all();
}

bool PendingObservations::closed() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	return m_closed;
}

void PendingObservations::note(const std::string& message)
{
	std::lock_guard<std::mutex> lock(m_mutex);
	m_notes.push_back(message);
}

std::vector<std::string> PendingObservations::takeNotes()
{
	std::lock_guard<std::mutex> lock(m_mutex);
	std::vector<std::string> out;
	out.swap(m_notes);
	return out;
}

PendingObservations::Counts PendingObservations::counts() const
{
	std::lock_guard<std::mutex> lock(m_mutex);
	Counts c = m_counts;
	c.pending = m_queue.size();
	return c;
}

}  // namespace pmslam
