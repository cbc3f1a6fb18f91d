// Carmen logs compressed as they are distributed (bzip2: Radish's .clf.bz2 / .log.bz2; gzip), read through
// LogReader::open exactly like the plain file; damaged ones read up to the damage with one warning; a bzip2
// rawlog refused with a message saying what is read instead. pm-slam-app on a .clf.bz2: tests/apps.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <pmslam/io/CarmenLogReader.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/TextLineReader.h>

#include <string>
#include <vector>

#include "Bzip2.h"
#include "SyntheticLogs.h"

using namespace pmslam::testing;
using pmslam::CarmenLogReader;
using pmslam::LogError;
using pmslam::LogEvent;
using pmslam::LogReader;

namespace
{
/** ~560 kB of FLASER and ODOM lines, all valid: six bzip2 blocks at block size 1 (100 kB). */
std::string syntheticLog()
{
	const auto truth = roomPath(400);
	CarmenLogSpec spec;
	spec.odomLines = true;
	return carmenLog(furnishedRoom(), truth, driftingOdometry(truth, 1.02, 0.02), spec);
}

struct Read
{
	std::vector<LogEvent> events;
	std::vector<std::string> warnings;
	pmslam::LogReadStats stats;
	std::size_t estimatedScans = 0;
};

Read readLog(const std::string& path)
{
	Read r;
	auto reader = LogReader::open(path);
	EXPECT_NE(dynamic_cast<CarmenLogReader*>(reader.get()), nullptr) << path;
	reader->onWarning = [&](const std::string& w) { r.warnings.push_back(w); };
	r.estimatedScans = reader->estimatedScanCount();
	LogEvent ev;
	while (reader->next(ev)) r.events.push_back(ev);
	r.stats = reader->stats();
	return r;
}

/** Same event, field by field (the scans beam by beam). */
void expectSameEvent(const LogEvent& a, const LogEvent& b)
{
	ASSERT_EQ(a.kind, b.kind);
	EXPECT_EQ(a.timestamp, b.timestamp);
	EXPECT_EQ(a.sourceIndex, b.sourceIndex);
	EXPECT_EQ(a.odometry, b.odometry);
	EXPECT_EQ(a.scanHasOdometry, b.scanHasOdometry);
	EXPECT_EQ(a.scanOdometry, b.scanOdometry);
	ASSERT_EQ(bool(a.scan), bool(b.scan));
	if (!a.scan) return;
	ASSERT_EQ(a.scan->getScanSize(), b.scan->getScanSize());
	for (std::size_t i = 0; i < a.scan->getScanSize(); ++i)
	{
		ASSERT_EQ(a.scan->getScanRange(i), b.scan->getScanRange(i)) << "beam " << i;
		ASSERT_EQ(a.scan->getScanRangeValidity(i), b.scan->getScanRangeValidity(i)) << "beam " << i;
	}
	EXPECT_EQ(a.scan->aperture, b.scan->aperture);
	EXPECT_EQ(a.scan->maxRange, b.scan->maxRange);
	EXPECT_EQ(a.scan->sensorPose, b.scan->sensorPose);
	EXPECT_EQ(a.scan->timestamp, b.scan->timestamp);
}

/** `part` holds the first events of `whole`, each the same. */
void expectPrefix(const Read& part, const Read& whole)
{
	ASSERT_LE(part.events.size(), whole.events.size());
	for (std::size_t k = 0; k < part.events.size(); ++k)
	{
		SCOPED_TRACE("event " + std::to_string(k));
		expectSameEvent(part.events[k], whole.events[k]);
	}
}

void writeGzip(const std::string& path, const std::string& text)
{
	mrpt::io::CFileGZOutputStream out(path);
	out.Write(text.data(), text.size());
}
}  // namespace

