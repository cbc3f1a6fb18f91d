// libFuzzer target: the MRPT rawlog reader (and format detection) on arbitrary
// bytes. Damage must stop reading with one warning, never crash, and what is
// delivered before it must be usable by the SLAM loop.
#include <pmslam/LogReader.h>
#include <pmslam/RawlogReader.h>

#include <cstddef>
#include <cstdint>
#include <memory>

#include "FuzzSupport.h"

namespace
{
void readAll(pmslam::LogReader& reader)
{
	std::size_t warnings = 0;
	reader.onWarning = [&](const std::string& w) {
		if (w.empty() || w.find('\n') != std::string::npos) pmslam::fuzz::fail("warning is not one line");
		++warnings;
	};
	pmslam::LogEvent ev;
	std::size_t events = 0;
	while (reader.next(ev))
	{
		pmslam::fuzz::checkEvent(ev);
		++events;
	}
	if (reader.next(ev)) pmslam::fuzz::fail("next() after the end delivered an event");
	const auto& st = reader.stats();
	if (st.scans + st.odometry != events) pmslam::fuzz::fail("stats do not count the delivered events");
	if (st.warnings != warnings) pmslam::fuzz::fail("stats do not count the warnings");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
	const std::string path = pmslam::fuzz::memoryFile(data, size);
	// Straight to the rawlog reader: every input reaches the object reader.
	{
		pmslam::RawlogReader reader(path);
		(void)reader.estimatedScanCount();
		readAll(reader);
	}
	// Format detection: either a reader or a one-line LogError, nothing else.
	std::unique_ptr<pmslam::LogReader> reader;
	try
	{
		reader = pmslam::LogReader::open(path);
	}
	catch (const pmslam::LogError& e)
	{
		const std::string what = e.what();
		if (what.find(path) == std::string::npos || what.find('\n') != std::string::npos)
			pmslam::fuzz::fail("LogError does not name the file in one line");
		return 0;
	}
	readAll(*reader);
	return 0;
}
