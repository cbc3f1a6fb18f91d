/* pm-icp-slam, the MRPT ICP-SLAM peer of the benchmark: runs the built program
 * on MRPT's sample log with the project's tuned configuration. */
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace
{
const std::string kBinary = PMSLAM_BINARY_DIR "/bin/pm-icp-slam";
const std::string kTunedConfig = PMSLAM_SOURCE_DIR "/config/icp-slam-tuned.ini";
const std::string kSampleLog = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";

std::string quote(const std::string& s)
{
	std::string q = "'";
	for (const char c : s)
	{
		if (c == '\'') q += "'\\''";
		else q += c;
	}
	return q + "'";
}

struct RunResult
{
	int exitCode = -1;
	std::string out, err;
};

std::string slurp(const fs::path& p)
{
	std::ifstream in(p);
	std::stringstream ss;
	ss << in.rdbuf();
	return ss.str();
}

/** Non-comment, non-blank lines of a text file. */
std::vector<std::string> dataLines(const fs::path& p)
{
	std::ifstream in(p);
	std::vector<std::string> lines;
	for (std::string line; std::getline(in, line);)
		if (!line.empty() && line[0] != '#') lines.push_back(line);
	return lines;
}

class IcpPeer : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		if (!fs::exists(kBinary)) GTEST_FAIL() << kBinary << " is not built";
		m_dir = fs::temp_directory_path() / ("pmslam-icp-peer-" + std::to_string(::getpid()) + "-" +
											 ::testing::UnitTest::GetInstance()->current_test_info()->name());
		fs::remove_all(m_dir);
		fs::create_directories(m_dir);
	}
	void TearDown() override
	{
		std::error_code ec;
		fs::remove_all(m_dir, ec);
	}

	RunResult run(const std::string& args) const
	{
		const fs::path out = m_dir / "stdout.txt", err = m_dir / "stderr.txt";
		const std::string cmd = quote(kBinary) + " " + args + " >" + quote(out.string()) + " 2>" + quote(err.string());
		const int status = std::system(cmd.c_str());
		RunResult r;
		r.exitCode = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
		r.out = slurp(out);
		r.err = slurp(err);
		return r;
	}

	fs::path m_dir;
};
}  // namespace

TEST_F(IcpPeer, MapsTheSampleLogWithTheTunedConfig)
{
	if (!fs::exists(kSampleLog)) GTEST_SKIP() << "MRPT sample log not installed: " << kSampleLog;
	ASSERT_TRUE(fs::exists(kTunedConfig)) << kTunedConfig;
	const fs::path out = m_dir / "out";
	const RunResult r = run("--config " + quote(kTunedConfig) + " --out " + quote(out.string()) + " --max-scans 60 " +
							quote(kSampleLog));
	ASSERT_EQ(r.exitCode, 0) << "stderr: " << r.err << "\nstdout: " << r.out;

	const auto traj = dataLines(out / "trajectory.txt");
	ASSERT_EQ(traj.size(), 60u);
	double lastX = 0, lastY = 0;
	for (const auto& line : traj)
	{
		std::istringstream ss(line);
		double t, x, y, yaw;
		ASSERT_TRUE(ss >> t >> x >> y >> yaw) << "malformed trajectory line '" << line << "'";
		EXPECT_TRUE(std::isfinite(x) && std::isfinite(y) && std::isfinite(yaw)) << line;
		lastX = x;
		lastY = y;
	}
	// The robot drives off along the corridor: the peer must move (MRPT's own
	// icp-slam stays at the origin on mis-imported logs).
	EXPECT_GT(std::hypot(lastX, lastY), 0.5);

	EXPECT_EQ(dataLines(out / "timing.txt").size(), 60u);
	EXPECT_NE(r.out.find("time per scan"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("peak memory"), std::string::npos) << r.out;
}

TEST_F(IcpPeer, MissingConfigIsAnInputError)
{
	const fs::path missing = m_dir / "no-such-config.ini";
	const RunResult r = run("--config " + quote(missing.string()) + " --out " + quote((m_dir / "out").string()) + " " +
							quote(kSampleLog));
	EXPECT_EQ(r.exitCode, 2) << r.err;
	EXPECT_NE(r.err.find("pm-icp-slam:"), std::string::npos) << r.err;
	EXPECT_NE(r.err.find("no-such-config.ini"), std::string::npos) << r.err;
	EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "expected one line, got: " << r.err;
	EXPECT_FALSE(fs::exists(m_dir / "out" / "trajectory.txt"));
}

TEST_F(IcpPeer, MissingConfigOptionIsAnInputError)
{
	const RunResult r = run(quote(kSampleLog));
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.err.find("--config"), std::string::npos) << r.err;
}
