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
	rel.push_back({2.0000011, 3.0, 1, 0, 0});  // 1.1 µs away: beyond a 1e-6 s tolerance
	const auto e = evaluateRelativePoses(straightLine(), rel, 1e-6);
	EXPECT_EQ(e.matched, 4u);
	EXPECT_EQ(e.missing, 3u);
	EXPECT_EQ(e.transErrors.size(), 4u);

	const auto none = evaluateRelativePoses({}, rel, 1e-6);
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
	const auto e = evaluateRelativePoses(t, rel, 1e-6);
	EXPECT_EQ(e.matched, 1u);
	EXPECT_EQ(e.missing, 1u);
	EXPECT_NEAR(e.transMean, 0.0, 1e-12);
	EXPECT_EQ(evaluateRelativePoses(t, rel, 1e-5).matched, 2u);
}

TEST(RelativePoseEvaluation, StampsRoundedToFiveDecimalsMatchEveryRelationWithTheSameErrors)
{
	// Poses stamped to the microsecond, relations written with 5 decimals: each stamp is up to 5 µs off.
	const Trajectory t = {{1.000003, 0, 0, 0}, {2.000006, 1, 0.1, 10 * kDeg}, {3.000000, 2, 0, 0}, {4.000002, 3, 0, 0}};
	const double stamp[] = {0, 1.000003, 2.000006, 3.000000, 4.000002};	 // by the whole second they stand for
	const double fiveDecimals[] = {0, 1.00000, 2.00001, 3.00000, 4.00000};
	std::vector<Relation> exact = straightLineRelations(), rounded = straightLineRelations();
	for (std::size_t k = 0; k < exact.size(); ++k)
	{
		const int a = static_cast<int>(exact[k].t1), b = static_cast<int>(exact[k].t2);
		exact[k].t1 = stamp[a], exact[k].t2 = stamp[b];
		rounded[k].t1 = fiveDecimals[a], rounded[k].t2 = fiveDecimals[b];
	}
	const auto e = evaluateRelativePoses(t, exact);
	const auto r = evaluateRelativePoses(t, rounded);
	ASSERT_EQ(e.matched, 4u);
	EXPECT_EQ(r.matched, 4u);
	EXPECT_EQ(r.missing, 0u);
	EXPECT_EQ(r.transErrors, e.transErrors);
	EXPECT_EQ(r.rotErrorsDeg, e.rotErrorsDeg);
	EXPECT_EQ(r.transMean, e.transMean);
	EXPECT_EQ(r.rotMeanDeg, e.rotMeanDeg);
	EXPECT_NEAR(e.transErrors[0], 0.1, 1e-12);	// the pose at 2 s is off as in OffsetInOnePose
	// Matching to the microsecond, as before, found none of them.
	EXPECT_EQ(evaluateRelativePoses(t, rounded, 1e-6).matched, 0u);

	// Offsets (µs) of the 8 stamps of (1,2) (2,3) (1,3) (3,4): 3 4, 4 0, 3 0, 0 2 → max 4, mean 16/8 = 2,
	// 5 of them more than 1 µs.
	EXPECT_NEAR(r.timeOffsetMax, 4e-6, 1e-12);
	EXPECT_NEAR(r.timeOffsetMean, 2e-6, 1e-12);
	EXPECT_EQ(r.inexactStamps, 5u);
	EXPECT_EQ(e.timeOffsetMax, 0.0);
	EXPECT_EQ(e.timeOffsetMean, 0.0);
	EXPECT_EQ(e.inexactStamps, 0u);
}

