/* pm-slam-eval — score a SLAM trajectory against Freiburg ground-truth relations
 * with the relative-displacement metric of Kümmerle et al. 2009
 * (see libpmslam/include/pmslam/eval/RelativePoseEvaluation.h). */
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace
{
const char* kUsage =
	"usage: pm-slam-eval [--carmen-out FILE] [--json] TRAJECTORY RELATIONS\n"
	"\n"
	"Scores TRAJECTORY (lines 'timestamp x y yaw', as written by pm-slam-app) against\n"
	"RELATIONS (Freiburg '.relations': 't1 t2 x y z roll pitch yaw') with the relative\n"
	"pose metric of Kuemmerle et al. 2009. Relation timestamps must equal pose timestamps\n"
	"(tolerance 1e-6 s).\n"
	"\n"
	"options (anywhere on the command line):\n"
	"  --carmen-out FILE  also write the trajectory as a Carmen log (FLASER lines with\n"
	"                     zero readings) for the Freiburg metricEvaluator\n"
	"  --json             print one JSON object with all the numbers instead of text\n"
	"  -h, --help         print this help and exit\n"
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
}  // namespace

int main(int argc, char** argv)
{
	std::string carmenOut;
	bool json = false;
	std::vector<std::string> positional;
	bool endOfOptions = false;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		if (endOfOptions || a.empty() || a[0] != '-' || a == "-")
			positional.push_back(a);
		else if (a == "--")
			endOfOptions = true;
		else if (a == "-h" || a == "--help")
		{
			std::cout << kUsage;
			return 0;
		}
		else if (a == "--json")
			json = true;
		else if (a == "--carmen-out")
		{
			if (i + 1 >= argc || argv[i + 1][0] == '\0')
				return fail("--carmen-out expects a FILE (see --help)");
			carmenOut = argv[++i];
		}
		else if (a.rfind("--carmen-out=", 0) == 0)
		{
			carmenOut = a.substr(13);
			if (carmenOut.empty()) return fail("--carmen-out expects a FILE (see --help)");
		}
		else
			return fail("unknown option '" + a + "' (see --help)");
	}
	if (positional.size() != 2)
		return fail("expected 2 arguments TRAJECTORY RELATIONS, got " + std::to_string(positional.size()) +
					" (see --help)");
	const std::string& trajPath = positional[0];
	const std::string& relPath = positional[1];

	try
	{
		const pmslam::Trajectory traj = pmslam::loadTrajectory(trajPath);
		const std::vector<pmslam::Relation> relations = pmslam::loadRelations(relPath);
		if (!carmenOut.empty()) pmslam::writeCarmenLog(carmenOut, traj);

		const pmslam::RelativePoseErrors e = pmslam::evaluateRelativePoses(traj, relations);
		if (e.matched == 0)
			return fail("no relation of " + relPath + " (" + std::to_string(relations.size()) +
						" relations) matched two poses of " + trajPath + " (" + std::to_string(traj.size()) +
						" poses); expected pose timestamps equal to the relations' t1/t2 within 1e-6 s");

		if (json)
		{
			std::cout << "{\"trajectory\": " << jsonString(trajPath) << ", \"relations_file\": " << jsonString(relPath)
					  << ", \"poses\": " << traj.size() << ", \"relations\": " << relations.size()
					  << ", \"matched\": " << e.matched << ", \"missing\": " << e.missing
					  << ", \"trans_mean_m\": " << num(e.transMean) << ", \"trans_std_m\": " << num(e.transStd)
					  << ", \"trans_mean_sq_m2\": " << num(e.transMeanSq) << ", \"trans_max_m\": " << num(e.transMax)
					  << ", \"rot_mean_deg\": " << num(e.rotMeanDeg) << ", \"rot_std_deg\": " << num(e.rotStdDeg)
					  << ", \"rot_mean_sq_deg2\": " << num(e.rotMeanSqDeg2) << ", \"rot_max_deg\": " << num(e.rotMaxDeg)
					  << "}" << std::endl;
		}
		else
		{
			char buf[256];
			std::cout << "trajectory: " << trajPath << " (" << traj.size() << " poses)\n"
					  << "relations:  " << relPath << " (" << relations.size() << " relations)\n"
					  << "relations matched: " << e.matched << ", missing: " << e.missing << "\n";
			std::snprintf(buf, sizeof(buf),
						  "translational error [m]: %.4f +/- %.4f, mean of squares %.6f m^2, max %.4f\n",
						  e.transMean, e.transStd, e.transMeanSq, e.transMax);
			std::cout << buf;
			std::snprintf(buf, sizeof(buf),
						  "rotational error [deg]:  %.3f +/- %.3f, mean of squares %.4f deg^2, max %.3f\n",
						  e.rotMeanDeg, e.rotStdDeg, e.rotMeanSqDeg2, e.rotMaxDeg);
			std::cout << buf << std::flush;
		}
		if (!std::cout) return fail("cannot write to standard output");
	}
	catch (const std::exception& ex)
	{
		return fail(ex.what());
	}
	return 0;
}
