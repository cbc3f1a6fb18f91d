// Relative pose error metric (Kümmerle et al. 2009) on hand-computed cases, and pm-slam-eval end to end.
#include <gtest/gtest.h>
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace pmslam;

namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Ground truth: straight line along x, 1 m apart, at t = 1, 2, 3, 4.
Trajectory straightLine()
{
	return {{1.0, 0, 0, 0}, {2.0, 1, 0, 0}, {3.0, 2, 0, 0}, {4.0, 3, 0, 0}};
}

// Relations between ground-truth poses, computed by hand for straightLine().
std::vector<Relation> straightLineRelations()
{
	return {{1.0, 2.0, 1, 0, 0}, {2.0, 3.0, 1, 0, 0}, {1.0, 3.0, 2, 0, 0}, {3.0, 4.0, 1, 0, 0}};
}
}  // namespace

TEST(RelativePoseEvaluation, IdentityHasZeroError)
{
	const auto e = evaluateRelativePoses(straightLine(), straightLineRelations());
	EXPECT_EQ(e.matched, 4u);
	EXPECT_EQ(e.missing, 0u);
	ASSERT_EQ(e.transErrors.size(), 4u);
	ASSERT_EQ(e.rotErrorsDeg.size(), 4u);
	EXPECT_EQ(e.transMean, 0.0);
	EXPECT_EQ(e.transMax, 0.0);
	EXPECT_EQ(e.rotMeanDeg, 0.0);
	EXPECT_EQ(e.rotMaxDeg, 0.0);
}

TEST(RelativePoseEvaluation, RigidMotionOfWholeTrajectoryHasZeroError)
{
	// Rotate the whole trajectory by 70° about the origin and shift it: relative poses do not change.
	const double a = 70 * kDeg, c = std::cos(a), s = std::sin(a);
	Trajectory moved;
	for (const auto& p : straightLine())
		moved.push_back({p.timestamp, c * p.x - s * p.y + 5.0, s * p.x + c * p.y - 3.0, p.yaw + a});
	const auto e = evaluateRelativePoses(moved, straightLineRelations());
	EXPECT_EQ(e.matched, 4u);
	EXPECT_NEAR(e.transMax, 0.0, 1e-12);
	EXPECT_NEAR(e.rotMaxDeg, 0.0, 1e-10);
}

TEST(RelativePoseEvaluation, OffsetInOnePose)
{
	// Pose at t=2 is wrong by (0, +0.1 m, +10°).
	Trajectory t = straightLine();
	t[1] = {2.0, 1.0, 0.1, 10 * kDeg};
	const auto e = evaluateRelativePoses(t, straightLineRelations());
	ASSERT_EQ(e.matched, 4u);
	// (1→2): δ = (1, 0.1, 10°), δ* = (1, 0, 0) → e = (0, 0.1, 10°).
	EXPECT_NEAR(e.transErrors[0], 0.1, 1e-12);
	EXPECT_NEAR(e.rotErrorsDeg[0], 10.0, 1e-10);
	// (2→3): δ = R(−10°)·(1, −0.1), yaw −10°; δ* = (1, 0, 0) → e.xy = δ.xy − (1, 0).
	const double c = std::cos(10 * kDeg), s = std::sin(10 * kDeg);
	const double ex = c * 1 + s * -0.1 - 1, ey = -s * 1 + c * -0.1;
	const double e23 = std::sqrt(ex * ex + ey * ey);  // = 0.27406...
	EXPECT_NEAR(e23, 0.274069, 1e-6);
	EXPECT_NEAR(e.transErrors[1], e23, 1e-12);
	EXPECT_NEAR(e.rotErrorsDeg[1], 10.0, 1e-10);
	// (1→3) and (3→4) do not involve the bad pose.
	EXPECT_NEAR(e.transErrors[2], 0.0, 1e-12);
	EXPECT_NEAR(e.transErrors[3], 0.0, 1e-12);
	EXPECT_NEAR(e.rotErrorsDeg[2], 0.0, 1e-10);

	const double mean = (0.1 + e23) / 4;
	EXPECT_NEAR(e.transMean, mean, 1e-12);
	EXPECT_NEAR(e.transMeanSq, (0.01 + e23 * e23) / 4, 1e-12);
	EXPECT_NEAR(e.transStd, std::sqrt((0.01 + e23 * e23) / 4 - mean * mean), 1e-12);  // population std
	EXPECT_NEAR(e.transMax, e23, 1e-12);
	EXPECT_NEAR(e.rotMeanDeg, 5.0, 1e-10);
	EXPECT_NEAR(e.rotStdDeg, 5.0, 1e-10);  // values {10, 10, 0, 0}
	EXPECT_NEAR(e.rotMeanSqDeg2, 50.0, 1e-8);
	EXPECT_NEAR(e.rotMaxDeg, 10.0, 1e-10);
}

