// libFuzzer target: the MRPT rawlog reader (and format detection) on arbitrary
// bytes. Damage must stop reading with one warning, never crash, and what is
// delivered before it must be usable by the SLAM loop.
#include <pmslam/io/LogReader.h>
#include <pmslam/io/RawlogReader.h>

#include <malloc.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>

#include "FuzzSupport.h"

// MRPT's deserialisation trusts the lengths it reads (a damaged string or vector
// length asks for gigabytes), and under AddressSanitizer a failing `new` aborts
// instead of throwing. Here an allocation above kAllocLimit, or one that takes
// the live total beyond kLiveLimit, throws std::bad_alloc as on a machine without
// overcommit, so the fuzzer checks that the reader turns that into a damage
// warning rather than reporting MRPT's trust in its input.
// (Every unaligned form is replaced, so that new/delete pairs stay matched;
// over-aligned allocations keep the sanitizer's own operators.)
namespace
{
constexpr std::size_t kAllocLimit = std::size_t(256) << 20;	// one allocation
constexpr std::size_t kLiveLimit = std::size_t(1) << 30;  // all of them (a count of small objects, e.g. a deque)
std::atomic<std::size_t> g_live{0};

void* tryAllocate(std::size_t n) noexcept
{
	if (n > kAllocLimit || g_live.load() + n > kLiveLimit) return nullptr;
	void* p = std::malloc(n ? n : 1);
	if (p) g_live += ::malloc_usable_size(p);
	return p;
}
void* allocate(std::size_t n)
{
	if (void* p = tryAllocate(n)) return p;
	throw std::bad_alloc();
}
void release(void* p) noexcept
{
	if (!p) return;
	g_live -= ::malloc_usable_size(p);
	std::free(p);
}
}  // namespace
void* operator new(std::size_t n) { return allocate(n); }
void* operator new[](std::size_t n) { return allocate(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return tryAllocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return tryAllocate(n); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }

namespace
{
// An object MRPT spins on is given up after 2 s, well inside libFuzzer's -timeout.
pmslam::LogReaderOptions options()
{
	pmslam::LogReaderOptions o;
	o.rawlogObjectTimeout = 2.0;
	return o;
}

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
		pmslam::RawlogReader reader(path, options());
		(void)reader.estimatedScanCount();
		readAll(reader);
	}
	// Format detection: either a reader or a one-line LogError, nothing else.
	std::unique_ptr<pmslam::LogReader> reader;
	try
	{
		reader = pmslam::LogReader::open(path, options());
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
