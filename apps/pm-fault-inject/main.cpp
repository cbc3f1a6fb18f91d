/* pm-fault-inject — injects the faults a real robot log has into a Carmen log, with known truth.
 *
 *   pm-fault-inject --fault KIND [options] IN.clf OUT.clf
 *
 * The faults (each at --count places drawn with --seed from the middle 90 % of the scans, at
 * least 1/(2·count) of the log apart):
 *   slip      the odometry turns by a heading drawn from --heading-deg LO:HI (random sign) and
 *             moves --lateral M sideways between two consecutive scans, kept from then on (a wheel slip)
 *   dropout   --scans N consecutive laser scans are missing (odometry goes on)
 *   gap       nothing is logged for --seconds S (the robot moves on meanwhile)
 *   spurious  in --fraction F of the scans, a person-sized blob: --beams N neighbouring beams
 *             return 0.5–3 m
 *   kidnap    the robot is carried --metres M: its odometry stands still while the scans move
 *   stall     during a turn of at least --turn-deg D (40) over --scans N scans (8), the odometry reading
 *             stands still for those N scans, then catches up with the whole turn in one step
 * FLASER/RLASER (laser and odometry poses) and ODOM lines are rewritten; other lines pass unchanged.
 * IN may be gz- or bzip2-compressed (.clf.gz, .clf.bz2), as pm-slam-app reads it; OUT is plain text. A
 * compressed IN damaged part way is used up to the damage, with a warning.
 * The places chosen are written to stderr, one line each ("fault KIND at t=… (scan #…)").
 * Exit status: 0 done, 2 bad arguments or unreadable input.
 */
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/TextLineReader.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../common/CommandLine.h"

