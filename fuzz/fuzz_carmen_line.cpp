// libFuzzer target: the Carmen log reader on arbitrary text (one or more lines).
// Every line is validated before MRPT's importer sees it; damaged lines must be
// skipped with a warning, never crash, and what is delivered must be usable.
#include <pmslam/io/CarmenLogReader.h>

#include <cstddef>
#include <cstdint>

#include "FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
	const std::string path = pmslam::fuzz::memoryFile(data, size);
	pmslam::LogReaderOptions opts;
	if (size > 0) opts.useOdomLines = (data[0] & 1) == 0;
	pmslam::CarmenLogReader reader(path, opts);
	std::size_t warnings = 0;
	reader.onWarning = [&](const std::string& w) {
		if (w.empty() || w.find('\n') != std::string::npos) pmslam::fuzz::fail("warning is not one line");
		++warnings;
	};
	(void)reader.estimatedScanCount();
	pmslam::LogEvent ev;
	std::size_t events = 0;
	while (reader.next(ev))
	{
		pmslam::fuzz::checkEvent(ev);
		if (ev.kind == pmslam::LogEvent::Kind::Scan)
		{
			bool anyValid = false;
			for (std::size_t i = 0; i < ev.scan->getScanSize(); ++i) anyValid |= ev.scan->getScanRangeValidity(i);
			if (!anyValid) pmslam::fuzz::fail("Carmen scan without a valid beam delivered");
			if (!(ev.scan->maxRange > 0) || ev.scan->maxRange > static_cast<float>(opts.noReturnRange))
				pmslam::fuzz::fail("Carmen scan maxRange outside (0, noReturnRange]");
		}
		++events;
	}
	if (reader.next(ev)) pmslam::fuzz::fail("next() after the end delivered an event");
	const auto& st = reader.stats();
	if (st.scans + st.odometry != events) pmslam::fuzz::fail("stats do not count the delivered events");
	if (st.warnings != warnings || st.skipped > st.warnings) pmslam::fuzz::fail("stats do not count the warnings");
	return 0;
}
