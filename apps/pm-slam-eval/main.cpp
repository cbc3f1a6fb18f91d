/* pm-slam-eval — score a SLAM trajectory against Freiburg ground-truth relations
 * with the relative-displacement metric of Kümmerle et al. 2009
 * (see libpmslam/include/pmslam/eval/RelativePoseEvaluation.h). */
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace
{
const char* kUsage =
	"usage: pm-slam-eval [--carmen-out FILE] [--json] [--max-time-offset S] TRAJECTORY RELATIONS\n"
	"\n"
	"Scores TRAJECTORY (lines 'timestamp x y yaw', as written by pm-slam-app) against\n"
	"RELATIONS (Freiburg '.relations': 't1 t2 x y z roll pitch yaw') with the relative\n"
	"pose metric of Kuemmerle et al. 2009. Each relation timestamp takes the pose with the\n"
	"nearest timestamp within --max-time-offset (a relation with a stamp farther from every\n"
	"pose is missing); how far the matched stamps were is printed with the errors.\n"
	"\n"
	"options (anywhere on the command line):\n"
	"  --carmen-out FILE    also write the trajectory as a Carmen log (FLASER lines with\n"
	"                       zero readings) for the Freiburg metricEvaluator\n"
	"  --json               print one JSON object with all the numbers instead of text\n"
	"  --max-time-offset S  farthest a relation timestamp may be from its pose's, in seconds\n"
	"                       (default 0.1, as the metricEvaluator)\n"
	"  -h, --help           print this help and exit\n"
	"\n"
	"exit status: 0 success, 2 bad arguments, unreadable or malformed input, or no\n"
	"relation matched a pose.\n";

constexpr int kExitError = 2;

int fail(const std::string& message)
{
	std::cerr << "pm-slam-eval: " << message << "\n";
	return kExitError;
}

std::string jsonString(const std::string& s)
{
	std::string out = "\"";
	for (const char c : s)
	{
		switch (c)
		{
			case '"': out += "\\\""; break;
			case '\\': out += "\\\\"; break;
			case '\n': out += "\\n"; break;
			case '\t': out += "\\t"; break;
			case '\r': out += "\\r"; break;
			default:
				if (static_cast<unsigned char>(c) < 0x20)
				{
					char buf[8];
					std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
					out += buf;
				}
				else
					out += c;
		}
	}
	return out + "\"";
}

std::string num(double v)
{
	char buf[64];
	std::snprintf(buf, sizeof(buf), "%.9g", v);
	return buf;
}

struct Arguments
{
	std::string carmenOut;
	bool json = false;
	double maxTimeOffset = pmslam::kDefaultMaxTimeOffset;
	std::vector<std::string> positional;
	bool help = false;
};

/** A value of --carmen-out / --max-time-offset, given as the next argument or after '='; "" if none. */
std::string optionValue(const std::string& name, int argc, char** argv, int& i)
{
	const std::string a = argv[i];
	if (a.size() > name.size()) return a.substr(name.size() + 1);	// --name=value
	return i + 1 < argc ? argv[++i] : "";
}

/** Parses the command line into `args`; "" or the message of a bad argument. */
std::string parseArguments(int argc, char** argv, Arguments& args)
{
	bool endOfOptions = false;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		const auto is = [&](const std::string& name) { return a == name || a.rfind(name + "=", 0) == 0; };
		if (endOfOptions || a.empty() || a[0] != '-' || a == "-")
			args.positional.push_back(a);
		else if (a == "--")
			endOfOptions = true;
		else if (a == "-h" || a == "--help")
		{
			args.help = true;
			return "";
		}
		else if (a == "--json")
			args.json = true;
		else if (is("--carmen-out"))
		{
			args.carmenOut = optionValue("--carmen-out", argc, argv, i);
			if (args.carmenOut.empty()) return "--carmen-out expects a FILE (see --help)";
		}
		else if (is("--max-time-offset"))
		{
			const std::string v = optionValue("--max-time-offset", argc, argv, i);
			char* end = nullptr;
			args.maxTimeOffset = std::strtod(v.c_str(), &end);
			if (v.empty() || *end != '\0' || !std::isfinite(args.maxTimeOffset) || args.maxTimeOffset < 0)
				return "--max-time-offset '" + v + "': expected seconds, a number >= 0 (see --help)";
		}
		else
			return "unknown option '" + a + "' (see --help)";
	}
	if (args.positional.size() != 2)
		return "expected 2 arguments TRAJECTORY RELATIONS, got " + std::to_string(args.positional.size()) +
			   " (see --help)";
	return "";
}

