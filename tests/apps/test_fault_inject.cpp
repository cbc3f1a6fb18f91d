// pm-fault-inject on a synthetic Carmen log: each fault is checked by brute force against the
// input (every scan pair, every line), and the places it reports on stderr must be the places
// where the output changed.
#include <gtest/gtest.h>

#include <regex>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace fs = std::filesystem;
using namespace pmslam::testing;
using mrpt::poses::CPose2D;

namespace
{
const std::string kInject = PMSLAM_BINARY_DIR "/bin/pm-fault-inject";

struct ClfLine
{
	std::string text, kind;	 // kind: FLASER, ODOM or "" (anything else)
	double t = 0;
	CPose2D odo, laser;
	std::vector<std::string> ranges;
};

std::vector<ClfLine> readClf(const std::string& path)
{
	std::vector<ClfLine> out;
	std::ifstream in(path);
	for (std::string s; std::getline(in, s);)
	{
		ClfLine l;
		l.text = s;
		std::istringstream ss(s);
		std::vector<std::string> tok;
		for (std::string w; ss >> w;) tok.push_back(w);
		if (!tok.empty() && tok[0] == "FLASER")
		{
			const std::size_t n = std::stoul(tok[1]);
			l.kind = "FLASER";
			l.ranges.assign(tok.begin() + 2, tok.begin() + 2 + n);
			l.laser = CPose2D(std::stod(tok[2 + n]), std::stod(tok[3 + n]), std::stod(tok[4 + n]));
			l.odo = CPose2D(std::stod(tok[5 + n]), std::stod(tok[6 + n]), std::stod(tok[7 + n]));
			l.t = std::stod(tok[8 + n]);
		}
		else if (!tok.empty() && tok[0] == "ODOM")
		{
			l.kind = "ODOM";
			l.odo = CPose2D(std::stod(tok[1]), std::stod(tok[2]), std::stod(tok[3]));
			l.t = std::stod(tok[7]);
		}
		out.push_back(std::move(l));
	}
	return out;
}

std::vector<ClfLine> only(const std::vector<ClfLine>& lines, const std::string& kind)
{
	std::vector<ClfLine> o;
	for (const auto& l : lines)
		if (l.kind == kind) o.push_back(l);
	return o;
}

struct Fault
{
	std::string kind;
	double t;
	std::size_t scan;
};

/** The "fault KIND at t=… (scan #N)" lines of the output; fails on any other line. */
std::vector<Fault> reportedFaults(const std::string& output)
{
	std::vector<Fault> f;
	std::istringstream ss(output);
	const std::regex re(R"(fault (\w+) at t=([0-9.]+) \(scan #([0-9]+)\))");
	for (std::string line; std::getline(ss, line);)
	{
		std::smatch m;
		if (std::regex_match(line, m, re))
			f.push_back({m[1], std::stod(m[2]), std::stoul(m[3])});
		else
			ADD_FAILURE() << "unexpected output line: " << line;
	}
	return f;
}

bool samePose(const CPose2D& a, const CPose2D& b, double tol = 1e-4)
{
	return std::abs(a.x() - b.x()) < tol && std::abs(a.y() - b.y()) < tol &&
		   std::abs(angleDiff(a.phi(), b.phi())) < tol;
}
CPose2D increment(const CPose2D& from, const CPose2D& to) { return to - from; }	 // in `from`'s frame

/** A few hundred scans through the furnished room, ODOM lines before each, odometry far from the
 * origin (so that a wrong composition order shows), laser mounted off the robot's centre. */
struct Fixture : public ::testing::Test
{
	ScratchDir d{"fault-inject"};
	std::string in;
	std::vector<ClfLine> input, inScans, inOdom;
	void SetUp() override
	{
		const auto truth = roomPath(300);
		const auto odo = driftingOdometry(truth, 1.0, 0.0, CPose2D(12.0, -7.0, 2.0));
		CarmenLogSpec spec;
		spec.odomLines = true;
		spec.laserOnRobot = CPose2D(0.2, 0.05, 0.0);
		in = d.write("in.clf", carmenLog(furnishedRoom(), truth, odo, spec));
		input = readClf(in);
		inScans = only(input, "FLASER");
		inOdom = only(input, "ODOM");
		ASSERT_EQ(inScans.size(), 300u);
		ASSERT_EQ(inOdom.size(), 300u);
	}
	RunResult inject(const std::string& args, const std::string& out)
	{
		return run(quote(kInject) + " " + args + " " + quote(in) + " " + quote(d.path(out)));
	}
};
using FaultInject = Fixture;
}  // namespace