TEST(CompressedCarmenLog, Bzip2GivesExactlyThePlainFilesEvents)
{
	ScratchDir d("bz2-same");
	const std::string text = syntheticLog();
	const Read plain = readLog(d.write("room.clf", text));
	ASSERT_EQ(plain.stats.scans, 400u);
	ASSERT_EQ(plain.stats.odometry, 400u);
	ASSERT_TRUE(plain.warnings.empty());

	const std::string bz = bzip2(text, 1);
	ASSERT_GT(text.size(), 5 * 100000u);	 // several bzip2 blocks
	// As Radish names them, named otherwise (told by content), and as pbzip2 writes them: several streams.
	const std::vector<std::string> files = {
		d.write("room.clf.bz2", bz), d.write("room.log.bz2", bz), d.write("room-no-extension", bz),
		d.write("room-pbzip2.clf.bz2", bzip2(text.substr(0, 200000), 1) + bzip2(text.substr(200000), 1))};
	for (const std::string& f : files)
	{
		SCOPED_TRACE(f);
		const Read z = readLog(f);
		EXPECT_TRUE(z.warnings.empty()) << z.warnings.front();
		EXPECT_EQ(z.stats.linesOrObjects, plain.stats.linesOrObjects);
		EXPECT_EQ(z.stats.skipped, 0u);
		EXPECT_EQ(z.estimatedScans, plain.estimatedScans);
		ASSERT_EQ(z.events.size(), plain.events.size());
		expectPrefix(z, plain);
	}
}

TEST(CompressedCarmenLog, GzipGivesExactlyThePlainFilesEvents)
{
	ScratchDir d("gz-same");
	const std::string text = syntheticLog();
	const Read plain = readLog(d.write("room.clf", text));
	const std::string gz = d.path("room.clf.gz");
	writeGzip(gz, text);
	const Read z = readLog(gz);
	EXPECT_TRUE(z.warnings.empty());
	ASSERT_EQ(z.events.size(), plain.events.size());
	expectPrefix(z, plain);
}

TEST(CompressedCarmenLog, TruncatedBzip2IsReadUpToTheDamageWithOneWarning)
{
	ScratchDir d("bz2-truncated");
	const std::string text = syntheticLog();
	const Read plain = readLog(d.write("room.clf", text));
	const std::string bz = bzip2(text, 1);
	const std::string path = d.write("room.clf.bz2", bz.substr(0, bz.size() * 6 / 10));

	const Read z = readLog(path);
	// bzip2 checks whole blocks: the complete blocks before the cut (3 of 6: ~300 kB of text) are read.
	EXPECT_GT(z.events.size(), plain.events.size() / 3);
	EXPECT_LT(z.events.size(), plain.events.size() * 6 / 10);
	expectPrefix(z, plain);
	ASSERT_EQ(z.warnings.size(), 1u);
	// Every line is an event here: the damage is met reading the line after the last event.
	const std::string line = std::to_string(z.events.back().sourceIndex + 1);
	EXPECT_EQ(z.warnings[0], path + ":" + line + ": read error (bzip2: data ends early (truncated file)), stopping");
	EXPECT_EQ(z.stats.warnings, 1u);
	EXPECT_EQ(z.stats.skipped, 0u);
	EXPECT_EQ(z.stats.scans + z.stats.odometry, z.events.size());
	// Progress counts what can be read.
	EXPECT_EQ(z.estimatedScans, z.stats.scans);
}

