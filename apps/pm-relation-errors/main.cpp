/* pm-relation-errors — the per-relation errors behind pm-slam-eval's means, for
 * error-distribution plots (bench/run.sh).
 *
 *   pm-relation-errors [--max-time-offset S] TRAJECTORY RELATIONS
 *
 * Prints one line per relation that has a pose at both ends, in the order of
 * RELATIONS: `t1 t2 trans_err_m rot_err_deg`, computed by
 * pmslam::evaluateRelativePoses (same metric and timestamp matching as pm-slam-eval).
 */
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace
{
const char* kUsage =
	"usage: pm-relation-errors [--max-time-offset S] TRAJECTORY RELATIONS\n"
	"\n"
	"Prints 't1 t2 trans_err_m rot_err_deg' for every relation of RELATIONS (Freiburg\n"
	"'.relations') whose two timestamps have a pose in TRAJECTORY ('timestamp x y yaw'),\n"
	"with the relative pose metric of Kuemmerle et al. 2009 (as pm-slam-eval): each\n"
	"timestamp takes the pose with the nearest timestamp within --max-time-offset seconds\n"
	"(default 0.1); the '#' header says how far the matched stamps were.\n"
	"Exit status: 0 success, 2 bad arguments or unreadable input.\n";

int fail(const std::string& message)
{
	std::cerr << "pm-relation-errors: " << message << "\n";
	return 2;
}

/** Seconds >= 0 from the text of --max-time-offset; false if it is not that. */
bool parseSeconds(const std::string& v, double& out)
{
	char* end = nullptr;
	out = std::strtod(v.c_str(), &end);
	return !v.empty() && *end == '\0' && std::isfinite(out) && out >= 0;
}
}  // namespace

int main(int argc, char** argv)
{
	std::vector<std::string> positional;
	double maxTimeOffset = pmslam::kDefaultMaxTimeOffset;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		if (a == "-h" || a == "--help")
		{
			std::fputs(kUsage, stdout);
			return 0;
		}
		if (a == "--max-time-offset" || a.rfind("--max-time-offset=", 0) == 0)
		{
			const std::string v = a.size() > 17 ? a.substr(18) : (i + 1 < argc ? argv[++i] : "");
			if (!parseSeconds(v, maxTimeOffset))
				return fail("--max-time-offset '" + v + "': expected seconds, a number >= 0 (see --help)");
			continue;
		}
		if (a.size() > 1 && a[0] == '-') return fail("unknown option '" + a + "' (see --help)");
		positional.push_back(a);
	}
	if (positional.size() != 2) return fail("expected TRAJECTORY RELATIONS (see --help)");
	try
	{
		const pmslam::Trajectory traj = pmslam::loadTrajectory(positional[0]);
		const std::vector<pmslam::Relation> all = pmslam::loadRelations(positional[1]);
		const auto e = pmslam::evaluateRelativePoses(traj, all, maxTimeOffset);
		std::printf("# %s vs %s: %zu of %zu relations matched\n", positional[0].c_str(), positional[1].c_str(),
					e.matched, all.size());
		std::printf("# time offset of the matched stamps [s]: max %.6f, mean %.6f; %zu of %zu not exact (> 1e-6 s), "
					"%g allowed\n# t1 t2 trans_err_m rot_err_deg\n",
					e.timeOffsetMax, e.timeOffsetMean, e.inexactStamps, 2 * e.matched, maxTimeOffset);
		for (std::size_t k = 0; k < e.matched; ++k)
		{
			const pmslam::Relation& r = all[e.matchedRelations[k]];
			std::printf("%.6f %.6f %.6f %.6f\n", r.t1, r.t2, e.transErrors[k], e.rotErrorsDeg[k]);
		}
	}
	catch (const std::exception& ex)
	{
		return fail(ex.what());
	}
	return 0;
}
