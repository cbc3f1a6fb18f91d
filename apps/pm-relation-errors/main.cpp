/* pm-relation-errors — the per-relation errors behind pm-slam-eval's means, for
 * error-distribution plots (bench/run.sh).
 *
 *   pm-relation-errors TRAJECTORY RELATIONS
 *
 * Prints one line per relation that has a pose at both ends, in the order of
 * RELATIONS: `t1 t2 trans_err_m rot_err_deg`, computed by
 * pmslam::evaluateRelativePoses (same metric and tolerance as pm-slam-eval).
 */
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/io/Trajectory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace
{
constexpr double kTolerance = 1e-6;	 // seconds, as pm-slam-eval

const char* kUsage =
	"usage: pm-relation-errors TRAJECTORY RELATIONS\n"
	"\n"
	"Prints 't1 t2 trans_err_m rot_err_deg' for every relation of RELATIONS (Freiburg\n"
	"'.relations') whose two timestamps have a pose in TRAJECTORY ('timestamp x y yaw'),\n"
	"with the relative pose metric of Kuemmerle et al. 2009 (as pm-slam-eval).\n"
	"Exit status: 0 success, 2 bad arguments or unreadable input.\n";

bool hasPose(const std::vector<double>& sortedStamps, double t)
{
	const auto it = std::lower_bound(sortedStamps.begin(), sortedStamps.end(), t - kTolerance);
	return it != sortedStamps.end() && std::abs(*it - t) <= kTolerance;
}
}  // namespace

int main(int argc, char** argv)
{
	std::vector<std::string> positional;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		if (a == "-h" || a == "--help")
		{
			std::fputs(kUsage, stdout);
			return 0;
		}
		if (a.size() > 1 && a[0] == '-')
		{
			std::cerr << "pm-relation-errors: unknown option '" << a << "' (see --help)\n";
			return 2;
		}
		positional.push_back(a);
	}
	if (positional.size() != 2)
	{
		std::cerr << "pm-relation-errors: expected TRAJECTORY RELATIONS (see --help)\n";
		return 2;
	}
	try
	{
		const pmslam::Trajectory traj = pmslam::loadTrajectory(positional[0]);
		const std::vector<pmslam::Relation> all = pmslam::loadRelations(positional[1]);

		// Keep the relations that will match, so the error vectors line up with them.
		std::vector<double> stamps;
		stamps.reserve(traj.size());
		for (const auto& p : traj) stamps.push_back(p.timestamp);
		std::sort(stamps.begin(), stamps.end());
		std::vector<pmslam::Relation> used;
		for (const auto& r : all)
			if (hasPose(stamps, r.t1) && hasPose(stamps, r.t2)) used.push_back(r);

		const auto e = pmslam::evaluateRelativePoses(traj, used, kTolerance);
		if (e.matched != used.size() || e.transErrors.size() != used.size() || e.rotErrorsDeg.size() != used.size())
		{
			std::cerr << "pm-relation-errors: internal mismatch: " << used.size() << " relations selected, "
					  << e.matched << " matched\n";
			return 2;
		}
		std::printf("# %s vs %s: %zu of %zu relations matched\n# t1 t2 trans_err_m rot_err_deg\n",
					positional[0].c_str(), positional[1].c_str(), used.size(), all.size());
		for (std::size_t i = 0; i < used.size(); ++i)
			std::printf("%.6f %.6f %.6f %.6f\n", used[i].t1, used[i].t2, e.transErrors[i], e.rotErrorsDeg[i]);
	}
	catch (const std::exception& ex)
	{
		std::cerr << "pm-relation-errors: " << ex.what() << "\n";
		return 2;
	}
	return 0;
}
