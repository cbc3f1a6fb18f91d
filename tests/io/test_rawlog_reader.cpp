// RawlogReader on MRPT's sample rawlog, the benchmark rawlogs (when present), rawlogs written here, and damaged copies.
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/RawlogReader.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using pmslam::LogError;
using pmslam::LogEvent;
using pmslam::LogReader;
using pmslam::RawlogReader;

namespace
{
namespace fs = std::filesystem;
constexpr double kDeg = M_PI / 180.0;
const std::string kSena = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

struct TempDir
{
	fs::path dir;
	TempDir()
	{
		static int counter = 0;
		dir = fs::temp_directory_path() /
			  ("pmslam_rawlog_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
		fs::create_directories(dir);
	}
	~TempDir()
	{
		std::error_code ec;
		fs::remove_all(dir, ec);
	}
	std::string path(const std::string& name) const { return (dir / name).string(); }
};

struct Collected
{
	std::vector<LogEvent> events;
	std::vector<std::string> warnings;
	pmslam::LogReadStats stats;
	std::size_t estimate = 0;
};

Collected readFile(const std::string& path, const pmslam::LogReaderOptions& opts = {})
{
	Collected c;
	auto reader = LogReader::open(path, opts);
	EXPECT_NE(dynamic_cast<RawlogReader*>(reader.get()), nullptr) << path;
	reader->onWarning = [&](const std::string& w) { c.warnings.push_back(w); };
	c.estimate = reader->estimatedScanCount();
	LogEvent ev;
	while (reader->next(ev)) c.events.push_back(ev);
	EXPECT_FALSE(reader->next(ev));  // stays at the end
	c.stats = reader->stats();
	return c;
}

std::string readBytes(const std::string& p)
{
	std::ifstream f(p, std::ios::binary);
	return std::string(std::istreambuf_iterator<char>(f), {});
}

void writeBytes(const std::string& p, const std::string& b) { std::ofstream(p, std::ios::binary) << b; }

/** Uncompressed copy of a (gz) rawlog, object by object; returns the object count. */
std::size_t writePlainCopy(const std::string& from, const std::string& to)
{
	mrpt::io::CFileGZInputStream in(from);
	auto ia = mrpt::serialization::archiveFrom(in);
	mrpt::io::CFileOutputStream out(to);
	auto oa = mrpt::serialization::archiveFrom(out);
	std::size_t n = 0;
	for (;;)
	{
		mrpt::serialization::CSerializable::Ptr obj;
		try
		{
			obj = ia.ReadObject();
		}
		catch (const std::exception&)
		{
			break;
		}
		oa << *obj;
		++n;
	}
	return n;
}

/** Same kinds, timestamps, poses and scan sizes. */
void expectSameEvents(const std::vector<LogEvent>& a, const std::vector<LogEvent>& b, std::size_t n)
{
	ASSERT_GE(a.size(), n);
	ASSERT_GE(b.size(), n);
	for (std::size_t i = 0; i < n; ++i)
	{
		ASSERT_EQ(a[i].kind, b[i].kind) << i;
		ASSERT_EQ(a[i].timestamp, b[i].timestamp) << i;
		ASSERT_EQ(a[i].sourceIndex, b[i].sourceIndex) << i;
		if (a[i].kind == LogEvent::Kind::Scan)
		{
			ASSERT_EQ(a[i].scan->getScanSize(), b[i].scan->getScanSize()) << i;
		}
		else
		{
			ASSERT_EQ(a[i].odometry.x, b[i].odometry.x) << i;
			ASSERT_EQ(a[i].odometry.phi, b[i].odometry.phi) << i;
		}
	}
}

mrpt::obs::CObservation2DRangeScan::Ptr makeScan(double t, float base)
{
	auto s = std::make_shared<mrpt::obs::CObservation2DRangeScan>();
	s->sensorLabel = "LASER";
	s->timestamp = mrpt::Clock::fromDouble(t);
	s->aperture = static_cast<float>(M_PI);
	s->maxRange = 30.0f;
	s->sensorPose = mrpt::poses::CPose3D(0.2, 0.0, 0.3, 0.0, 0.0, 0.0);
	s->resizeScan(181);
	for (std::size_t i = 0; i < 181; ++i)
	{
		s->setScanRange(i, base + 0.01f * static_cast<float>(i));
		s->setScanRangeValidity(i, i != 7);
	}
	return s;
}

}  // namespace

TEST(RawlogReader, MrptSampleActionObservationLog)
{
	if (!fs::exists(kSena)) GTEST_SKIP() << "MRPT sample rawlog not found: " << kSena;
	const auto c = readFile(kSena);
	EXPECT_TRUE(c.warnings.empty()) << c.warnings.front();
	EXPECT_GT(c.stats.scans, 100u);
	EXPECT_GT(c.stats.odometry, 100u);
	EXPECT_EQ(c.stats.skipped, 0u);
	// The first frame comes before any action: an origin odometry event precedes it.
	ASSERT_FALSE(c.events.empty());
	EXPECT_EQ(c.events[0].kind, LogEvent::Kind::Odometry);
	EXPECT_EQ(c.events[0].odometry.x, 0.0);
	EXPECT_EQ(c.events[1].kind, LogEvent::Kind::Scan);
	EXPECT_EQ(c.events[1].sourceIndex, 1u);

	double path = 0, lastT = -1;
	mrpt::math::TPose2D prev;
	std::size_t backwards = 0;
	for (const auto& e : c.events)
	{
		if (e.timestamp < lastT) ++backwards;
		lastT = e.timestamp;
		if (e.kind == LogEvent::Kind::Odometry)
		{
			path += std::hypot(e.odometry.x - prev.x, e.odometry.y - prev.y);
			prev = e.odometry;
		}
		else
		{
			ASSERT_TRUE(e.scan);
			EXPECT_EQ(e.scan->getScanSize(), 361u);
			EXPECT_NEAR(e.scan->aperture, M_PI, 1e-6);	// not a Carmen import: untouched
			EXPECT_NEAR(e.scan->sensorPose.x(), 0.78, 1e-6);
			EXPECT_FALSE(e.scanHasOdometry);
			EXPECT_GT(e.timestamp, 1.1e9);	// 2006
		}
	}
	EXPECT_GT(path, 10.0) << "odometry does not advance";
	EXPECT_GT(std::hypot(prev.x, prev.y) + std::abs(prev.phi), 0.1);
	EXPECT_EQ(backwards, 0u);
	// Progress estimate: within 30 % of the truth.
	EXPECT_NEAR(static_cast<double>(c.estimate), static_cast<double>(c.stats.scans), 0.3 * c.stats.scans);
}

TEST(RawlogReader, AcesObservationOnlyWithCarmenImportDefectsCorrected)
{
	const std::string p = std::string(PMSLAM_SOURCE_DIR) + "/../shared/datasets/aces/aces.rawlog";
	if (!fs::exists(p)) GTEST_SKIP() << "dataset not found: " << p;
	const auto c = readFile(p);
	EXPECT_EQ(c.stats.scans, 7374u);
	EXPECT_GT(c.stats.odometry, 7000u);
	ASSERT_EQ(c.warnings.size(), 1u);  // the one notice about the corrected geometry
	EXPECT_NE(c.warnings[0].find("Carmen importer"), std::string::npos) << c.warnings[0];
	EXPECT_NEAR(static_cast<double>(c.estimate), 7374.0, 0.3 * 7374.0);
	std::size_t saturated = 0;
	for (const auto& e : c.events)
	{
		if (e.kind != LogEvent::Kind::Scan) continue;
		ASSERT_EQ(e.scan->getScanSize(), 180u);
		ASSERT_NEAR(e.scan->aperture, 179.0 * kDeg, 1e-6);
		ASSERT_NEAR(e.scan->sensorPose.yaw() + e.scan->getScanAngle(0), -90.0 * kDeg, 1e-5);
		ASSERT_NEAR(e.scan->sensorPose.yaw() + e.scan->getScanAngle(179), 89.0 * kDeg, 1e-5);
		for (std::size_t i = 0; i < 180; ++i)
			if (e.scan->getScanRange(i) >= 49.99f)
			{
				++saturated;
				ASSERT_FALSE(e.scan->getScanRangeValidity(i));
			}
	}
	EXPECT_GT(saturated, 0u);
}

TEST(RawlogReader, GzObservationOnlyWrittenHere)
{
	TempDir tmp;
	const std::string p = tmp.path("obs.rawlog");
	{
		mrpt::io::CFileGZOutputStream out(p);
		auto a = mrpt::serialization::archiveFrom(out);
		for (int k = 0; k < 3; ++k)
		{
			auto o = std::make_shared<mrpt::obs::CObservationOdometry>();
			o->timestamp = mrpt::Clock::fromDouble(1000.25 + k);
			o->odometry = mrpt::poses::CPose2D(0.5 * k, -0.1 * k, 0.2 * k);
			a << *o;
			a << *makeScan(1000.5 + k, 1.0f + k);
		}
	}
	EXPECT_EQ(static_cast<unsigned char>(readBytes(p)[0]), 0x1f);  // really gz
	const auto c = readFile(p);
	EXPECT_TRUE(c.warnings.empty());
	ASSERT_EQ(c.events.size(), 6u);
	EXPECT_EQ(c.estimate, 3u);
	for (int k = 0; k < 3; ++k)
	{
		const LogEvent& o = c.events[2 * k];
		const LogEvent& s = c.events[2 * k + 1];
		ASSERT_EQ(o.kind, LogEvent::Kind::Odometry);
		ASSERT_EQ(s.kind, LogEvent::Kind::Scan);
		EXPECT_NEAR(o.timestamp, 1000.25 + k, 1e-6);
		EXPECT_NEAR(s.timestamp, 1000.5 + k, 1e-6);
		EXPECT_NEAR(o.odometry.x, 0.5 * k, 1e-12);
		EXPECT_NEAR(o.odometry.y, -0.1 * k, 1e-12);
		EXPECT_NEAR(o.odometry.phi, 0.2 * k, 1e-12);
		EXPECT_EQ(o.sourceIndex, static_cast<std::size_t>(2 * k + 1));
		EXPECT_EQ(s.sourceIndex, static_cast<std::size_t>(2 * k + 2));
		ASSERT_EQ(s.scan->getScanSize(), 181u);
		EXPECT_FLOAT_EQ(s.scan->getScanRange(10), 1.0f + k + 0.1f);
		EXPECT_FALSE(s.scan->getScanRangeValidity(7));
		EXPECT_TRUE(s.scan->getScanRangeValidity(8));
		EXPECT_NEAR(s.scan->aperture, M_PI, 1e-6);
		EXPECT_FLOAT_EQ(s.scan->maxRange, 30.0f);
		EXPECT_NEAR(s.scan->sensorPose.z(), 0.3, 1e-12);
	}
	EXPECT_EQ(c.stats.linesOrObjects, 6u);
	EXPECT_EQ(c.stats.scans, 3u);
	EXPECT_EQ(c.stats.odometry, 3u);
}

TEST(RawlogReader, GzActionObservationAccumulatesOdometry)
{
	TempDir tmp;
	const std::string p = tmp.path("actobs.rawlog.gz");
	const std::vector<mrpt::poses::CPose2D> inc = {{0.5, 0.0, 0.1}, {0.4, 0.1, -0.3}, {0.0, 0.0, 1.2}};
	{
		mrpt::io::CFileGZOutputStream out(p);
		auto a = mrpt::serialization::archiveFrom(out);
		for (std::size_t k = 0; k < inc.size(); ++k)
		{
			mrpt::obs::CActionCollection acts;
			mrpt::obs::CActionRobotMovement2D mv;
			mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
			mv.computeFromOdometry(inc[k], opts);
			mv.timestamp = mrpt::Clock::fromDouble(20.0 + k);
			acts.insert(mv);
			a << acts;
			mrpt::obs::CSensoryFrame sf;
			sf.insert(makeScan(20.5 + k, 2.0f));
			a << sf;
		}
	}
	const auto c = readFile(p);
	EXPECT_TRUE(c.warnings.empty());
	ASSERT_EQ(c.events.size(), 6u);
	mrpt::poses::CPose2D acc;
	for (std::size_t k = 0; k < inc.size(); ++k)
	{
		acc = acc + inc[k];
		const LogEvent& o = c.events[2 * k];
		ASSERT_EQ(o.kind, LogEvent::Kind::Odometry);
		EXPECT_NEAR(o.timestamp, 20.0 + k, 1e-6);
		EXPECT_NEAR(o.odometry.x, acc.x(), 1e-9);
		EXPECT_NEAR(o.odometry.y, acc.y(), 1e-9);
		EXPECT_NEAR(o.odometry.phi, acc.phi(), 1e-9);
		ASSERT_EQ(c.events[2 * k + 1].kind, LogEvent::Kind::Scan);
		EXPECT_NEAR(c.events[2 * k + 1].timestamp, 20.5 + k, 1e-6);
	}
}

TEST(RawlogReader, DamagedCopiesDeliverEverythingBeforeTheDamageWithOneWarning)
{
	if (!fs::exists(kSena)) GTEST_SKIP() << "MRPT sample rawlog not found: " << kSena;
	TempDir tmp;
	const std::string plain = tmp.path("sena_plain.rawlog");
	const std::size_t objects = writePlainCopy(kSena, plain);
	ASSERT_GT(objects, 100u);
	const auto full = readFile(plain);
	ASSERT_TRUE(full.warnings.empty());
	EXPECT_EQ(full.stats.linesOrObjects, objects);
	const auto fullGz = readFile(kSena);
	expectSameEvents(full.events, fullGz.events, fullGz.events.size());

	const std::string plainBytes = readBytes(plain);
	const std::string gzBytes = readBytes(kSena);
	const std::string garbage = "\x13\x37 this is not an MRPT object \xff\xfe\x00\x01 garbage garbage";

	struct Case
	{
		std::string name, bytes;
		bool truncated;
	};
	const std::vector<Case> cases = {
		{"truncated_plain.rawlog", plainBytes.substr(0, plainBytes.size() * 6 / 10), true},
		{"truncated_gz.rawlog", gzBytes.substr(0, gzBytes.size() * 6 / 10), true},
		{"garbage_plain.rawlog", plainBytes + garbage, false},
	};
	for (const auto& k : cases)
	{
		SCOPED_TRACE(k.name);
		const std::string p = tmp.path(k.name);
		writeBytes(p, k.bytes);
		const auto c = readFile(p);
		ASSERT_EQ(c.warnings.size(), 1u);
		EXPECT_EQ(c.stats.warnings, 1u);
		const std::string& w = c.warnings[0];
		EXPECT_EQ(w.rfind(p + ": damaged after object ", 0), 0u) << w;
		EXPECT_NE(w.find("), stopping"), std::string::npos) << w;
		EXPECT_EQ(w.find('\n'), std::string::npos) << w;
		const std::string n = std::to_string(c.stats.linesOrObjects);
		EXPECT_NE(w.find("after object " + n + " ("), std::string::npos) << w;
		if (k.truncated)
		{
			EXPECT_GT(c.events.size(), full.events.size() / 3);
			EXPECT_LT(c.events.size(), full.events.size());
			EXPECT_LT(c.stats.linesOrObjects, objects);
			expectSameEvents(c.events, full.events, c.events.size());
		}
		else
		{
			EXPECT_EQ(c.stats.linesOrObjects, objects);
			ASSERT_EQ(c.events.size(), full.events.size());
			expectSameEvents(c.events, full.events, full.events.size());
		}
	}

	// zlib stops at the end of a complete gzip stream: bytes appended after it
	// are not seen at all, so the log reads completely and cleanly.
	const std::string p = tmp.path("garbage_gz.rawlog");
	writeBytes(p, gzBytes + garbage);
	const auto g = readFile(p);
	EXPECT_LE(g.warnings.size(), 1u);
	ASSERT_GE(g.events.size(), full.events.size());
	expectSameEvents(g.events, full.events, full.events.size());
}

TEST(RawlogReader, OpenRejectsGarbageRawlog)
{
	TempDir tmp;
	const std::string p = tmp.path("junk.rawlog");
	writeBytes(p, std::string("\x05\x06\x07\x00\x01\x02 junk junk junk", 20));
	try
	{
		LogReader::open(p);
		ADD_FAILURE() << "no LogError";
	}
	catch (const LogError& e)
	{
		EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
		EXPECT_NE(std::string(e.what()).find("rawlog"), std::string::npos) << e.what();
	}
}