TEST_F(FaultInject, SlipChangesTheOdometryIncrementAtExactlyCountPlaces)
{
	const auto r = inject("--fault slip --count 3 --seed 7 --lateral 0.2", "slip.clf");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto faults = reportedFaults(r.output);
	ASSERT_EQ(faults.size(), 3u) << r.output;
	const auto out = readClf(d.path("slip.clf"));
	ASSERT_EQ(out.size(), input.size());
	const auto scans = only(out, "FLASER"), odom = only(out, "ODOM");
	ASSERT_EQ(scans.size(), inScans.size());
	ASSERT_EQ(odom.size(), inOdom.size());

	std::vector<std::size_t> changed;  // scan k: the increment from scan k-1 to k changed
	for (std::size_t k = 0; k < scans.size(); ++k)
	{
		EXPECT_EQ(scans[k].ranges, inScans[k].ranges) << "scan " << k;
		EXPECT_EQ(scans[k].t, inScans[k].t);
		// The laser stays where it is mounted on the robot.
		EXPECT_TRUE(samePose(scans[k].laser - scans[k].odo, inScans[k].laser - inScans[k].odo)) << "scan " << k;
		if (k == 0)
		{
			EXPECT_TRUE(samePose(scans[0].odo, inScans[0].odo));  // nothing before the first slip
			continue;
		}
		const CPose2D dIn = increment(inScans[k - 1].odo, inScans[k].odo);
		const CPose2D dOut = increment(scans[k - 1].odo, scans[k].odo);
		if (samePose(dIn, dOut)) continue;
		changed.push_back(k);
		// The slip, in the robot frame after the true increment: a turn and a sideways step.
		const CPose2D slip = dOut - dIn;
		const double deg = std::abs(slip.phi()) * 180.0 / M_PI;
		EXPECT_GE(deg, 18.0 - 1e-3) << "scan " << k;
		EXPECT_LE(deg, 30.0 + 1e-3) << "scan " << k;
		EXPECT_NEAR(slip.x(), 0.0, 1e-4) << "scan " << k;
		EXPECT_NEAR(std::abs(slip.y()), 0.2, 1e-4) << "scan " << k;
	}
	ASSERT_EQ(changed.size(), 3u);
	for (std::size_t i = 0; i < 3; ++i)
	{
		EXPECT_EQ(faults[i].kind, "slip");
		EXPECT_EQ(faults[i].scan, changed[i]);
		EXPECT_NEAR(faults[i].t, inScans[changed[i]].t, 1e-6);
	}
	// The ODOM lines slip as well, once each (the ODOM line before a slipping scan still has the old
	// odometry, so its increment to the next ODOM line is the changed one).
	std::size_t odomChanged = 0;
	for (std::size_t k = 1; k < odom.size(); ++k)
		odomChanged += !samePose(increment(inOdom[k - 1].odo, inOdom[k].odo), increment(odom[k - 1].odo, odom[k].odo));
	EXPECT_EQ(odomChanged, 3u);
	// Other lines pass unchanged.
	for (std::size_t i = 0; i < out.size(); ++i)
	{
		if (input[i].kind.empty()) { EXPECT_EQ(out[i].text, input[i].text); }
	}
}

