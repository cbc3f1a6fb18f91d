// Trajectory and relations text files, atomic writing, and the Carmen export.
#include <gtest/gtest.h>
#include <pmslam/io/AtomicFile.h>
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pmslam;

namespace
{
class TrajectoryIo : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
		m_dir = fs::temp_directory_path() /
				("pmslam_test_trajectory_io_" + std::to_string(::getpid()) + "_" + info->name());
		fs::remove_all(m_dir);
		fs::create_directories(m_dir);
	}
	void TearDown() override { fs::remove_all(m_dir); }

	std::string path(const std::string& name) const { return (m_dir / name).string(); }
	std::string write(const std::string& name, const std::string& content) const
	{
		std::ofstream(path(name)) << content;
		return path(name);
	}
	static std::string read(const std::string& p)
	{
		std::ifstream in(p);
		std::stringstream ss;
		ss << in.rdbuf();
		return ss.str();
	}
	// Names in the directory other than `keep`.
	std::vector<std::string> strayFiles(const std::string& keep) const
	{
		std::vector<std::string> out;
		for (const auto& e : fs::directory_iterator(m_dir))
			if (e.path().filename() != keep) out.push_back(e.path().filename().string());
		return out;
	}
	template <class F>
	static std::string errorOf(F&& f)
	{
		try
		{
			f();
		}
		catch (const std::runtime_error& e)
		{
			return e.what();
		}
		return "(no exception)";
	}

	fs::path m_dir;
};
}  // namespace

TEST_F(TrajectoryIo, RoundTripIsExactToMicroseconds)
{
	const Trajectory t = {{976052857.123456, 1.5, -2.25, 0.12345678},
						  {976052857.323457, -0.000001, 123.456789, -3.14159265},
						  {70.000001, 0, 0, 0}};
	const std::string p = path("traj.txt");
	saveTrajectory(p, t, "pmslam test\nsecond line");
	const std::string text = read(p);
	EXPECT_EQ(text.rfind("# pmslam test\n# second line\n", 0), 0u) << text;
	EXPECT_NE(text.find("976052857.123456 1.500000 -2.250000 0.12345678\n"), std::string::npos) << text;

	const Trajectory back = loadTrajectory(p);
	ASSERT_EQ(back.size(), t.size());
	for (size_t i = 0; i < t.size(); ++i)
	{
		EXPECT_NEAR(back[i].timestamp, t[i].timestamp, 1e-6) << i;
		EXPECT_EQ(back[i].timestamp, t[i].timestamp) << i;  // 6 decimals reproduce these doubles exactly
		EXPECT_NEAR(back[i].x, t[i].x, 1e-6) << i;
		EXPECT_NEAR(back[i].y, t[i].y, 1e-6) << i;
		EXPECT_NEAR(back[i].yaw, t[i].yaw, 1e-8) << i;
	}
	EXPECT_TRUE(strayFiles("traj.txt").empty());
}

TEST_F(TrajectoryIo, LoadSkipsCommentsAndBlankLines)
{
	const std::string p = write("t.txt", "# header\n\n   \n1.0 2 3 0.5\r\n  # indented comment\n\t2.0\t4 5 -0.5  \n");
	const Trajectory t = loadTrajectory(p);
	ASSERT_EQ(t.size(), 2u);
	EXPECT_EQ(t[0].timestamp, 1.0);
	EXPECT_EQ(t[0].yaw, 0.5);
	EXPECT_EQ(t[1].x, 4.0);
	EXPECT_EQ(t[1].yaw, -0.5);
}

TEST_F(TrajectoryIo, MalformedTrajectoryLineNamesFileAndLine)
{
	const std::string p = write("bad.txt", "# c\n1 2 3 4\n1 2 3\n");
	const std::string msg = errorOf([&] { loadTrajectory(p); });
	EXPECT_NE(msg.find(p + ":3: expected 'timestamp x y yaw', got '1 2 3'"), std::string::npos) << msg;

	const std::string p2 = write("bad2.txt", "1 2 3 4 5\n");
	EXPECT_NE(errorOf([&] { loadTrajectory(p2); }).find(p2 + ":1: expected"), std::string::npos);
	const std::string p3 = write("bad3.txt", "1 2 3 4\n\n1 2 x 4\n");
	EXPECT_NE(errorOf([&] { loadTrajectory(p3); }).find(p3 + ":3: expected"), std::string::npos);
	const std::string p4 = write("bad4.txt", "1 2 3 nan\n");
	EXPECT_NE(errorOf([&] { loadTrajectory(p4); }).find(p4 + ":1: expected"), std::string::npos);
}

TEST_F(TrajectoryIo, MissingFileIsAnError)
{
	const std::string p = path("does-not-exist.txt");
	const std::string msg = errorOf([&] { loadTrajectory(p); });
	EXPECT_NE(msg.find(p + ": cannot open"), std::string::npos) << msg;
	EXPECT_NE(errorOf([&] { loadRelations(p); }).find(p + ": cannot open"), std::string::npos);
}

TEST_F(TrajectoryIo, LoadRelations)
{
	const std::string p = write("r.relations",
								"976052905.167303 976052911.885496 -0.056990 -0.128430 0.000000 0.000000 "
								"0.000000 -1.682210\n\n1 2 0.1 0.2 0 0 0 3.0\n");
	const auto r = loadRelations(p);
	ASSERT_EQ(r.size(), 2u);
	EXPECT_EQ(r[0].t1, 976052905.167303);
	EXPECT_EQ(r[0].t2, 976052911.885496);
	EXPECT_EQ(r[0].x, -0.056990);
	EXPECT_EQ(r[0].y, -0.128430);
	EXPECT_EQ(r[0].yaw, -1.682210);
	EXPECT_EQ(r[1].yaw, 3.0);
}