TEST(CompressedCarmenLog, CorruptBzip2BlockStopsWithOneReadErrorNeverACrash)
{
	ScratchDir d("bz2-corrupt");
	const std::string text = syntheticLog();
	const Read plain = readLog(d.write("room.clf", text));
	std::string bz = bzip2(text, 1);
	for (std::size_t i = 0; i < 16; ++i) bz[bz.size() * 7 / 10 + i] ^= 0x5a;
	const std::string path = d.write("room.clf.bz2", bz);

	const Read z = readLog(path);
	// The blocks before the damage are intact (a block holds ~70 lines here); the damaged block's text
	// reaches the reader before bzip2 checks it, where the line checks skip what it garbled.
	ASSERT_GT(z.events.size(), 100u);
	EXPECT_LT(z.events.size(), plain.events.size());
	Read first = z;
	first.events.resize(100);
	expectPrefix(first, plain);
	ASSERT_FALSE(z.warnings.empty());
	EXPECT_EQ(z.warnings.back().rfind(path + ":", 0), 0u) << z.warnings.back();
	EXPECT_NE(z.warnings.back().find(": read error (bzip2: damaged data"), std::string::npos) << z.warnings.back();
	EXPECT_NE(z.warnings.back().find("), stopping"), std::string::npos) << z.warnings.back();
	for (const std::string& w : z.warnings) EXPECT_EQ(w.find('\n'), std::string::npos) << w;
}

TEST(CompressedCarmenLog, TruncatedGzipIsReadUpToTheDamageWithOneWarning)
{
	ScratchDir d("gz-truncated");
	const std::string text = syntheticLog();
	const Read plain = readLog(d.write("room.clf", text));
	const std::string whole = d.path("whole.clf.gz");
	writeGzip(whole, text);
	const std::string gz = readText(whole);
	const std::string path = d.write("room.clf.gz", gz.substr(0, gz.size() / 2));

	const Read z = readLog(path);
	// gzip decompresses as it goes: about half the lines come out.
	EXPECT_GT(z.events.size(), plain.events.size() * 4 / 10);
	EXPECT_LT(z.events.size(), plain.events.size() * 6 / 10);
	expectPrefix(z, plain);
	ASSERT_EQ(z.warnings.size(), 1u);
	const std::string line = std::to_string(z.events.back().sourceIndex + 1);
	EXPECT_EQ(z.warnings[0], path + ":" + line + ": read error (gzip: data ends early (truncated file)), stopping");
}

TEST(CompressedCarmenLog, Bzip2RawlogIsRefusedSayingWhatIsRead)
{
	ScratchDir d("bz2-rawlog");
	const std::string raw = d.path("room.rawlog");
	const auto truth = roomPath(20);
	writeRawlog(raw, furnishedRoom(), truth, truth, RawlogSpec());
	ASSERT_NO_THROW(LogReader::open(raw));
	for (const std::string name : {"room.rawlog.bz2", "room.bz2"})
	{
		const std::string path = d.write(name, bzip2(readText(raw)));
		try
		{
			LogReader::open(path);
			ADD_FAILURE() << "no LogError for " << path;
		}
		catch (const LogError& e)
		{
			const std::string m = e.what();
			EXPECT_EQ(m.rfind("pmslam: '" + path + "' is bzip2-compressed but not a Carmen log", 0), 0u) << m;
			EXPECT_NE(m.find("MRPT .rawlog plain or gz-compressed"), std::string::npos) << m;
			EXPECT_EQ(m.find("unknown log format"), std::string::npos) << m;
			EXPECT_EQ(m.find('\n'), std::string::npos) << m;
		}
	}
}

TEST(TextLineReader, LinesOfPlainGzipAndBzip2FilesAlike)
{
	ScratchDir d("text-lines");
	const std::string text = "first\r\n\nthird line\nlast without newline";
	const std::string gz = d.path("t.gz");
	writeGzip(gz, text);
	for (const std::string& path : {d.write("t.txt", text), gz, d.write("t.bz2", bzip2(text))})
	{
		SCOPED_TRACE(path);
		pmslam::TextLineReader in;
		ASSERT_TRUE(in.open(path));
		std::vector<std::string> lines;
		for (std::string l; in.getline(l);) lines.push_back(l);
		EXPECT_EQ(lines, (std::vector<std::string>{"first\r", "", "third line", "last without newline"}));
	}
	pmslam::TextLineReader none;
	EXPECT_FALSE(none.open(d.path("missing.txt")));
}