TEST_F(FaultInject, DropoutRemovesCountTimesScansLaserLinesAndKeepsTheOdometry)
{
	const auto r = inject("--fault dropout --count 2 --scans 20 --seed 3", "dropout.clf");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto faults = reportedFaults(r.output);
	ASSERT_EQ(faults.size(), 2u) << r.output;
	const auto out = readClf(d.path("dropout.clf"));
	const auto scans = only(out, "FLASER"), odom = only(out, "ODOM");
	EXPECT_EQ(scans.size(), inScans.size() - 2 * 20);
	ASSERT_EQ(odom.size(), inOdom.size());
	for (std::size_t k = 0; k < odom.size(); ++k) EXPECT_EQ(odom[k].text, inOdom[k].text) << k;
	// The missing scans are exactly the 20 from each reported place on; the others are unchanged.
	std::set<std::size_t> dropped;
	for (const auto& f : faults)
	{
		EXPECT_EQ(f.kind, "dropout");
		EXPECT_NEAR(f.t, inScans[f.scan].t, 1e-6);
		for (std::size_t k = f.scan; k < f.scan + 20; ++k) dropped.insert(k);
	}
	ASSERT_EQ(dropped.size(), 40u);
	std::vector<std::string> expected;
	for (const auto& l : input)
		if (!(l.kind == "FLASER" && dropped.count(std::size_t(std::lround((l.t - inScans[0].t) / 0.1)))))
			expected.push_back(l.text);
	ASSERT_EQ(out.size(), expected.size());
	for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].text, expected[i]) << "line " << i;
}

TEST_F(FaultInject, GapRemovesEveryLineInsideTheWindowsAndNothingElse)
{
	const double seconds = 3.0;
	const auto r = inject("--fault gap --count 2 --seconds 3 --seed 5", "gap.clf");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto faults = reportedFaults(r.output);
	ASSERT_EQ(faults.size(), 2u) << r.output;
	for (const auto& f : faults)
	{
		EXPECT_EQ(f.kind, "gap");
		EXPECT_NEAR(f.t, inScans[f.scan].t, 1e-6);
	}
	const auto out = readClf(d.path("gap.clf"));
	// A window starts with its scan (the ODOM line just before it, at the same time, is still logged)
	// and lasts `seconds`.
	auto inWindow = [&](const ClfLine& l) {
		for (const auto& f : faults)
			if (l.t >= f.t - 1e-9 && l.t < f.t + seconds - 1e-9 && !(l.kind == "ODOM" && l.t < f.t + 1e-9)) return true;
		return false;
	};
	std::size_t removed = 0;
	std::vector<std::string> expected;
	for (const auto& l : input)
	{
		if (!l.kind.empty() && inWindow(l))
			++removed;
		else
			expected.push_back(l.text);
	}
	EXPECT_EQ(removed, 2u * (30 + 29));	 // 30 scans and 29 ODOM lines per 3 s window at 10 Hz
	for (const auto& l : out)
	{
		if (!l.kind.empty()) { EXPECT_FALSE(inWindow(l)) << l.text.substr(0, 40); }
	}
	ASSERT_EQ(out.size(), expected.size());
	for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i].text, expected[i]) << "line " << i;
	// The robot moved on meanwhile: the odometry after a gap is the input's, not continued from before it.
}

TEST_F(FaultInject, KidnapFreezesTheOdometryWhileTheScansMoveThenResumes)
{
	const double metres = 1.0;
	const auto r = inject("--fault kidnap --count 1 --metres 1 --seed 11", "kidnap.clf");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto faults = reportedFaults(r.output);
	ASSERT_EQ(faults.size(), 1u) << r.output;
	const std::size_t s = faults[0].scan;
	EXPECT_EQ(faults[0].kind, "kidnap");
	EXPECT_NEAR(faults[0].t, inScans[s].t, 1e-6);
	const auto out = readClf(d.path("kidnap.clf"));
	const auto scans = only(out, "FLASER");
	ASSERT_EQ(scans.size(), inScans.size());
	// The end of the stretch: the first scan at least `metres` of (true) travel after the start.
	std::size_t e = s;
	for (double carried = 0; e + 1 < inScans.size() && carried < metres; ++e)
		carried += increment(inScans[e].odo, inScans[e + 1].odo).norm();
	ASSERT_GT(e, s + 5);
	ASSERT_LT(e + 10, inScans.size());
	for (std::size_t k = 0; k < scans.size(); ++k)
	{
		EXPECT_EQ(scans[k].ranges, inScans[k].ranges) << "scan " << k;	// the scans see the robot move
		EXPECT_TRUE(samePose(scans[k].laser - scans[k].odo, inScans[k].laser - inScans[k].odo)) << "scan " << k;
		if (k <= s)
			EXPECT_TRUE(samePose(scans[k].odo, inScans[k].odo)) << "scan " << k;  // unchanged before
		else if (k <= e)
			EXPECT_TRUE(samePose(scans[k].odo, scans[s].odo, 1e-6)) << "scan " << k << " of the stretch " << s << ".." << e;
		else
			EXPECT_TRUE(samePose(increment(scans[k - 1].odo, scans[k].odo), increment(inScans[k - 1].odo, inScans[k].odo)))
				<< "scan " << k;
	}
	// The stretch ends where it should: the odometry moves again right after it.
	EXPECT_FALSE(samePose(scans[e + 1].odo, scans[s].odo, 1e-6));
}

