/* pm-relation-check — how consistent are reference relations with the scans and the odometry?
 *
 *   pm-relation-check [--max-dt S] [--map-span S] LOG RELATIONS [TRAJECTORY]
 *
 * For every relation `t1 t2` of RELATIONS at most --max-dt apart (default 1 s) over which the
 * robot moved more than 5 cm, scan t2 is aligned with the Perfect Match aligner to a map made of
 * scan t1 (plus the scans of the --map-span seconds before it, placed by TRAJECTORY, default 0),
 * starting from the reference relation itself. Prints per relation
 *   t1 t2 dist  match_along match_cross  odo_along odo_cross  [slam_along slam_cross]
 * the errors (m) of that match, of the log's odometry and of TRAJECTORY against the reference,
 * along / across the track; then '#' summary lines: RMS of each, and the component every pair
 * shares, sqrt(mean(a·b)). Odometry and scan matching share nothing but the reference: what
 * they have in common estimates the reference's own error.
 */
#include <mrpt/poses/CPose2D.h>
#include <pmslam/io/CarmenLogReader.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>
#include <pmslam/eval/RelativePoseEvaluation.h>
#include <pmslam/sensor/ScanPoints.h>
#include <pmslam/io/Trajectory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>
#include <vector>

#include "../common/CommandLine.h"
#include "../common/Message.h"

namespace
{
const char* kUsage =
	"usage: pm-relation-check [--max-dt S] [--map-span S] LOG RELATIONS [TRAJECTORY]\n"
	"\n"
	"Aligns scan t2 of each short relation to a map of scan t1 starting from the reference\n"
	"relation and prints the errors of that match, of the odometry and of TRAJECTORY against\n"
	"the reference (along / across the track), then RMS and shared components. LOG is a Carmen\n"
	"log. Exit status: 0 success, 2 bad arguments or unreadable input.\n";

using mrpt::poses::CPose2D;
long long key(double t) { return std::llround(t * 1e6); }
}  // namespace

int main(int argc, char** argv)
{
	double maxDt = 1.0, mapSpan = 0.0;
	std::vector<std::string> files;
	const auto words = pmslam_app::splitOptionValues(argc, argv, {"--max-dt", "--map-span"});
	for (std::size_t i = 0; i < words.size(); ++i)
	{
		const std::string& a = words[i];
		if ((a == "--max-dt" || a == "--map-span") && i + 1 < words.size())
			(a == "--max-dt" ? maxDt : mapSpan) = std::atof(words[++i].c_str());
		else if (a == "-h" || a == "--help")
			return std::printf("%s", kUsage), 0;
		else
			files.push_back(a);
	}
	if (files.size() < 2 || files.size() > 3 || !(maxDt > 0) || !(mapSpan >= 0))
		return std::fprintf(stderr, "%s", kUsage), 2;
	try
	{
		pmslam::CarmenLogReader reader(files[0]);
		reader.onWarning = nullptr;
		pmslam::OccupancyGridUpdateOptions gridOpts;
		std::map<long long, std::pair<pmslam::ScanPoints, mrpt::math::TPose2D>> scans;
		pmslam::LogEvent ev;
		while (reader.next(ev))
			if (ev.kind == pmslam::LogEvent::Kind::Scan && ev.scanHasOdometry)
				scans[key(ev.timestamp)] = {pmslam::scanToPoints(*ev.scan, gridOpts.scan), ev.scanOdometry};
		const auto relations = pmslam::loadRelations(files[1]);
		std::map<long long, CPose2D> slam;
		if (files.size() == 3)
			for (const auto& p : pmslam::loadTrajectory(files[2])) slam[key(p.timestamp)] = CPose2D(p.x, p.y, p.yaw);

		pmslam::PerfectMatchMatcher aligner;
		std::vector<std::vector<double>> rows;	// match a/c, odo a/c, slam a/c
		for (const auto& r : relations)
		{
			const long long k1 = key(r.t1), k2 = key(r.t2);
			if (r.t2 - r.t1 > maxDt || std::hypot(r.x, r.y) < 0.05 || !scans.count(k1) || !scans.count(k2)) continue;
			pmslam::OccupancyDistanceGridMap map(gridOpts);
			map.insertScan(scans[k1].first, {0, 0, 0});
			if (mapSpan > 0 && slam.count(k1))
				for (auto it = scans.lower_bound(key(r.t1 - mapSpan)); it != scans.end() && it->first < k1; ++it)
					if (slam.count(it->first)) map.insertScan(it->second.first, (slam[it->first] - slam[k1]).asTPose());
			const CPose2D ref(r.x, r.y, r.yaw);
			const CPose2D match(aligner.alignPoints(map.distanceMap(), scans[k2].first.hits, ref.asTPose()));
			const CPose2D odo = CPose2D(scans[k2].second) - CPose2D(scans[k1].second);
			// Errors in the reference's frame at t2: x along the track.
			const CPose2D em = match - ref, eo = odo - ref;
			std::vector<double> row{em.x(), em.y(), eo.x(), eo.y()};
			std::printf("%.6f %.6f %.3f  %+.4f %+.4f  %+.4f %+.4f", r.t1, r.t2, std::hypot(r.x, r.y), em.x(), em.y(),
						eo.x(), eo.y());
			if (slam.count(k1) && slam.count(k2))
			{
				const CPose2D es = (slam[k2] - slam[k1]) - ref;
				row.push_back(es.x());
				row.push_back(es.y());
				std::printf("  %+.4f %+.4f", es.x(), es.y());
			}
			std::printf("\n");
			rows.push_back(row);
		}
		if (rows.empty()) return std::fprintf(stderr, "pm-relation-check: no usable relation\n"), 2;
		const bool withSlam = rows.front().size() == 6 &&
							  std::all_of(rows.begin(), rows.end(), [](const auto& v) { return v.size() == 6; });
		const char* names[3] = {"match", "odometry", "slam"};
		const int nEst = withSlam ? 3 : 2;
		auto mean = [&](int a, int b) {
			double s = 0;
			for (const auto& v : rows) s += v[a] * v[b];
			return s / double(rows.size());
		};
		auto signedRoot = [](double v) { return std::copysign(std::sqrt(std::abs(v)), v); };
		std::printf("# %zu relations; RMS error against the reference (m), along / across the track:\n", rows.size());
		for (int e = 0; e < nEst; ++e)
			std::printf("#   %-8s %.4f / %.4f\n", names[e], std::sqrt(mean(2 * e, 2 * e)),
						std::sqrt(mean(2 * e + 1, 2 * e + 1)));
		std::printf("# shared component sqrt(mean(a*b)) (m), along / across:\n");
		for (int a = 0; a < nEst; ++a)
			for (int b = a + 1; b < nEst; ++b)
				std::printf("#   %s-%s %.4f / %.4f\n", names[a], names[b], signedRoot(mean(2 * a, 2 * b)),
							signedRoot(mean(2 * a + 1, 2 * b + 1)));
	}
	catch (const std::exception& e)
	{
		std::fprintf(stderr, "pm-relation-check: %s\n", pmslam_app::withoutLibraryPrefix(e.what()).c_str());
		return 2;
	}
	return 0;
}