TEST(RelativePoseEvaluation, AStampFartherThanTheToleranceFromEveryPoseIsMissing)
{
	std::vector<Relation> rel = straightLineRelations();
	rel.push_back({2.2, 3.0, 1, 0, 0});	  // 0.2 s after the pose at 2 s, 0.8 s before the one at 3 s
	rel.push_back({1.0, 4.15, 3, 0, 0});  // 0.15 s after the last pose
	rel.push_back({0.93, 2.0, 1, 0, 0});  // 0.07 s before the first pose: within 0.1 s
	const auto e = evaluateRelativePoses(straightLine(), rel);
	EXPECT_EQ(e.matched, 5u);
	EXPECT_EQ(e.missing, 2u);
	EXPECT_EQ(e.matchedRelations, (std::vector<std::size_t>{0, 1, 2, 3, 6}));
	ASSERT_EQ(e.transErrors.size(), 5u);
	EXPECT_NEAR(e.transErrors[4], 0.0, 1e-12);	// (0.93, 2) took the poses at 1 and 2 s
	// Offsets: 8 exact stamps, then 0.07 and 0.
	EXPECT_NEAR(e.timeOffsetMax, 0.07, 1e-12);
	EXPECT_NEAR(e.timeOffsetMean, 0.07 / 10, 1e-12);
	EXPECT_EQ(e.inexactStamps, 1u);
	// A wider tolerance takes them in, none leaves only the exact ones.
	EXPECT_EQ(evaluateRelativePoses(straightLine(), rel, 0.25).matched, 7u);
	EXPECT_EQ(evaluateRelativePoses(straightLine(), rel, 0.0).matched, 4u);
}

TEST(RelativePoseEvaluation, TheNearestOfTwoCandidatePosesIsTaken)
{
	// Two poses within 0.1 s of the stamps 1.01 and 1.03, out of time order in the file: 1.04 s at x = 0.5,
	// 1.00 s at x = 0. The pose at 2 s (x = 1) is 0.5 m ahead of the first, 1 m ahead of the second.
	const Trajectory t = {{1.04, 0.5, 0, 0}, {2.0, 1, 0, 0}, {1.00, 0, 0, 0}};
	const auto e = evaluateRelativePoses(t, {{1.03, 2.0, 0.5, 0, 0}, {1.01, 2.0, 1.0, 0, 0}});
	ASSERT_EQ(e.matched, 2u);
	EXPECT_NEAR(e.transErrors[0], 0.0, 1e-12);	// 1.03 → the pose at 1.04 (0.01 s), not 1.00 (0.03 s)
	EXPECT_NEAR(e.transErrors[1], 0.0, 1e-12);	// 1.01 → the pose at 1.00 (0.01 s), not 1.04 (0.03 s)
	// Relations saying the opposite are 0.5 m off: the errors pin down the choice.
	const auto wrong = evaluateRelativePoses(t, {{1.03, 2.0, 1.0, 0, 0}, {1.01, 2.0, 0.5, 0, 0}});
	EXPECT_NEAR(wrong.transErrors[0], 0.5, 1e-12);
	EXPECT_NEAR(wrong.transErrors[1], 0.5, 1e-12);
	// Offsets: 0.01, 0 (t2 exact), 0.01, 0 → max 0.01, mean 0.005, 2 not exact.
	EXPECT_NEAR(e.timeOffsetMax, 0.01, 1e-12);
	EXPECT_NEAR(e.timeOffsetMean, 0.005, 1e-12);
	EXPECT_EQ(e.inexactStamps, 2u);
}