TEST_F(FaultInject, StallFreezesTheReadingDuringTurnsThenCatchesUpWithNoCorrection)
{
	// The room path turns at most about 3 degrees over 8 scans: a stall during a turn of 2 degrees or more.
	const auto r = inject("--fault stall --count 3 --scans 8 --turn-deg 2 --seed 5", "stall.clf");
	ASSERT_EQ(r.exitCode, 0) << r.output;
	const auto faults = reportedFaults(r.output);
	ASSERT_EQ(faults.size(), 3u) << r.output;
	const auto scans = only(readClf(d.path("stall.clf")), "FLASER");
	ASSERT_EQ(scans.size(), inScans.size());
	std::vector<bool> stale(scans.size(), false);
	for (const auto& f : faults)
	{
		EXPECT_EQ(f.kind, "stall");
		ASSERT_LT(f.scan + 9, inScans.size());
		// During a turn: the odometry turns at least 2 degrees over the stall.
		EXPECT_GE(std::abs(angleDiff(inScans[f.scan + 8].odo.phi(), inScans[f.scan].odo.phi())), 2 * M_PI / 180);
		for (std::size_t k = f.scan + 1; k <= f.scan + 8; ++k) stale[k] = true;
	}
	for (std::size_t k = 0; k < scans.size(); ++k)
	{
		EXPECT_EQ(scans[k].ranges, inScans[k].ranges) << "scan " << k;
		std::size_t s = k;	// the reading it shows: the last before the stall
		while (stale[s]) --s;
		EXPECT_TRUE(samePose(scans[k].odo, inScans[s].odo)) << "scan " << k;
		EXPECT_TRUE(samePose(scans[k].laser - scans[k].odo, inScans[k].laser - inScans[k].odo)) << "scan " << k;
	}
}

TEST_F(FaultInject, BadArgumentsExitWith2AndOneLine)
{
	const std::string out = d.path("never.clf");
	const std::string shortLog = d.write("short.clf", "FLASER 3 1 1 1 0 0 0 0 0 0 1000.0 nohost 1000.0\n");
	const std::vector<std::string> bad = {
		"--fault bogus " + quote(in) + " " + quote(out),
		"--fault slip --count 0 " + quote(in) + " " + quote(out),
		"--fault slip --count many " + quote(in) + " " + quote(out),
		"--fault slip --heading-deg 18:x " + quote(in) + " " + quote(out),
		"--fault slip --frobnicate " + quote(in) + " " + quote(out),
		"--fault slip " + quote(in),
		"--fault slip " + quote(in) + " " + quote(out) + " extra",
		"--fault slip --count",
		"--fault slip /nonexistent/in.clf " + quote(out),
		"--fault slip " + quote(shortLog) + " " + quote(out),
	};
	for (const auto& args : bad)
	{
		const auto r = run(quote(kInject) + " " + args);
		EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
		EXPECT_EQ(r.output.rfind("pm-fault-inject: ", 0), 0u) << args << "\n" << r.output;
		EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n" << r.output;
		EXPECT_EQ(r.output.find("fault slip at"), std::string::npos) << args;
		EXPECT_FALSE(fs::exists(out)) << args;
	}
	// An output that cannot be written: the places were already drawn (and said), then exit 2.
	const auto r = run(quote(kInject) + " --fault slip " + quote(in) + " /nonexistent/dir/out.clf");
	EXPECT_EQ(r.exitCode, 2) << r.output;
	EXPECT_NE(r.output.find("pm-fault-inject: cannot write '/nonexistent/dir/out.clf'"), std::string::npos) << r.output;
	const auto help = run(quote(kInject) + " --help");
	EXPECT_EQ(help.exitCode, 0);
	EXPECT_NE(help.output.find("usage: pm-fault-inject"), std::string::npos);
}