TEST(RelativePoseEvaluation, MissingTimestampsAreCounted)
{
	std::vector<Relation> rel = straightLineRelations();
	rel.push_back({2.0, 99.0, 1, 0, 0});  // t2 missing
	rel.push_back({0.5, 3.0, 1, 0, 0});	  // t1 missing
	rel.push_back({2.0000011, 3.0, 1, 0, 0});  // 1.1 µs away: beyond the 1e-6 s tolerance
	const auto e = evaluateRelativePoses(straightLine(), rel);
	EXPECT_EQ(e.matched, 4u);
	EXPECT_EQ(e.missing, 3u);
	EXPECT_EQ(e.transErrors.size(), 4u);

	const auto none = evaluateRelativePoses({}, rel);
	EXPECT_EQ(none.matched, 0u);
	EXPECT_EQ(none.missing, rel.size());
	EXPECT_EQ(none.transMean, 0.0);
}

TEST(RelativePoseEvaluation, EpochTimestampsMatchWithinTolerance)
{
	// Unsorted trajectory with absolute epoch stamps (as in intel).
	const Trajectory t = {{976052857.323457, 1, 0, 0}, {976052857.123456, 0, 0, 0}};
	const std::vector<Relation> rel = {{976052857.123456, 976052857.323457, 1, 0, 0},
									   {976052857.123460, 976052857.323457, 1, 0, 0}};	// 4 µs off
	const auto e = evaluateRelativePoses(t, rel);
	EXPECT_EQ(e.matched, 1u);
	EXPECT_EQ(e.missing, 1u);
	EXPECT_NEAR(e.transMean, 0.0, 1e-12);
	EXPECT_EQ(evaluateRelativePoses(t, rel, 1e-5).matched, 2u);
}

TEST(RelativePoseEvaluation, AngleWrapAround)
{
	// Estimated relative yaw −179°, true +179°: the error is 2°, not 358°.
	const Trajectory t = {{1.0, 0, 0, 0}, {2.0, 0, 0, -179 * kDeg}};
	const auto e = evaluateRelativePoses(t, {{1.0, 2.0, 0, 0, 179 * kDeg}});
	ASSERT_EQ(e.matched, 1u);
	EXPECT_NEAR(e.rotMeanDeg, 2.0, 1e-9);
	EXPECT_NEAR(e.transMean, 0.0, 1e-12);

	// Same with absolute yaws far outside (−π, π].
	const Trajectory t2 = {{1.0, 0, 0, 4 * kPi + 170 * kDeg}, {2.0, 0, 0, -6 * kPi - 171 * kDeg}};
	EXPECT_NEAR(evaluateRelativePoses(t2, {{1.0, 2.0, 0, 0, 20 * kDeg}}).rotMeanDeg, 1.0, 1e-9);
}

TEST(RelativePoseEvaluation, TranslationIsMeasuredInTheFrameOfT1)
{
	// Robot at t1 faces +y; it moves 1 m forward (to (0, 1)). The relation says 1 m forward too.
	const Trajectory t = {{1.0, 0, 0, 90 * kDeg}, {2.0, 0, 1, 90 * kDeg}};
	EXPECT_NEAR(evaluateRelativePoses(t, {{1.0, 2.0, 1, 0, 0}}).transMean, 0.0, 1e-12);
	// A relation claiming 1 m sideways (left) is off by sqrt(2).
	EXPECT_NEAR(evaluateRelativePoses(t, {{1.0, 2.0, 0, 1, 0}}).transMean, std::sqrt(2.0), 1e-12);
}

TEST(RelativePoseEvaluation, LargeTrajectoryLookup)
{
	// 30k poses, 3k relations: exercises the sorted lookup (and must be fast).
	Trajectory t;
	for (int i = 0; i < 30000; ++i) t.push_back({1000.0 + 0.1 * i, 0.01 * i, 0, 0});
	std::vector<Relation> rel;
	for (int k = 0; k < 3000; ++k)
	{
		const int i = (k * 7919) % 29990;
		rel.push_back({t[i].timestamp, t[i + 5].timestamp, 0.05, 0, 0});
	}
	const auto e = evaluateRelativePoses(t, rel);
	EXPECT_EQ(e.matched, 3000u);
	EXPECT_NEAR(e.transMax, 0.0, 1e-9);
}

// ---------------------------------------------------------------- pm-slam-eval end to end