TEST(RelativePoseEvaluation, ExactStampsGiveTheSameNumbersWhateverTheTolerance)
{
	Trajectory t = straightLine();
	t[1] = {2.0, 1.0, 0.1, 10 * kDeg};
	const auto narrow = evaluateRelativePoses(t, straightLineRelations(), 1e-6);
	const auto wide = evaluateRelativePoses(t, straightLineRelations());
	EXPECT_EQ(wide.matched, narrow.matched);
	EXPECT_EQ(wide.transErrors, narrow.transErrors);
	EXPECT_EQ(wide.rotErrorsDeg, narrow.rotErrorsDeg);
	EXPECT_EQ(wide.transMean, narrow.transMean);
	EXPECT_EQ(wide.transStd, narrow.transStd);
	EXPECT_EQ(wide.transMeanSq, narrow.transMeanSq);
	EXPECT_EQ(wide.rotMeanDeg, narrow.rotMeanDeg);
	EXPECT_EQ(wide.rotStdDeg, narrow.rotStdDeg);
	EXPECT_EQ(wide.timeOffsetMax, 0.0);
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

TEST_F(PmSlamEval, PrintsHowFarTheMatchedStampsWere)
{
	RunResult r = run(q(m_traj) + " " + q(m_rel));
	EXPECT_EQ(r.exitCode, 0) << r.out;
	EXPECT_NE(r.out.find("time offset of the matched stamps [s]: max 0.000000, mean 0.000000; 0 of 8 not exact "
						 "(> 1e-6 s), 0.1 allowed\n"),
			  std::string::npos)
		<< r.out;

	// The relations written with 1 decimal and 40 ms off: 2.04 and 3.04 still take the poses at 2 and 3 s.
	const std::string off = (m_dir / "off.relations").string();
	std::ofstream(off) << "1.0 2.04 1 0 0 0 0 0\n2.04 3.04 1 0 0 0 0 0\n";
	r = run(q(m_traj) + " " + q(off));
	EXPECT_EQ(r.exitCode, 0) << r.out;
	EXPECT_NE(r.out.find("relations matched: 2, missing: 0\n"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("translational error [m]: 0.1870 +/- "), std::string::npos) << r.out;	 // (0.1 + 0.274069)/2
	EXPECT_NE(r.out.find("[s]: max 0.040000, mean 0.030000; 3 of 4 not exact"), std::string::npos) << r.out;
	r = run("--json " + q(m_traj) + " " + q(off));
	EXPECT_NE(r.out.find("\"max_time_offset_s\": 0.1, \"time_offset_max_s\": 0.04"), std::string::npos) << r.out;
	EXPECT_NE(r.out.find("\"inexact_stamps\": 3}"), std::string::npos) << r.out;

	// Narrower than 40 ms: nothing matches, and the message names the option.
	r = run("--max-time-offset 0.03 " + q(m_traj) + " " + q(off), true);
	EXPECT_EQ(r.exitCode, 2) << r.out;
	EXPECT_NE(r.out.find("within 0.03 s of the relations' t1/t2 (--max-time-offset)"), std::string::npos) << r.out;
	r = run("--max-time-offset=0.05 " + q(m_traj) + " " + q(off));
	EXPECT_NE(r.out.find("relations matched: 2, missing: 0\n"), std::string::npos) << r.out;
	for (const char* bad : {"-1", "x", "nan", ""})
	{
		r = run("--max-time-offset '" + std::string(bad) + "' " + q(m_traj) + " " + q(off), true);
		EXPECT_EQ(r.exitCode, 2) << bad;
		EXPECT_NE(r.out.find("--max-time-offset '" + std::string(bad) + "': expected seconds"), std::string::npos)
			<< r.out;
	}
}

TEST_F(PmSlamEval, RelationErrorsListsTheMatchedRelationsInOrderWithTheOffsets)
{
	const std::string off = (m_dir / "off.relations").string();
	std::ofstream(off) << "1.0 2.04 1 0 0 0 0 0\n5.0 6.0 1 0 0 0 0 0\n2.04 3.04 1 0 0 0 0 0\n";
	const std::string cmd = std::string("'") + PMSLAM_BINARY_DIR "/bin/pm-relation-errors' ";
	RunResult r;
	const auto runErrors = [&](const std::string& args) {
		FILE* p = ::popen((cmd + args + " 2>&1").c_str(), "r");
		std::array<char, 4096> buf;
		size_t n;
		r.out.clear();
		while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
		const int status = ::pclose(p);
		r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
	};
	runErrors(q(m_traj) + " " + q(off));
	EXPECT_EQ(r.exitCode, 0) << r.out;
	EXPECT_EQ(r.out, "# " + m_traj + " vs " + off +
						 ": 2 of 3 relations matched\n"
						 "# time offset of the matched stamps [s]: max 0.040000, mean 0.030000; 3 of 4 not exact "
						 "(> 1e-6 s), 0.1 allowed\n"
						 "# t1 t2 trans_err_m rot_err_deg\n"
						 "1.000000 2.040000 0.100000 10.000000\n"
						 "2.040000 3.040000 0.274070 10.000000\n");	// e23 = 0.2740696 (OffsetInOnePose)
	runErrors("--max-time-offset 0.01 " + q(m_traj) + " " + q(off));
	EXPECT_EQ(r.exitCode, 0) << r.out;
	EXPECT_NE(r.out.find(": 0 of 3 relations matched\n"), std::string::npos) << r.out;
	runErrors("--max-time-offset -2 " + q(m_traj) + " " + q(off));
	EXPECT_EQ(r.exitCode, 2) << r.out;
}
