/* pmslam — live sensor data as a LogReader (see LiveReader.h). */
#include <pmslam/live/LiveReader.h>

#include <chrono>
#include <utility>

namespace pmslam
{
LiveReader::LiveReader(std::string name, PendingObservations& pending, std::function<bool()> stopRequested,
					   std::function<void()> stopSources, const LogReaderOptions& opts)
	: LogReader(name),
	  m_pending(pending),
	  m_stop(std::move(stopRequested)),
	  m_stopSources(std::move(stopSources)),
	  m_events(opts, name, [this](const std::string& w) { warn(w); }, m_stats)
{
}

void LiveReader::passNotes()
{
	for (const auto& n : m_pending.takeNotes()) warn(n);
}

bool LiveReader::next(LogEvent& ev)
{
	while (m_queue.empty())
	{
		passNotes();
		if (m_done) return false;
		if (!m_stopping && m_stop && m_stop())
		{
			// No new data from here; what was received is still delivered.
			m_stopping = true;
			if (m_stopSources) m_stopSources();
			m_pending.close();
		}
		mrpt::serialization::CSerializable::Ptr obj;
		// A short wait: Ctrl-C and the sensors' notes are seen within it.
		if (!m_pending.pop(obj, std::chrono::milliseconds(50)))
		{
			if (m_pending.closed())
			{
				m_events.finish(m_queue);
				m_done = true;
			}
			continue;
		}
		m_stats.linesOrObjects = ++m_objects;
		m_events.add(obj, m_objects, m_queue);
	}
	return deliver(m_queue, ev);
}

}  // namespace pmslam