namespace
{
struct RunResult
{
	int exitCode = -1;
	std::string out;
};

// Run the program with `args` (already shell-quoted); stdout captured, stderr merged if asked.
RunResult run(const std::string& args, bool mergeStderr = false)
{
	const std::string cmd =
		std::string("'") + PMSLAM_BINARY_DIR "/bin/pm-slam-eval' " + args + (mergeStderr ? " 2>&1" : " 2>/dev/null");
	RunResult r;
	FILE* p = ::popen(cmd.c_str(), "r");
	if (!p) return r;
	std::array<char, 4096> buf;
	size_t n;
	while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
	const int status = ::pclose(p);
	r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
	return r;
}

class PmSlamEval : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		ASSERT_TRUE(fs::exists(PMSLAM_BINARY_DIR "/bin/pm-slam-eval"))
			<< "build the pm-slam-eval target first (" PMSLAM_BINARY_DIR "/bin/pm-slam-eval)";
		const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
		m_dir = fs::temp_directory_path() / ("pmslam_test_eval_" + std::to_string(::getpid()) + "_" + info->name());
		fs::remove_all(m_dir);
		fs::create_directories(m_dir);
		m_traj = (m_dir / "traj.txt").string();
		m_rel = (m_dir / "gt.relations").string();
		Trajectory t = straightLine();
		t[1] = {2.0, 1.0, 0.1, 10 * kDeg};
		saveTrajectory(m_traj, t, "test");
		std::ofstream(m_rel) << "1.000000 2.000000 1 0 0 0 0 0\n"
								"2.000000 3.000000 1 0 0 0 0 0\n"
								"1.000000 3.000000 2 0 0 0 0 0\n"
								"3.000000 4.000000 1 0 0 0 0 0\n"
								"3.000000 9.000000 1 0 0 0 0 0\n";
	}
	void TearDown() override { fs::remove_all(m_dir); }
	static std::string q(const std::string& s) { return "'" + s + "'"; }

	fs::path m_dir;
	std::string m_traj, m_rel;
};
}  // namespace

TEST_F(PmSlamEval, PrintsErrors)
{
	const RunResult r = run(q(m_traj) + " " + q(m_rel));
	EXPECT_EQ(r.exitCode, 0) << r.out;
	EXPECT_NE(r.out.find("relations matched: 4, missing: 1"), std::string::npos) << r.out;
	// mean (0.1 + 0.274069)/4 = 0.0935, rot {10, 10, 0, 0}: 5 ± 5, mean of squares 50, max 10.
	EXPECT_NE(r.out.find("translational error [m]: 0.0935 +/- "), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("max 0.2741"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("rotational error [deg]:  5.000 +/- 5.000, mean of squares 50.0000 deg^2, max 10.000"),
			  std::string::npos)
		<< r.out;
}

TEST_F(PmSlamEval, JsonAndCarmenOutputWithOptionsAnywhere)
{
	const std::string clf = (m_dir / "out.clf").string();
	const RunResult r = run(q(m_traj) + " --json " + q(m_rel) + " --carmen-out " + q(clf));
	EXPECT_EQ(r.exitCode, 0) << r.out;
	EXPECT_EQ(r.out.front(), '{') << r.out;
	EXPECT_NE(r.out.find("\"matched\": 4, \"missing\": 1"), std::string::npos) << r.out;
	// Yaw is stored with 8 decimals (radians), so 10° reads back as 10.0000003°.
	EXPECT_NE(r.out.find("\"rot_mean_deg\": 5.00000"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("\"rot_max_deg\": 10.00000"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("\"trans_max_m\": 0.27406"), std::string::npos) << r.out;
	EXPECT_EQ(r.out.back(), '\n');
	std::ifstream in(clf);
	std::string line;
	int lines = 0;
	while (std::getline(in, line))
	{
		++lines;
		EXPECT_EQ(line.rfind("FLASER 0 ", 0), 0u) << line;
	}
	EXPECT_EQ(lines, 4);
}

TEST_F(PmSlamEval, HelpExitsZero)
{
	const RunResult r = run("--help");
	EXPECT_EQ(r.exitCode, 0);
	EXPECT_EQ(r.out.rfind("usage: pm-slam-eval", 0), 0u) << r.out;
}

TEST_F(PmSlamEval, ErrorsExitTwoWithOneLineMessage)
{
	const std::string missing = (m_dir / "missing.txt").string();
	RunResult r = run(q(missing) + " " + q(m_rel), true);
	EXPECT_EQ(r.exitCode, 2) << r.out;
	EXPECT_NE(r.out.find(missing + ": cannot open"), std::string::npos) << r.out;
	EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << r.out;  // one line

	const std::string bad = (m_dir / "bad.relations").string();
	std::ofstream(bad) << "1 2 1 0 0 0 0 0\n1 2 1 0\n";
	r = run(q(m_traj) + " " + q(bad), true);
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.out.find(bad + ":2: expected 't1 t2 x y z roll pitch yaw'"), std::string::npos) << r.out;

	const std::string unmatched = (m_dir / "unmatched.relations").string();
	std::ofstream(unmatched) << "100 200 1 0 0 0 0 0\n";
	r = run(q(m_traj) + " " + q(unmatched), true);
	EXPECT_EQ(r.exitCode, 2);
	EXPECT_NE(r.out.find("no relation"), std::string::npos) << r.out;

	EXPECT_EQ(run(q(m_traj)).exitCode, 2);
	EXPECT_EQ(run("--bogus " + q(m_traj) + " " + q(m_rel)).exitCode, 2);
	EXPECT_EQ(run(q(m_traj) + " " + q(m_rel) + " --carmen-out").exitCode, 2);
}