TEST_F(TrajectoryIo, MalformedRelationLineNamesFileAndLine)
{
	const std::string p = write("bad.relations", "1 2 0 0 0 0 0 0\n# ok\n1 2 0 0 0 0 0\n");
	const std::string msg = errorOf([&] { loadRelations(p); });
	EXPECT_NE(msg.find(p + ":3: expected 't1 t2 x y z roll pitch yaw', got '1 2 0 0 0 0 0'"), std::string::npos)
		<< msg;
}

TEST_F(TrajectoryIo, AtomicWriteReplacesAndLeavesNoTempFile)
{
	const std::string p = path("out.txt");
	writeFileAtomically(p, [](std::ostream& os) { os << "old\n"; });
	EXPECT_EQ(read(p), "old\n");
	writeFileAtomically(p, [](std::ostream& os) { os << "new\n"; });
	EXPECT_EQ(read(p), "new\n");
	EXPECT_TRUE(strayFiles("out.txt").empty());
}

TEST_F(TrajectoryIo, AtomicWriteKeepsOldFileWhenWriterThrows)
{
	const std::string p = write("out.txt", "precious\n");
	EXPECT_THROW(writeFileAtomically(p,
									 [](std::ostream& os) {
										 os << std::string(200000, 'x');  // more than one buffer reaches the disk
										 throw std::logic_error("writer failed");
									 }),
				 std::logic_error);
	EXPECT_EQ(read(p), "precious\n");
	EXPECT_TRUE(strayFiles("out.txt").empty());
}

TEST_F(TrajectoryIo, AtomicWriteFailureNamesPath)
{
	const std::string p = path("no/such/dir/out.txt");
	const std::string msg = errorOf([&] { writeFileAtomically(p, [](std::ostream& os) { os << "x"; }); });
	EXPECT_NE(msg.find(p), std::string::npos) << msg;
	EXPECT_NE(msg.find("No such file or directory"), std::string::npos) << msg;

	// Renaming over a directory fails: the temporary file must not remain.
	fs::create_directories(path("adir"));
	const std::string msg2 = errorOf([&] { writeFileAtomically(path("adir"), [](std::ostream& os) { os << "x"; }); });
	EXPECT_NE(msg2.find(path("adir")), std::string::npos) << msg2;
	EXPECT_TRUE(strayFiles("adir").empty());
}

TEST_F(TrajectoryIo, AtomicWriteToAPipeWritesIntoItAndKeepsIt)
{
	// A FIFO stands for /dev/null or /dev/stdout: renaming a file over it would replace the device.
	const std::string p = path("pipe");
	ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
	const int reader = ::open(p.c_str(), O_RDONLY | O_NONBLOCK);  // so that the writer's open does not block
	ASSERT_GE(reader, 0);
	writeFileAtomically(p, [](std::ostream& os) { os << "through the pipe\n"; });
	char buf[64] = {};
	const ssize_t n = ::read(reader, buf, sizeof buf - 1);
	::close(reader);
	EXPECT_EQ(std::string(buf, n > 0 ? std::size_t(n) : 0), "through the pipe\n");
	EXPECT_TRUE(fs::is_fifo(p));
	EXPECT_TRUE(strayFiles("pipe").empty());
}

TEST_F(TrajectoryIo, SaveRejectsNonFinite)
{
	const std::string p = path("t.txt");
	EXPECT_THROW(saveTrajectory(p, {{1.0, 0, 0, std::nan("")}}), std::invalid_argument);
	EXPECT_FALSE(fs::exists(p));
}

TEST_F(TrajectoryIo, CheckDirectoryWritable)
{
	const std::string nested = path("a/b/c");
	EXPECT_NO_THROW(checkDirectoryWritable(nested));
	EXPECT_TRUE(fs::is_directory(nested));
	EXPECT_TRUE(fs::is_empty(nested));  // the probe file is removed

	const std::string file = write("plain-file", "x");
	const std::string msg = errorOf([&] { checkDirectoryWritable(file); });
	EXPECT_NE(msg.find(file), std::string::npos) << msg;
	EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
	const std::string msg2 = errorOf([&] { checkDirectoryWritable(file + "/sub"); });
	EXPECT_NE(msg2.find("cannot create directory '" + file + "/sub'"), std::string::npos) << msg2;
}

TEST_F(TrajectoryIo, CarmenLogHasOneFlaserLinePerPose)
{
	const std::string p = path("out.clf");
	writeCarmenLog(p, {{976052857.123456, 1.5, -2.0, 0.25}, {976052857.5, 0, 0, -3.0}});
	EXPECT_EQ(read(p),
			  "FLASER 0 1.500000 -2.000000 0.25000000 1.500000 -2.000000 0.25000000 976052857.123456 pmslam "
			  "976052857.123456\n"
			  "FLASER 0 0.000000 0.000000 -3.00000000 0.000000 0.000000 -3.00000000 976052857.500000 pmslam "
			  "976052857.500000\n");
	EXPECT_TRUE(strayFiles("out.clf").empty());
}
