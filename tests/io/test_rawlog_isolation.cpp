// RawlogReader reads each object in a child process first: an object on which MRPT's
// deserialisation crashes, spins, throws or asks for all memory ends the log with one
// warning instead of taking the program with it. The hostile objects are MRPT
// serialisable classes defined here, written to a rawlog by MRPT's own writer.
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/RawlogReader.h>

#include <chrono>
#include <csignal>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "SyntheticLogs.h"

namespace pmslam::testing
{
/** What a damaged object makes MRPT do; `how` is serialised, so the writer never misbehaves. */
class HostileObject : public mrpt::serialization::CSerializable
{
	DEFINE_SERIALIZABLE(HostileObject, pmslam::testing)
   public:
	enum How : uint8_t
	{
		Crash,
		Spin,
		Throw,
		ExhaustMemory
	};
	How how = Crash;
};
IMPLEMENTS_SERIALIZABLE(HostileObject, CSerializable, pmslam::testing)

uint8_t HostileObject::serializeGetVersion() const { return 0; }
void HostileObject::serializeTo(mrpt::serialization::CArchive& out) const { out << static_cast<uint8_t>(how); }
void HostileObject::serializeFrom(mrpt::serialization::CArchive& in, uint8_t)
{
	uint8_t h;
	in >> h;
	switch (h)
	{
		case Crash:
			std::raise(SIGSEGV);
			break;
		case Spin:
			for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(10));
		case Throw:
			throw std::runtime_error("hostile object refuses to be read");
		case ExhaustMemory:
		{
			std::vector<char> all(std::size_t(64) << 30, 1);  // 64 GiB, touched
			h = static_cast<uint8_t>(all.back());
			break;
		}
	}
	how = static_cast<How>(h);
}
}  // namespace pmslam::testing

namespace
{
using pmslam::LogEvent;
using pmslam::testing::HostileObject;
using pmslam::testing::ScratchDir;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAsan = true;  // the child has no address-space cap there (see RawlogProbe.cpp)
#else
constexpr bool kAsan = false;
#endif

struct Registered
{
	Registered() { mrpt::rtti::registerClass(CLASS_ID(HostileObject)); }
};

/** Scan, odometry, scan, then the hostile object (object 4), then one more scan. */
std::string writeLog(const ScratchDir& d, HostileObject::How how)
{
	static Registered once;
	const std::string path = d.path("hostile.rawlog");
	mrpt::io::CFileOutputStream f(path);
	auto a = mrpt::serialization::archiveFrom(f);
	auto scan = [](double t) {
		mrpt::obs::CObservation2DRangeScan s;
		s.timestamp = mrpt::Clock::fromDouble(t);
		s.aperture = static_cast<float>(M_PI);
		s.maxRange = 30.0f;
		s.resizeScan(181);
		for (std::size_t i = 0; i < 181; ++i) s.setScanRange(i, 3.0f), s.setScanRangeValidity(i, true);
		return s;
	};
	mrpt::obs::CObservationOdometry odo;
	odo.timestamp = mrpt::Clock::fromDouble(1.5);
	HostileObject hostile;
	hostile.how = how;
	a << scan(1.0) << odo << scan(2.0) << hostile << scan(3.0);
	return path;
}

struct Outcome
{
	std::vector<LogEvent::Kind> events;
	std::vector<std::string> warnings;
	double seconds = 0;
};

Outcome readAll(const std::string& path, double objectTimeout)
{
	pmslam::LogReaderOptions o;
	o.rawlogObjectTimeout = objectTimeout;
	const auto t0 = std::chrono::steady_clock::now();
	auto reader = pmslam::LogReader::open(path, o);
	Outcome r;
	reader->onWarning = [&](const std::string& w) { r.warnings.push_back(w); };
	(void)reader->estimatedScanCount();  // reads ahead too
	LogEvent ev;
	while (reader->next(ev)) r.events.push_back(ev.kind);
	EXPECT_FALSE(reader->next(ev));
	r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return r;
}

void expectStopsBeforeObject4(const Outcome& r, const std::string& path, const std::string& reason)
{
	using K = LogEvent::Kind;
	EXPECT_EQ(r.events, (std::vector<K>{K::Scan, K::Odometry, K::Scan}));
	ASSERT_EQ(r.warnings.size(), 1u);
	EXPECT_EQ(r.warnings[0], path + ": damaged after object 3 (" + reason + "), stopping");
}
}  // namespace

TEST(RawlogIsolation, CrashInsideMrptEndsTheLogBeforeThatObject)
{
	ScratchDir d("isolation-crash");
	const auto path = writeLog(d, HostileObject::Crash);
	expectStopsBeforeObject4(readAll(path, 10.0), path, "MRPT crashed reading it (signal 11, Segmentation fault)");
}

TEST(RawlogIsolation, ObjectThatNeverFinishesIsGivenUpAfterTheTimeout)
{
	ScratchDir d("isolation-spin");
	const auto path = writeLog(d, HostileObject::Spin);
	const auto r = readAll(path, 0.3);
	expectStopsBeforeObject4(r, path, "MRPT did not finish reading it within 0.3 s");
	EXPECT_LT(r.seconds, 5.0);	// one timeout, not one per question asked
}

TEST(RawlogIsolation, ExceptionIsReportedWithItsMessage)
{
	ScratchDir d("isolation-throw");
	const auto path = writeLog(d, HostileObject::Throw);
	// MRPT 2.5 replaces the exception of a class's reader by its own, naming the class and the file.
	expectStopsBeforeObject4(readAll(path, 10.0), path,
							 "Exception while parsing typed object 'pmslam::testing::HostileObject' from "
							 "mrpt::io::CFileGZInputStream for file '" +
								 path + "'");
}

TEST(RawlogIsolation, MemoryExhaustionIsContainedInTheChild)
{
	if (kAsan) GTEST_SKIP() << "AddressSanitizer reserves the address space the child's cap would limit";
	ScratchDir d("isolation-memory");
	const auto path = writeLog(d, HostileObject::ExhaustMemory);
	const auto r = readAll(path, 10.0);
	expectStopsBeforeObject4(r, path, "std::bad_alloc");
}

TEST(RawlogIsolation, HostileFirstObjectIsRefusedWithTheReason)
{
	static_cast<void>(writeLog(ScratchDir("isolation-register"), HostileObject::Throw));  // registers the class
	ScratchDir d("isolation-first");
	const std::string path = d.path("first.rawlog");
	{
		mrpt::io::CFileOutputStream f(path);
		HostileObject h;
		h.how = HostileObject::Crash;
		mrpt::serialization::archiveFrom(f) << h;
	}
	try
	{
		pmslam::LogReader::open(path);
		ADD_FAILURE() << "no LogError";
	}
	catch (const pmslam::LogError& e)
	{
		EXPECT_EQ(std::string(e.what()), "pmslam: '" + path +
											 "' is not a readable MRPT rawlog (MRPT crashed reading it (signal 11, "
											 "Segmentation fault))");
	}
}