namespace
{
[[noreturn]] void fail(const std::string& m)
{
	std::cerr << "pm-fault-inject: " << m << "\n";
	std::exit(2);
}

double number(const std::string& opt, const std::string& v)
{
	char* end = nullptr;
	const double x = std::strtod(v.c_str(), &end);
	if (end == v.c_str() || *end || !std::isfinite(x)) fail(opt + " '" + v + "': expected a number");
	return x;
}

struct Line
{
	std::string text;
	std::vector<std::string> tok;
	bool scan = false, odom = false;
	std::size_t n = 0;	// beams of a scan
	double t = 0;
	bool keep = true;
};

std::string fmt(double v)
{
	char b[64];
	std::snprintf(b, sizeof b, "%.6f", v);
	return b;
}

mrpt::poses::CPose2D poseAt(const Line& l, std::size_t i)
{
	return {std::stod(l.tok[i]), std::stod(l.tok[i + 1]), std::stod(l.tok[i + 2])};
}
void setPose(Line& l, std::size_t i, const mrpt::poses::CPose2D& p)
{
	l.tok[i] = fmt(p.x());
	l.tok[i + 1] = fmt(p.y());
	l.tok[i + 2] = fmt(p.phi());
}
mrpt::poses::CPose2D inverse(const mrpt::poses::CPose2D& p) { return mrpt::poses::CPose2D() - p; }
// Index of the odometry pose in a line (the raw odometry of a scan line).
std::size_t odomIndex(const Line& l) { return l.scan ? 5 + l.n : 1; }

/** What to inject where (the command line). */
struct Fault
{
	std::string kind, in, out;
	int count = 1;
	unsigned seed = 1;
	double headLo = 18, headHi = 30, lateral = 0.3, seconds = 20, fraction = 0.3, metres = 3, turnDeg = 40;
	int scansOut = -1, beams = 8;  // scansOut: 50 for a dropout, 8 for a stall
};

Fault parseArgs(int argc, char** argv)
{
	Fault f;
	std::vector<std::string> pos;
	const auto words = pmslam_app::splitOptionValues(
		argc, argv, {"--fault", "--count", "--seed", "--heading-deg", "--lateral", "--scans", "--seconds", "--fraction", "--beams", "--metres", "--turn-deg"});
	for (std::size_t i = 0; i < words.size(); ++i)
	{
		const std::string& a = words[i];
		auto val = [&]() -> std::string {
			if (i + 1 >= words.size()) fail(a + " needs a value");
			return words[++i];
		};
		if (a == "--fault") f.kind = val();
		else if (a == "--count") f.count = int(number(a, val()));
		else if (a == "--seed") f.seed = unsigned(number(a, val()));
		else if (a == "--heading-deg")
		{
			const std::string v = val();
			const auto c = v.find(':');
			f.headLo = number(a, v.substr(0, c));
			f.headHi = c == std::string::npos ? f.headLo : number(a, v.substr(c + 1));
		}
		else if (a == "--lateral") f.lateral = number(a, val());
		else if (a == "--scans") f.scansOut = int(number(a, val()));
		else if (a == "--seconds") f.seconds = number(a, val());
		else if (a == "--fraction") f.fraction = number(a, val());
		else if (a == "--beams") f.beams = int(number(a, val()));
		else if (a == "--metres") f.metres = number(a, val());
		else if (a == "--turn-deg") f.turnDeg = number(a, val());
		else if (a == "-h" || a == "--help")
		{
			std::cout << "usage: pm-fault-inject --fault slip|dropout|gap|spurious|kidnap|stall [--count N] [--seed S]\n"
						 "  [--heading-deg LO:HI] [--lateral M] [--scans N] [--seconds S] [--fraction F] [--beams N]\n"
						 "  [--metres M] [--turn-deg D] IN.clf OUT.clf   (see the comment at the top of apps/pm-fault-inject/main.cpp;\n"
						 "  a value may also follow its option after '=': --count=3)\n";
			std::exit(0);
		}
		else if (!a.empty() && a[0] == '-') fail("unknown option '" + a + "'");
		else pos.push_back(a);
	}
	if (pos.size() != 2) fail("expected IN.clf OUT.clf (see --help)");
	f.in = pos[0];
	f.out = pos[1];
	const std::set<std::string> kinds{"slip", "dropout", "gap", "spurious", "kidnap", "stall"};
	if (!kinds.count(f.kind)) fail("--fault '" + f.kind + "': expected slip, dropout, gap, spurious, kidnap or stall");
	if (f.count < 1) fail("--count: expected >= 1");
	if (f.scansOut < 0) f.scansOut = f.kind == "stall" ? 8 : 50;
	if (f.scansOut < 1) fail("--scans: expected >= 1");
	return f;
}

/** The next line of `f` into `s`; false at its end. Damage after `linesRead` lines: a warning and false (none
 * read: an error). */
bool nextLine(pmslam::TextLineReader& f, const std::string& in, std::size_t linesRead, std::string& s)
{
	try
	{
		return f.getline(s);
	}
	catch (const std::exception& e)
	{
		const std::string where = in + ":" + std::to_string(linesRead + 1) + ": read error (" + e.what() + ")";
		if (linesRead == 0) fail("cannot read " + where);
		std::cerr << "pm-fault-inject: warning: " << where << ", the " << linesRead << " lines before it are used\n";
		return false;
	}
}

/** The log's lines, each scan and odometry line parsed; `scans` gets the indices of the scan lines. */
std::vector<Line> readLines(const std::string& in, std::vector<std::size_t>& scans)
{
	pmslam::TextLineReader f;
	if (!f.open(in)) fail("cannot read '" + in + "'");
	std::vector<Line> lines;
	for (std::string s; nextLine(f, in, lines.size(), s);)
	{
		Line l;
		l.text = s;
		std::istringstream ss(s);
		for (std::string w; ss >> w;) l.tok.push_back(w);
		try
		{
			if (!l.tok.empty() && (l.tok[0] == "FLASER" || l.tok[0] == "RLASER") && l.tok.size() > 2)
			{
				l.n = std::stoul(l.tok[1]);
				if (l.tok.size() >= 11 + l.n)
				{
					l.scan = true;
					l.t = std::stod(l.tok[8 + l.n]);
					scans.push_back(lines.size());
				}
			}
			else if (!l.tok.empty() && l.tok[0] == "ODOM" && l.tok.size() >= 10)
			{
				l.odom = true;
				l.t = std::stod(l.tok[7]);
			}
		}
		catch (const std::exception&)
		{
			l.scan = l.odom = false;
		}
		lines.push_back(std::move(l));
	}
	if (scans.size() < 100) fail("'" + in + "' has " + std::to_string(scans.size()) + " laser scans: expected at least 100");
	return lines;
}

/** A stall's places: from each drawn scan on, the first (within its slice, wrapping round) from which the
 * odometry turns at least --turn-deg over the next --scans scans. A slice without such a turn has none. */
std::vector<std::size_t> duringTurns(const std::vector<std::size_t>& drawn, const std::vector<Line>& lines,
									 const Fault& f, double lo, double width)
{
	std::vector<double> heading;  // raw odometry heading of each scan
	for (const auto& l : lines)
		if (l.scan) heading.push_back(poseAt(l, odomIndex(l)).phi());
	const auto turns = [&](std::size_t s) {
		return s + f.scansOut < heading.size() &&
			   std::abs(mrpt::math::wrapToPi(heading[s + f.scansOut] - heading[s])) >= f.turnDeg * M_PI / 180;
	};
	std::vector<std::size_t> at;
	for (std::size_t k = 0; k < drawn.size(); ++k)
	{
		const std::size_t b = std::size_t(lo + width * k), e = std::size_t(lo + width * (k + 1));
		for (std::size_t i = 0; i < e - b; ++i)
		{
			const std::size_t s = b + (drawn[k] - b + i) % (e - b);
			if (turns(s))
			{
				at.push_back(s);
				break;
			}
		}
	}
	std::sort(at.begin(), at.end());
	return at;
}

/** Rewrites the lines with the faults: one place per equal slice of the middle 90 % of the scans,
 * drawn inside its slice (spurious: every scan, with probability --fraction). */
void inject(const Fault& f, std::vector<Line>& lines, std::size_t scanCount)
{
	std::mt19937 rng(f.seed);
	auto uniform = [&]() { return (rng() >> 8) * (1.0 / 16777216.0); };	// same on every platform
	std::vector<std::size_t> at;  // scan numbers
	const double lo = 0.05 * scanCount, width = 0.9 * scanCount / f.count;
	if (f.kind != "spurious")
		for (int k = 0; k < f.count; ++k) at.push_back(std::size_t(lo + width * (k + 0.25 + 0.5 * uniform())));
	if (f.kind == "stall") at = duringTurns(at, lines, f, lo, width);

	mrpt::poses::CPose2D C;	 // correction applied to every odometry pose from here on
	std::size_t next = 0;
	std::size_t scanNo = 0;
	bool frozen = false;
	mrpt::poses::CPose2D frozenAt;	// raw odometry where the kidnap began
	double carried = 0;
	mrpt::poses::CPose2D lastRaw;
	bool haveLast = false;
	double gapUntil = -1;
	int dropLeft = 0, stallLeft = 0;
	for (auto& l : lines)
	{
		if (!(l.scan || l.odom)) continue;
		if (l.t < gapUntil)
		{
			l.keep = false;
			if (l.scan) ++scanNo;  // scan numbers are the input's, as for the other faults
			continue;
		}
		const mrpt::poses::CPose2D raw = poseAt(l, odomIndex(l));
		if (l.scan)
		{
			if (next < at.size() && scanNo == at[next])
			{
				++next;
				std::cerr << "fault " << f.kind << " at t=" << fmt(l.t) << " (scan #" << scanNo << ")\n";
				if (f.kind == "slip")
				{
					const double h = (f.headLo + (f.headHi - f.headLo) * uniform()) * (uniform() < 0.5 ? -1 : 1);
					const double side = f.lateral * (uniform() < 0.5 ? -1 : 1);
					C = C + raw + mrpt::poses::CPose2D(0, side, h * M_PI / 180) + inverse(raw);
				}
				else if (f.kind == "dropout") dropLeft = f.scansOut;
				else if (f.kind == "gap")
				{
					gapUntil = l.t + f.seconds;
					l.keep = false;
					++scanNo;
					continue;
				}
				else if (f.kind == "kidnap")
				{
					frozen = true;
					frozenAt = raw;
					carried = 0;
				}
				else if (f.kind == "stall")
				{
					stallLeft = f.scansOut + 2;	 // this scan's reading stands still for the next --scans
					frozenAt = raw;
				}
			}
			if (stallLeft > 0) --stallLeft;
			if (dropLeft > 0)
			{
				--dropLeft;
				l.keep = false;
			}
			if (f.kind == "spurious" && uniform() < f.fraction && int(l.n) > f.beams)
			{
				const std::size_t b0 = std::size_t(uniform() * (l.n - f.beams));
				const double r0 = 0.5 + 2.5 * uniform();
				for (int b = 0; b < f.beams; ++b) l.tok[2 + b0 + b] = fmt(r0 + 0.05 * (uniform() - 0.5));
			}
			++scanNo;
		}
		if (frozen && haveLast) carried += (raw - lastRaw).norm();
		lastRaw = raw;
		haveLast = true;
		if (frozen && carried >= f.metres)
		{
			frozen = false;
			C = C + frozenAt + inverse(raw);	// odometry resumes from where it stood
		}
		// A stall's reading catches up (no correction) at the first scan after it.
		const mrpt::poses::CPose2D odo = frozen || stallLeft > 0 ? frozenAt : raw;
		if (l.scan)
		{
			const mrpt::poses::CPose2D laser = poseAt(l, 2 + l.n);
			setPose(l, 2 + l.n, C + odo + (laser - raw));
		}
		setPose(l, odomIndex(l), C + odo);
		std::string s;
		for (const auto& w : l.tok) s += (s.empty() ? "" : " ") + w;
		l.text = s;
	}
}
}  // namespace

int main(int argc, char** argv)
{
	const Fault f = parseArgs(argc, argv);
	std::vector<std::size_t> scans;	 // indices of scan lines
	std::vector<Line> lines = readLines(f.in, scans);
	inject(f, lines, scans.size());
	try
	{
		pmslam::writeFileAtomically(f.out, [&](std::ostream& o) {
			for (const auto& l : lines)
				if (l.keep) o << l.text << "\n";
		});
	}
	catch (const std::exception& e)
	{
		fail(e.what());
	}
	return 0;
}
