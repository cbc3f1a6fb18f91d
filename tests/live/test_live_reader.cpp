// LiveReader and --record: live events equal those of the recording read back; --follow reads a rawlog
// while it is being written, exactly as the finished file, and stops on idleness or on request.
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <gtest/gtest.h>
#include <pmslam/io/RawlogReader.h>
#include <pmslam/io/RawlogRecorder.h>
#include <pmslam/live/LiveReader.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "SyntheticLogs.h"
#include "SyntheticWorld.h"

namespace fs = std::filesystem;
using mrpt::serialization::CSerializable;
using namespace pmslam::testing;

namespace
{
fs::path tempDir(const std::string& name)
{
	const fs::path d = fs::temp_directory_path() / ("pmslam_test_live_" + name + "_" + std::to_string(::getpid()));
	fs::remove_all(d);
	fs::create_directories(d);
	return d;
}

// What a sensor set would deliver: odometry and a ray-cast scan per pose, stamped 25 ms apart.
std::vector<CSerializable::Ptr> sensorObjects(std::size_t n)
{
	const auto world = furnishedRoom();
	const auto truth = roomPath(n);
	std::vector<CSerializable::Ptr> out;
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		auto o = mrpt::obs::CObservationOdometry::Create();
		o->sensorLabel = "ODOMETRY";
		o->odometry = mrpt::poses::CPose2D(truth[k]);
		o->timestamp = mrpt::Clock::fromDouble(2000.0 + 0.025 * double(k));
		out.push_back(o);
		auto s = mrpt::obs::CObservation2DRangeScan::Create(world.scan(truth[k], 271, 1.5 * M_PI, 20.0, 0.01, unsigned(k)));
		s->sensorLabel = "LIDAR";
		s->timestamp = mrpt::Clock::fromDouble(2000.0 + 0.025 * double(k) + 0.001);
		out.push_back(s);
	}
	return out;
}

std::vector<pmslam::LogEvent> drain(pmslam::LogReader& r)
{
	std::vector<pmslam::LogEvent> out;
	pmslam::LogEvent ev;
	while (r.next(ev)) out.push_back(ev);
	return out;
}

void expectSameEvents(const std::vector<pmslam::LogEvent>& a, const std::vector<pmslam::LogEvent>& b)
{
	ASSERT_EQ(a.size(), b.size());
	for (std::size_t i = 0; i < a.size(); ++i)
	{
		ASSERT_EQ(a[i].kind, b[i].kind) << i;
		EXPECT_EQ(a[i].timestamp, b[i].timestamp) << i;
		if (a[i].kind == pmslam::LogEvent::Kind::Odometry)
		{
			EXPECT_EQ(a[i].odometry.x, b[i].odometry.x);
			EXPECT_EQ(a[i].odometry.phi, b[i].odometry.phi);
			continue;
		}
		const auto &sa = *a[i].scan, &sb = *b[i].scan;
		ASSERT_EQ(sa.getScanSize(), sb.getScanSize());
		EXPECT_EQ(sa.aperture, sb.aperture);
		EXPECT_EQ(sa.sensorPose, sb.sensorPose);
		for (std::size_t k = 0; k < sa.getScanSize(); ++k)
		{
			EXPECT_EQ(sa.getScanRange(k), sb.getScanRange(k));
			EXPECT_EQ(sa.getScanRangeValidity(k), sb.getScanRangeValidity(k));
		}
	}
}
}  // namespace

TEST(LiveReader, DeliversWhatSensorsPushedAndTheRecordingReplaysIdentically)
{
	const fs::path dir = tempDir("record");
	const std::string rec = (dir / "live.rawlog").string();
	const auto objs = sensorObjects(80);
	std::vector<pmslam::LogEvent> live;
	{
		pmslam::PendingObservations pending(1000);
		pmslam::RawlogRecorder recorder(rec);
		pending.onReceived = [&](const CSerializable::Ptr& o) { recorder.write(*o); };
		std::thread sensor([&] {
			for (const auto& o : objs) pending.push(o);
			pending.close();
		});
		pmslam::LiveReader reader("test sensors", pending, nullptr, nullptr);
		live = drain(reader);
		sensor.join();
		EXPECT_TRUE(fs::exists(rec + ".part"));	 // not the final name until closed
		EXPECT_FALSE(fs::exists(rec));
		recorder.close();
		EXPECT_EQ(recorder.objects(), objs.size());
		EXPECT_EQ(reader.stats().scans, 80u);
		EXPECT_EQ(reader.stats().odometry, 80u);
	}
	ASSERT_TRUE(fs::exists(rec));
	EXPECT_FALSE(fs::exists(rec + ".part"));
	ASSERT_EQ(live.size(), 160u);
	for (std::size_t i = 0; i < live.size(); ++i)
		EXPECT_EQ(live[i].timestamp, mrpt::Clock::toDouble(std::dynamic_pointer_cast<mrpt::obs::CObservation>(objs[i])->timestamp));
	pmslam::RawlogReader offline(rec);
	expectSameEvents(live, drain(offline));
	fs::remove_all(dir);
}

