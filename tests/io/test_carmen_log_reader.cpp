// CarmenLogReader and LogReader::open on generated Carmen files and, when present, the benchmark logs.
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <pmslam/io/CarmenLogReader.h>
#include <pmslam/io/LogReader.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using pmslam::CarmenLogReader;
using pmslam::LogError;
using pmslam::LogEvent;
using pmslam::LogReader;
using pmslam::LogReaderOptions;

namespace
{
namespace fs = std::filesystem;
constexpr double kDeg = M_PI / 180.0;

struct TempDir
{
	fs::path dir;
	TempDir()
	{
		static int counter = 0;
		dir = fs::temp_directory_path() /
			  ("pmslam_carmen_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
		fs::create_directories(dir);
	}
	~TempDir()
	{
		std::error_code ec;
		fs::remove_all(dir, ec);
	}
	std::string write(const std::string& name, const std::string& content) const
	{
		const std::string p = (dir / name).string();
		std::ofstream(p, std::ios::binary) << content;
		return p;
	}
};

std::string fmt6(double v)
{
	char b[64];
	std::snprintf(b, sizeof(b), "%.6f", v);
	return b;
}

std::string joinRanges(const std::vector<double>& r)
{
	std::string s;
	char b[32];
	for (double v : r)
	{
		std::snprintf(b, sizeof(b), " %.2f", v);
		s += b;
	}
	return s;
}

/** FLASER/RLASER line: laser pose (lx, ly, lth), odometry (ox, oy, oth). */
std::string laserLine(const std::string& kw, const std::vector<double>& r, double lx, double ly, double lth, double ox,
					  double oy, double oth, const std::string& ts)
{
	std::ostringstream s;
	s << kw << " " << r.size() << joinRanges(r) << " " << fmt6(lx) << " " << fmt6(ly) << " " << fmt6(lth) << " "
	  << fmt6(ox) << " " << fmt6(oy) << " " << fmt6(oth) << " " << ts << " nohost 0.123456";
	return s.str();
}

std::string flaser(std::size_t n, const std::string& ts, double x = 0, double y = 0, double th = 0)
{
	std::vector<double> r(n);
	for (std::size_t i = 0; i < n; ++i) r[i] = 1.0 + 0.01 * static_cast<double>(i % 300);
	return laserLine("FLASER", r, x, y, th, x, y, th, ts);
}

std::string odom(double x, double y, double th, const std::string& ts)
{
	return "ODOM " + fmt6(x) + " " + fmt6(y) + " " + fmt6(th) + " 0.000000 0.000000 0.000000 " + ts + " nohost 0.5";
}

struct Collected
{
	std::vector<LogEvent> events;
	std::vector<std::string> warnings;
	pmslam::LogReadStats stats;
};

Collected readAll(LogReader& reader)
{
	Collected c;
	reader.onWarning = [&](const std::string& w) { c.warnings.push_back(w); };
	LogEvent ev;
	while (reader.next(ev)) c.events.push_back(ev);
	c.stats = reader.stats();
	return c;
}

Collected readFile(const std::string& path, const LogReaderOptions& opts = {})
{
	auto reader = LogReader::open(path, opts);
	EXPECT_NE(dynamic_cast<CarmenLogReader*>(reader.get()), nullptr) << path;
	return readAll(*reader);
}

/** Direction of beam i in the robot frame, from MRPT's documented convention
 * (not from getScanAngle): yaw(sensorPose) − aperture/2 + i·aperture/(N−1). */
double beamAngleInRobot(const mrpt::obs::CObservation2DRangeScan& s, std::size_t i)
{
	const double n = static_cast<double>(s.getScanSize());
	double a = -0.5 * s.aperture + static_cast<double>(i) * s.aperture / (n - 1);
	if (!s.rightToLeft) a = -a;
	return s.sensorPose.yaw() + a;
}

double angleDiff(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

void expectFan(const mrpt::obs::CObservation2DRangeScan& s, double first, double step, double robotYawOfLaser)
{
	for (std::size_t i = 0; i < s.getScanSize(); ++i)
	{
		const double expected = robotYawOfLaser + first + static_cast<double>(i) * step;
		ASSERT_NEAR(angleDiff(beamAngleInRobot(s, i), expected), 0.0, 1e-6) << "beam " << i;
		ASSERT_NEAR(angleDiff(s.sensorPose.yaw() + s.getScanAngle(i), expected), 0.0, 1e-5) << "beam " << i;
	}
}

std::string datasetPath(const std::string& name)
{
	return std::string(PMSLAM_SOURCE_DIR) + "/../shared/datasets/" + name + "/" + name + ".clf";
}

}  // namespace

TEST(CarmenLogReader, Flaser180BeamsOneDegreeFromMinus90AndExactTimestamp)
{
	TempDir tmp;
	const std::string ts = "976052857.337530";
	const auto c = readFile(tmp.write("a.clf", flaser(180, ts, 1.0, 2.0, 0.3) + "\n"));
	ASSERT_EQ(c.events.size(), 1u);
	const LogEvent& e = c.events[0];
	ASSERT_EQ(e.kind, LogEvent::Kind::Scan);
	ASSERT_TRUE(e.scan);
	EXPECT_EQ(fmt6(e.timestamp), ts);
	EXPECT_EQ(fmt6(mrpt::Clock::toDouble(e.scan->timestamp)), ts);
	EXPECT_EQ(e.sourceIndex, 1u);
	ASSERT_EQ(e.scan->getScanSize(), 180u);
	EXPECT_NEAR(e.scan->aperture, 179.0 * kDeg, 1e-6);
	EXPECT_TRUE(e.scan->rightToLeft);
	EXPECT_NEAR(e.scan->sensorPose.x(), 0.0, 1e-9);
	EXPECT_NEAR(e.scan->sensorPose.y(), 0.0, 1e-9);
	expectFan(*e.scan, -90 * kDeg, 1.0 * kDeg, 0.0);
	EXPECT_NEAR(beamAngleInRobot(*e.scan, 179), 89.0 * kDeg, 1e-6);
	EXPECT_TRUE(e.scanHasOdometry);
	EXPECT_NEAR(e.scanOdometry.x, 1.0, 1e-9);
	EXPECT_NEAR(e.scanOdometry.y, 2.0, 1e-9);
	EXPECT_NEAR(e.scanOdometry.phi, 0.3, 1e-9);
	EXPECT_FLOAT_EQ(e.scan->getScanRange(7), 1.07f);
	EXPECT_EQ(e.scan->sensorLabel, "FLASER");
	EXPECT_TRUE(c.warnings.empty());
	EXPECT_EQ(c.stats.scans, 1u);
}

TEST(CarmenLogReader, Flaser360And361BeamsHalfDegree)
{
	TempDir tmp;
	const auto c = readFile(tmp.write("b.clf", flaser(360, "1211.520329") + "\n" + flaser(361, "1211.620329") + "\n"));
	ASSERT_EQ(c.events.size(), 2u);
	const auto& s360 = *c.events[0].scan;
	const auto& s361 = *c.events[1].scan;
	EXPECT_NEAR(s360.aperture, 179.5 * kDeg, 1e-6);
	expectFan(s360, -90 * kDeg, 0.5 * kDeg, 0.0);
	EXPECT_NEAR(beamAngleInRobot(s360, 359), 89.5 * kDeg, 1e-6);
	EXPECT_NEAR(s361.aperture, 180.0 * kDeg, 1e-6);
	expectFan(s361, -90 * kDeg, 0.5 * kDeg, 0.0);
	EXPECT_NEAR(beamAngleInRobot(s361, 0), -90.0 * kDeg, 1e-6);
	EXPECT_NEAR(beamAngleInRobot(s361, 360), 90.0 * kDeg, 1e-6);
	EXPECT_EQ(fmt6(c.events[0].timestamp), "1211.520329");
	EXPECT_EQ(fmt6(c.events[1].timestamp), "1211.620329");
	EXPECT_NEAR(CarmenLogReader::flaserBeamStep(180), 1.0 * kDeg, 1e-12);
	EXPECT_NEAR(CarmenLogReader::flaserBeamStep(181), 1.0 * kDeg, 1e-12);
}

TEST(CarmenLogReader, RearLaserLooksBackwards)
{
	TempDir tmp;
	std::vector<double> r(180, 2.0);
	// One rear line writing the robot heading for the laser, one writing heading + pi.
	const std::string a = laserLine("RLASER", r, 5, 6, 0.4, 5, 6, 0.4, "10.000001");
	const std::string b = laserLine("RLASER", r, 5, 6, 0.4 + M_PI, 5, 6, 0.4, "10.100001");
	const auto c = readFile(tmp.write("r.clf", a + "\n" + b + "\n"));
	ASSERT_EQ(c.events.size(), 2u);
	for (const auto& e : c.events)
	{
		ASSERT_EQ(e.kind, LogEvent::Kind::Scan);
		EXPECT_EQ(e.scan->sensorLabel, "RLASER");
		expectFan(*e.scan, -90 * kDeg, 1.0 * kDeg, M_PI);
	}
	EXPECT_TRUE(c.warnings.empty());
}

TEST(CarmenLogReader, SensorOffsetFromTheTwoPoseTriples)
{
	TempDir tmp;
	std::vector<double> r(360, 3.0);
	// Robot at (1, 2) heading 90 deg; laser 0.04 m ahead and 0.01 m to the left of it.
	const double th = 0.5 * M_PI;
	const double lx = 1.0 + 0.04 * std::cos(th) - 0.01 * std::sin(th);
	const double ly = 2.0 + 0.04 * std::sin(th) + 0.01 * std::cos(th);
	const auto c = readFile(tmp.write("o.clf", laserLine("FLASER", r, lx, ly, th, 1.0, 2.0, th, "5.000000") + "\n"));
	ASSERT_EQ(c.events.size(), 1u);
	const auto& s = *c.events[0].scan;
	EXPECT_NEAR(s.sensorPose.x(), 0.04, 2e-6);
	EXPECT_NEAR(s.sensorPose.y(), 0.01, 2e-6);
	expectFan(s, -90 * kDeg, 0.5 * kDeg, 0.0);
	EXPECT_NEAR(c.events[0].scanOdometry.x, 1.0, 1e-9);
	EXPECT_NEAR(c.events[0].scanOdometry.phi, th, 1e-6);
}

TEST(CarmenLogReader, RobotLaser1UsesItsOwnGeometry)
{
	TempDir tmp;
	// start -1.0 rad, fov 2.0, resolution 0.5 => 5 beams at -1, -0.5, 0, 0.5, 1 rad; max range 30 m.
	// Laser pose: robot (2, 3, 0.2) ⊕ (0.1, -0.05, 0.3).
	const double rth = 0.2;
	const double lx = 2.0 + 0.1 * std::cos(rth) + 0.05 * std::sin(rth);
	const double ly = 3.0 + 0.1 * std::sin(rth) - 0.05 * std::cos(rth);
	const std::string line = "ROBOTLASER1 0 -1.000000 2.000000 0.500000 30.000000 0.01 0 5 1.50 2.50 30.00 0.00 4.25 "
							 "2 7 8 " +
							 fmt6(lx) + " " + fmt6(ly) + " " + fmt6(rth + 0.3) +
							 " 2.000000 3.000000 0.200000 0.1 0.0 0.5 0.3 0.2 1234567890.123456 robot 0.010000";
	const auto c = readFile(tmp.write("rl.log", line + "\n"));
	ASSERT_EQ(c.events.size(), 1u) << (c.warnings.empty() ? "" : c.warnings[0]);
	const LogEvent& e = c.events[0];
	ASSERT_EQ(e.scan->getScanSize(), 5u);
	EXPECT_EQ(fmt6(e.timestamp), "1234567890.123456");
	EXPECT_EQ(fmt6(mrpt::Clock::toDouble(e.scan->timestamp)), "1234567890.123456");
	EXPECT_NEAR(e.scan->sensorPose.x(), 0.1, 2e-6);
	EXPECT_NEAR(e.scan->sensorPose.y(), -0.05, 2e-6);
	expectFan(*e.scan, -1.0, 0.5, 0.3);
	EXPECT_NEAR(e.scan->aperture, 2.0, 1e-6);
	EXPECT_FLOAT_EQ(e.scan->maxRange, 30.0f);
	const std::vector<bool> valid = {true, true, false, false, true};
	for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(e.scan->getScanRangeValidity(i), valid[i]) << i;
	EXPECT_FLOAT_EQ(e.scan->getScanRange(2), 30.0f);  // raw value kept
	EXPECT_TRUE(e.scanHasOdometry);
	EXPECT_NEAR(e.scanOdometry.x, 2.0, 1e-9);
	EXPECT_NEAR(e.scanOdometry.phi, 0.2, 1e-9);
}

TEST(CarmenLogReader, OdomLinesAndExactTimestamps)
{
	TempDir tmp;
	const std::string text = "# CARMEN Logfile\nPARAM robot_frontlaser_offset 0.0 nohost 0\n" +
							 odom(0.5, -0.25, 1.5, "976052857.337284") + "\n" + flaser(180, "976052857.337530") + "\n" +
							 odom(0.75, -0.25, 1.5, "976052857.437284") + "\n";
	const auto c = readFile(tmp.write("odom.clf", text));
	ASSERT_EQ(c.events.size(), 3u);
	EXPECT_EQ(c.events[0].kind, LogEvent::Kind::Odometry);
	EXPECT_EQ(c.events[1].kind, LogEvent::Kind::Scan);
	EXPECT_EQ(c.events[2].kind, LogEvent::Kind::Odometry);
	EXPECT_EQ(fmt6(c.events[0].timestamp), "976052857.337284");
	EXPECT_EQ(fmt6(c.events[2].timestamp), "976052857.437284");
	EXPECT_NEAR(c.events[0].odometry.x, 0.5, 1e-12);
	EXPECT_NEAR(c.events[0].odometry.y, -0.25, 1e-12);
	EXPECT_NEAR(c.events[0].odometry.phi, 1.5, 1e-12);
	EXPECT_EQ(c.events[0].sourceIndex, 3u);
	EXPECT_EQ(c.events[1].sourceIndex, 4u);
	EXPECT_EQ(c.stats.odometry, 2u);
	EXPECT_EQ(c.stats.scans, 1u);
	EXPECT_EQ(c.stats.linesOrObjects, 5u);
	EXPECT_TRUE(c.warnings.empty());

	LogReaderOptions noOdom;
	noOdom.useOdomLines = false;
	const auto d = readFile(tmp.write("odom2.clf", text), noOdom);
	ASSERT_EQ(d.events.size(), 1u);
	EXPECT_EQ(d.events[0].kind, LogEvent::Kind::Scan);
	EXPECT_EQ(d.stats.odometry, 0u);
	EXPECT_EQ(d.stats.skipped, 0u);
}

TEST(CarmenLogReader, LogWithoutOdomLinesCarriesScanOdometry)
{
	TempDir tmp;
	const std::string text = flaser(180, "1.000000", 0, 0, 0) + "\n" + flaser(180, "1.200000", 0.1, 0, 0.01) + "\n" +
							 flaser(180, "1.400000", 0.2, 0.01, 0.02) + "\n";
	const auto c = readFile(tmp.write("noodom.clf", text));
	ASSERT_EQ(c.events.size(), 3u);
	EXPECT_EQ(c.stats.odometry, 0u);
	for (const auto& e : c.events)
	{
		EXPECT_EQ(e.kind, LogEvent::Kind::Scan);
		EXPECT_TRUE(e.scanHasOdometry);
	}
	EXPECT_NEAR(c.events[2].scanOdometry.x, 0.2, 1e-9);
	EXPECT_NEAR(c.events[2].scanOdometry.y, 0.01, 1e-9);
	EXPECT_NEAR(c.events[2].scanOdometry.phi, 0.02, 1e-9);
}

TEST(CarmenLogReader, NoReturnReadingsAreInvalidButKeepTheirRange)
{
	TempDir tmp;
	std::vector<double> r(180, 3.0);
	r[0] = 81.91;
	r[1] = 50.00;
	r[2] = 49.89;
	r[3] = 0.0;
	const std::string text = laserLine("FLASER", r, 0, 0, 0, 0, 0, 0, "70.289900") + "\n";
	const auto c = readFile(tmp.write("nr.clf", text));
	ASSERT_EQ(c.events.size(), 1u);
	const auto& s = *c.events[0].scan;
	EXPECT_FLOAT_EQ(s.maxRange, 49.9f);
	EXPECT_FALSE(s.getScanRangeValidity(0));
	EXPECT_FALSE(s.getScanRangeValidity(1));
	EXPECT_TRUE(s.getScanRangeValidity(2));
	EXPECT_FALSE(s.getScanRangeValidity(3));
	EXPECT_TRUE(s.getScanRangeValidity(4));
	EXPECT_FLOAT_EQ(s.getScanRange(0), 81.91f);
	EXPECT_FLOAT_EQ(s.getScanRange(1), 50.0f);

	LogReaderOptions far;
	far.noReturnRange = 81.0;
	const auto d = readFile(tmp.write("nr2.clf", text), far);
	ASSERT_EQ(d.events.size(), 1u);
	EXPECT_FLOAT_EQ(d.events[0].scan->maxRange, 81.0f);
	EXPECT_FALSE(d.events[0].scan->getScanRangeValidity(0));
	EXPECT_TRUE(d.events[0].scan->getScanRangeValidity(1));
}

TEST(CarmenLogReader, MalformedLinesAreSkippedWithTheirLineNumber)
{
	TempDir tmp;
	std::vector<std::string> lines;
	std::vector<std::size_t> bad;  // 1-based line numbers expected to be skipped
	std::vector<std::string> why;  // a word expected in each warning
	auto good = [&](const std::string& l) { lines.push_back(l); };
	auto badLine = [&](const std::string& l, const std::string& w) {
		lines.push_back(l);
		bad.push_back(lines.size());
		why.push_back(w);
	};
	good("# comment line");
	good("PARAM robot_front_laser_max 80.99 nohost 0");
	good(flaser(180, "100.000000"));  // line 3
	good("");
	good("TRUEPOS 1 2 3 4 5 6 100.0 nohost 0");	 // unknown to the reader: silent
	{
		std::string l = flaser(180, "100.100000");	// one range removed: 179 ranges for n = 180
		const auto p = l.find(" 1.00 ");
		l.erase(p, 5);
		badLine(l, "disagrees");
	}
	{
		std::string l = flaser(180, "100.200000");
		l.replace(l.find(" 1.05 "), 6, " 1.o5 ");
		badLine(l, "non-numeric");
	}
	{
		std::string l = flaser(180, "100.300000");
		l.replace(l.find(" 1.05 "), 6, " nan ");
		badLine(l, "non-finite");
	}
	{
		std::string l = flaser(180, "100.400000");
		l.replace(l.find(" 1.05 "), 6, " inf ");
		badLine(l, "non-finite");
	}
	{
		std::string l = flaser(180, "100.500000");
		l.replace(l.find(" 1.05 "), 6, " -1.05 ");
		badLine(l, "negative");
	}
	badLine(flaser(180, "1OO.600000"), "ipc_timestamp");
	badLine("FLASER abc 1.0 2.0", "beam count");
	badLine(odom(1, 2, 3, "100.700000") + " extra", "fields");
	badLine("ODOM 1.0 2.0 x 0 0 0 100.800000 nohost 0", "theta");
	badLine("ROBOTLASER1 0 -1.0 2.0 0.1 30.0 0.01 0 5 1 2 3 4 5 0 0 0 0 0 0 0 0 0 0 0 0 100.9 h 0", "disagrees");
	badLine(laserLine("FLASER", std::vector<double>(180, 81.9), 0, 0, 0, 0, 0, 0, "101.000000"), "no valid beam");
	good(flaser(180, "101.100000"));
	badLine(flaser(180, "91.000000"), "goes back");  // 10 s back
	good(flaser(180, "100.600000"));				  // 0.5 s back: normal Carmen jitter, kept
	good(odom(1, 2, 3, "101.200000"));
	const std::size_t goodEvents = 4;

	std::string text;
	for (const auto& l : lines) text += l + "\n";
	const std::string path = tmp.write("bad.clf", text);
	const auto c = readFile(path);
	EXPECT_EQ(c.events.size(), goodEvents);
	EXPECT_EQ(c.stats.skipped, bad.size());
	EXPECT_EQ(c.stats.warnings, bad.size());
	ASSERT_EQ(c.warnings.size(), bad.size());
	for (std::size_t k = 0; k < bad.size(); ++k)
	{
		const std::string& w = c.warnings[k];
		EXPECT_EQ(w.rfind(path + ":" + std::to_string(bad[k]) + ": ", 0), 0u) << w;
		EXPECT_NE(w.find(why[k]), std::string::npos) << "expected '" << why[k] << "' in: " << w;
		EXPECT_NE(w.find("skipped"), std::string::npos) << w;
		EXPECT_EQ(w.find('\n'), std::string::npos) << w;
	}
	EXPECT_EQ(c.stats.linesOrObjects, lines.size());
	EXPECT_EQ(c.events[0].sourceIndex, 3u);
	EXPECT_EQ(fmt6(c.events[2].timestamp), "100.600000");
}

TEST(CarmenLogReader, EstimatedScanCountAndCrlfAndGzip)
{
	TempDir tmp;
	std::string text = "# c\r\n";
	for (int i = 0; i < 7; ++i) text += flaser(180, fmt6(10.0 + i)) + "\r\n" + odom(i, 0, 0, fmt6(10.5 + i)) + "\r\n";
	const std::string plain = tmp.write("crlf.clf", text);
	auto reader = LogReader::open(plain);
	EXPECT_EQ(reader->estimatedScanCount(), 7u);
	const auto c = readAll(*reader);
	EXPECT_EQ(c.stats.scans, 7u);
	EXPECT_EQ(c.stats.odometry, 7u);
	EXPECT_TRUE(c.warnings.empty());

	const std::string gz = (tmp.dir / "zipped.clf.gz").string();
	{
		mrpt::io::CFileGZOutputStream out(gz);
		out.Write(text.data(), text.size());
	}
	auto zr = LogReader::open(gz);
	ASSERT_NE(dynamic_cast<CarmenLogReader*>(zr.get()), nullptr);
	EXPECT_EQ(zr->estimatedScanCount(), 7u);
	const auto z = readAll(*zr);
	ASSERT_EQ(z.events.size(), c.events.size());
	EXPECT_EQ(fmt6(z.events.back().timestamp), fmt6(c.events.back().timestamp));
}

TEST(LogReaderOpen, ClearErrorsAndContentDetection)
{
	TempDir tmp;
	auto expectError = [](const std::string& path, const std::string& word) {
		try
		{
			LogReader::open(path);
			ADD_FAILURE() << "no LogError for " << path;
		}
		catch (const LogError& e)
		{
			const std::string m = e.what();
			EXPECT_NE(m.find(path), std::string::npos) << m;
			EXPECT_NE(m.find(word), std::string::npos) << m;
			EXPECT_EQ(m.find('\n'), std::string::npos) << m;
		}
	};
	expectError((tmp.dir / "missing.clf").string(), "does not exist");
	expectError(tmp.dir.string(), "directory");
	expectError(tmp.write("empty.clf", ""), "empty");
	expectError(tmp.write("binary.dat", std::string("\x01\x02\x00\x03garbage\x00", 12)), "unknown log format");
	expectError(tmp.write("notes.dat", "hello world\nnothing here\n"), "unknown log format");
	expectError(tmp.write("bad.rawlog", "this is not a rawlog"), "rawlog");
	static_assert(std::is_base_of_v<std::runtime_error, LogError>);

	// Carmen detected by content whatever the name; comment lines skipped.
	auto r1 = LogReader::open(tmp.write("scans.dat", "# header\n\n" + flaser(180, "1.000000") + "\n"));
	EXPECT_NE(dynamic_cast<CarmenLogReader*>(r1.get()), nullptr);
	EXPECT_EQ(r1->path(), (tmp.dir / "scans.dat").string());
	// Carmen by extension even if the first line is unusual.
	auto r2 = LogReader::open(tmp.write("odd.txt", "NOTAKEYWORD 1 2 3\n" + flaser(180, "1.000000") + "\n"));
	EXPECT_NE(dynamic_cast<CarmenLogReader*>(r2.get()), nullptr);
	const auto c = readAll(*r2);
	EXPECT_EQ(c.stats.scans, 1u);
}

// ---------------------------------------------------------------- benchmark logs

TEST(CarmenDatasets, IntelAllScansWithExactTimestamps)
{
	const std::string path = datasetPath("intel");
	if (!fs::exists(path)) GTEST_SKIP() << "dataset not found: " << path;
	// First FLASER line's ipc_timestamp, straight from the text.
	std::string firstTs;
	{
		std::ifstream f(path);
		std::string l;
		while (std::getline(f, l) && firstTs.empty())
			if (l.rfind("FLASER ", 0) == 0)
			{
				std::istringstream s(l);
				std::vector<std::string> t;
				std::string w;
				while (s >> w) t.push_back(w);
				firstTs = t[std::stoul(t[1]) + 8];
			}
	}
	ASSERT_FALSE(firstTs.empty());
	auto reader = LogReader::open(path);
	EXPECT_EQ(reader->estimatedScanCount(), 13631u);
	const auto c = readAll(*reader);
	EXPECT_EQ(c.stats.scans, 13631u);
	EXPECT_EQ(c.stats.odometry, 26915u);
	EXPECT_EQ(c.stats.skipped, 0u);
	EXPECT_TRUE(c.warnings.empty()) << c.warnings.front();
	std::set<std::string> scanStamps;
	bool first = true;
	for (const auto& e : c.events)
	{
		if (e.kind != LogEvent::Kind::Scan) continue;
		if (first)
		{
			EXPECT_EQ(fmt6(e.timestamp), firstTs);
		}
		first = false;
		ASSERT_EQ(e.scan->getScanSize(), 180u);
		ASSERT_NEAR(e.scan->aperture, 179.0 * kDeg, 1e-6);
		scanStamps.insert(fmt6(e.timestamp));
	}
	// Every ground-truth relation refers to a scan by its exact ipc_timestamp.
	const std::string rel = std::string(PMSLAM_SOURCE_DIR) + "/../shared/datasets/intel/intel.relations";
	std::ifstream rf(rel);
	ASSERT_TRUE(rf.good()) << rel;
	std::string t1, t2, rest;
	std::size_t relations = 0, missing = 0;
	while (rf >> t1 >> t2 && std::getline(rf, rest))
	{
		++relations;
		missing += scanStamps.count(fmt6(std::stod(t1))) == 0;
		missing += scanStamps.count(fmt6(std::stod(t2))) == 0;
	}
	EXPECT_EQ(relations, 2984u);
	EXPECT_EQ(missing, 0u) << "of " << relations << " relations";
}

TEST(CarmenDatasets, Fr079HalfDegreeScansWithSensorOffset)
{
	const std::string path = datasetPath("fr079");
	if (!fs::exists(path)) GTEST_SKIP() << "dataset not found: " << path;
	const auto c = readFile(path);
	EXPECT_EQ(c.stats.scans, 4934u);
	EXPECT_EQ(c.stats.odometry, 8951u);
	EXPECT_EQ(c.stats.skipped, 0u);
	for (const auto& e : c.events)
	{
		if (e.kind != LogEvent::Kind::Scan) continue;
		ASSERT_EQ(e.scan->getScanSize(), 360u);
		ASSERT_NEAR(e.scan->aperture, 179.5 * kDeg, 1e-6);
		// The laser triple lies 0.04 m from the odometry triple along the robot's
		// x axis, on its negative side (PARAM robot_frontlaser_offset -0.04).
		ASSERT_NEAR(e.scan->sensorPose.x(), -0.04, 1e-3) << "line " << e.sourceIndex;
		ASSERT_NEAR(e.scan->sensorPose.y(), 0.0, 1e-3) << "line " << e.sourceIndex;
		ASSERT_NEAR(beamAngleInRobot(*e.scan, 0), -90.0 * kDeg, 1e-5);
	}
}

TEST(CarmenDatasets, AcesSaturatedReadingsAreNoReturn)
{
	const std::string path = datasetPath("aces");
	if (!fs::exists(path)) GTEST_SKIP() << "dataset not found: " << path;
	const auto c = readFile(path);
	EXPECT_EQ(c.stats.scans, 7374u);
	EXPECT_EQ(c.stats.odometry, 7375u);
	EXPECT_EQ(c.stats.skipped, 0u);
	std::size_t saturated = 0;
	for (const auto& e : c.events)
	{
		if (e.kind != LogEvent::Kind::Scan) continue;
		for (std::size_t i = 0; i < e.scan->getScanSize(); ++i)
			if (e.scan->getScanRange(i) >= 49.99f)
			{
				++saturated;
				ASSERT_FALSE(e.scan->getScanRangeValidity(i));
			}
	}
	EXPECT_GT(saturated, 0u);
}
