/* pmslam — LogReader base (see LogReader.h); LogReader::open(), the format detection, is in OpenLog.cpp. */
#include <pmslam/io/LogReader.h>

#include <iostream>
#include <string>
#include <utility>

namespace pmslam
{
LogReader::LogReader(std::string path)
	: onWarning([](const std::string& s) { std::cerr << s << std::endl; }), m_path(std::move(path))
{
}

void LogReader::warn(const std::string& message)
{
	++m_stats.warnings;
	if (onWarning) onWarning(message);
}

bool LogReader::deliver(std::deque<LogEvent>& queue, LogEvent& ev)
{
	ev = std::move(queue.front());
	queue.pop_front();
	if (ev.kind == LogEvent::Kind::Scan)
		++m_stats.scans;
	else
		++m_stats.odometry;
	return true;
}

}  // namespace pmslam