TEST(LiveReader, StopsPromptlyWhenAskedWhileWaiting)
{
	pmslam::PendingObservations pending(4);
	std::atomic<bool> stop{false};
	bool sourcesStopped = false;
	pending.push(mrpt::obs::CObservation2DRangeScan::Create(furnishedRoom().scan({0, 0, 0})));
	pmslam::LiveReader reader("test sensors", pending, [&] { return stop.load(); }, [&] { sourcesStopped = true; });
	std::vector<std::string> warnings;
	reader.onWarning = [&](const std::string& w) { warnings.push_back(w); };
	pending.note("sensor [LIDAR] (CHokuyoURG): connection lost (no data for 2.0 s): retrying");
	std::thread stopper([&] {
		std::this_thread::sleep_for(std::chrono::milliseconds(100));
		stop = true;
	});
	pmslam::LogEvent ev;
	ASSERT_TRUE(reader.next(ev));  // what was pending before the stop
	const auto t0 = std::chrono::steady_clock::now();
	EXPECT_FALSE(reader.next(ev));
	EXPECT_TRUE(sourcesStopped);
	EXPECT_TRUE(pending.closed());
	const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	stopper.join();
	EXPECT_GE(s, 0.09);
	EXPECT_LT(s, 2.0);
	ASSERT_EQ(warnings.size(), 1u);	 // the sensors' notes come out as warnings
	EXPECT_NE(warnings[0].find("connection lost"), std::string::npos);
}

TEST(FollowRawlog, ReadsAFileWhileItIsWrittenAsTheFinishedFileReadsAndStopsWhenIdle)
{
	const fs::path dir = tempDir("follow");
	const auto objs = sensorObjects(150);
	for (const bool gz : {true, false})
	{
		const std::string path = (dir / (gz ? "grab.rawlog" : "plain.rawlog")).string();
		{
			mrpt::io::CFileOutputStream touch(path);  // rawlog-grabber creates the file before any data
		}
		std::atomic<bool> writing{true};
		std::thread writer([&] {
			// As rawlog-grabber: one object after another, in real time (here 4x faster), gz or plain.
			std::unique_ptr<mrpt::io::CStream> out;
			if (gz)
				out = std::make_unique<mrpt::io::CFileGZOutputStream>(path);
			else
				out = std::make_unique<mrpt::io::CFileOutputStream>(path);
			auto a = mrpt::serialization::archiveFrom(*out);
			for (const auto& o : objs)
			{
				a << *o;
				std::this_thread::sleep_for(std::chrono::microseconds(3000));
			}
			out.reset();
			writing = false;
		});
		pmslam::LogReaderOptions opts;
		opts.follow = true;
		opts.followTimeout = 1.0;
		pmslam::RawlogReader follower(path, opts);
		std::vector<std::string> warnings;
		follower.onWarning = [&](const std::string& w) { warnings.push_back(w); };
		std::vector<pmslam::LogEvent> followed;
		bool firstWhileWriting = false;
		for (pmslam::LogEvent ev; follower.next(ev);)
		{
			if (followed.empty()) firstWhileWriting = writing;
			followed.push_back(ev);
		}
		writer.join();
		// Plain files reach the disk every few kB, so reading starts long before the writer ends; a gz
		// stream may hold its first block until the end.
		if (!gz)
		{
			EXPECT_TRUE(firstWhileWriting);
		}
		EXPECT_TRUE(warnings.empty()) << warnings.front();
		pmslam::RawlogReader whole(path);
		expectSameEvents(followed, drain(whole));
		EXPECT_EQ(followed.size(), 300u) << (gz ? "gz" : "plain");
	}
	fs::remove_all(dir);
}

TEST(FollowRawlog, StopsOnRequestWithoutAWarning)
{
	const fs::path dir = tempDir("follow_stop");
	const std::string path = (dir / "grab.rawlog").string();
	{
		mrpt::io::CFileOutputStream out(path);
		auto a = mrpt::serialization::archiveFrom(out);
		for (const auto& o : sensorObjects(5)) a << *o;
	}
	std::atomic<bool> stop{false};
	pmslam::LogReaderOptions opts;
	opts.follow = true;	 // no timeout: only the request ends it
	opts.stopRequested = [&] { return stop.load(); };
	pmslam::RawlogReader follower(path, opts);
	std::vector<std::string> warnings;
	follower.onWarning = [&](const std::string& w) { warnings.push_back(w); };
	std::thread stopper([&] {
		std::this_thread::sleep_for(std::chrono::milliseconds(300));
		stop = true;
	});
	const auto events = drain(follower);
	stopper.join();
	EXPECT_EQ(events.size(), 10u);
	EXPECT_TRUE(warnings.empty());
	fs::remove_all(dir);
}