void printJson(const Arguments& args, std::size_t poses, std::size_t relations, const pmslam::RelativePoseErrors& e)
{
	std::cout << "{\"trajectory\": " << jsonString(args.positional[0])
			  << ", \"relations_file\": " << jsonString(args.positional[1]) << ", \"poses\": " << poses
			  << ", \"relations\": " << relations << ", \"matched\": " << e.matched << ", \"missing\": " << e.missing
			  << ", \"trans_mean_m\": " << num(e.transMean) << ", \"trans_std_m\": " << num(e.transStd)
			  << ", \"trans_mean_sq_m2\": " << num(e.transMeanSq) << ", \"trans_max_m\": " << num(e.transMax)
			  << ", \"rot_mean_deg\": " << num(e.rotMeanDeg) << ", \"rot_std_deg\": " << num(e.rotStdDeg)
			  << ", \"rot_mean_sq_deg2\": " << num(e.rotMeanSqDeg2) << ", \"rot_max_deg\": " << num(e.rotMaxDeg)
			  << ", \"max_time_offset_s\": " << num(args.maxTimeOffset)
			  << ", \"time_offset_max_s\": " << num(e.timeOffsetMax)
			  << ", \"time_offset_mean_s\": " << num(e.timeOffsetMean) << ", \"inexact_stamps\": " << e.inexactStamps
			  << "}" << std::endl;
}

void printText(const Arguments& args, std::size_t poses, std::size_t relations, const pmslam::RelativePoseErrors& e)
{
	char buf[256];
	std::cout << "trajectory: " << args.positional[0] << " (" << poses << " poses)\n"
			  << "relations:  " << args.positional[1] << " (" << relations << " relations)\n"
			  << "relations matched: " << e.matched << ", missing: " << e.missing << "\n";
	std::snprintf(buf, sizeof(buf), "translational error [m]: %.4f +/- %.4f, mean of squares %.6f m^2, max %.4f\n",
				  e.transMean, e.transStd, e.transMeanSq, e.transMax);
	std::cout << buf;
	std::snprintf(buf, sizeof(buf), "rotational error [deg]:  %.3f +/- %.3f, mean of squares %.4f deg^2, max %.3f\n",
				  e.rotMeanDeg, e.rotStdDeg, e.rotMeanSqDeg2, e.rotMaxDeg);
	std::cout << buf;
	std::snprintf(buf, sizeof(buf),
				  "time offset of the matched stamps [s]: max %.6f, mean %.6f; %zu of %zu not exact (> 1e-6 s), "
				  "%g allowed\n",
				  e.timeOffsetMax, e.timeOffsetMean, e.inexactStamps, 2 * e.matched, args.maxTimeOffset);
	std::cout << buf << std::flush;
}
}  // namespace

int main(int argc, char** argv)
{
	Arguments args;
	const std::string bad = parseArguments(argc, argv, args);
	if (args.help)
	{
		std::cout << kUsage;
		return 0;
	}
	if (!bad.empty()) return fail(bad);
	const std::string& trajPath = args.positional[0];
	const std::string& relPath = args.positional[1];
	try
	{
		const pmslam::Trajectory traj = pmslam::loadTrajectory(trajPath);
		const std::vector<pmslam::Relation> relations = pmslam::loadRelations(relPath);
		if (!args.carmenOut.empty()) pmslam::writeCarmenLog(args.carmenOut, traj);

		const pmslam::RelativePoseErrors e = pmslam::evaluateRelativePoses(traj, relations, args.maxTimeOffset);
		if (e.matched == 0)
			return fail("no relation of " + relPath + " (" + std::to_string(relations.size()) +
						" relations) matched two poses of " + trajPath + " (" + std::to_string(traj.size()) +
						" poses); expected pose timestamps within " + num(args.maxTimeOffset) +
						" s of the relations' t1/t2 (--max-time-offset)");
		if (args.json)
			printJson(args, traj.size(), relations.size(), e);
		else
			printText(args, traj.size(), relations.size(), e);
		if (!std::cout) return fail("cannot write to standard output");
	}
	catch (const std::exception& ex)
	{
		return fail(ex.what());
	}
	return 0;
}
