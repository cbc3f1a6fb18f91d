/* pm-global-localization — how often the start is found on a map without a start pose.
 *
 *   pm-global-localization MAP LOG TRAJECTORY [--starts N] [--config INI] [--coarse K FLOOR POINTS]
 *
 * MAP is what `pm-slam-app --localize` takes (a pm-slam-app output folder, say), TRAJECTORY the SLAM
 * run's trajectory.txt on it (the reference). From N start scans spread evenly over LOG, each start
 * is searched with GlobalLocalizer from that scan on, as `pm-slam-app --localize MAP` without
 * --initial-pose does, and its answer compared with the reference pose of that scan: found (within
 * 0.3 m and 5 degrees), wrong and confident (decided elsewhere), or undecided. Prints one Markdown
 * table row: found / wrong / undecided, scans needed (median, max), whole-map search time (mean, max)
 * and the map's area. bench/global.sh runs it on the three logs.
 */
#include <mrpt/math/wrap2pi.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/io/PriorMap.h>
#include <pmslam/slam/GlobalLocalizer.h>
#include <pmslam/slam/OdometrySelector.h>
#include <pmslam/slam/SlamConfig.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace
{
struct Scan
{
	pmslam::LogEvent event;
	std::optional<mrpt::math::TPose2D> odometry;
};

std::vector<Scan> readScans(const std::string& log, const pmslam::SlamConfig& cfg)
{
	auto reader = pmslam::LogReader::open(log, cfg.log);
	pmslam::OdometrySelector odo(cfg.odometrySource);
	std::vector<Scan> scans;
	for (pmslam::LogEvent ev; reader->next(ev);)
		if (ev.kind == pmslam::LogEvent::Kind::Odometry)
			odo.takeReading(ev);
		else
			scans.push_back({ev, odo.forScan(ev)});
	return scans;
}

std::map<long long, mrpt::math::TPose2D> readTrajectory(const std::string& path)
{
	std::map<long long, mrpt::math::TPose2D> poses;
	std::ifstream in(path);
	for (std::string line; std::getline(in, line);)
	{
		if (line.empty() || line[0] == '#') continue;
		double t, x, y, yaw;
		if (std::istringstream(line) >> t >> x >> y >> yaw) poses[std::llround(t * 1e6)] = {x, y, yaw};
	}
	return poses;
}

double median(std::vector<double> v)
{
	if (v.empty()) return 0;
	std::sort(v.begin(), v.end());
	return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv)
{
	std::vector<std::string> pos;
	std::size_t starts = 100;
	std::string ini;
	pmslam::GlobalLocalizerOptions opts;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		if (a == "--starts" && i + 1 < argc) starts = std::stoul(argv[++i]);
		else if (a == "--config" && i + 1 < argc) ini = argv[++i];
		else if (a == "--coarse" && i + 3 < argc)
		{
			opts.coarseToFine = true;
			opts.coarseCandidates = std::stoul(argv[++i]);
			opts.coarseFloor = std::stod(argv[++i]);
			opts.coarsePoints = std::stoul(argv[++i]);
		}
		else pos.push_back(a);
	}
	if (pos.size() != 3)
	{
		std::fprintf(stderr, "usage: pm-global-localization MAP LOG TRAJECTORY [--starts N] [--config INI]\n");
		return 2;
	}
	const auto cfg = pmslam::loadSlamConfig(ini);
	const auto map = pmslam::loadPriorMap(pos[0], cfg.mapping.grid.resolution);
	const auto scans = readScans(pos[1], cfg);
	const auto reference = readTrajectory(pos[2]);
	const std::size_t last = scans.size() > 400 ? scans.size() - 400 : 0;  // room to decide after a start
	std::size_t found = 0, wrong = 0, undecided = 0, searches = 0;
	std::vector<double> needed, searchTimes;
	double maxSearch = 0;
	for (std::size_t k = 0; k < starts; ++k)
	{
		const std::size_t s0 = last * k / starts;
		pmslam::GlobalLocalizer g(map.grid, cfg.matcher, cfg.mapping.grid.scan, opts);
		std::size_t s = s0;
		while (s < scans.size() && g.addScan(*scans[s].event.scan, scans[s].odometry) ==
									   pmslam::GlobalLocalizer::State::Searching)
			++s;
		searches += g.searches();
		searchTimes.push_back(g.searchSeconds() / std::max<std::size_t>(1, g.searches()));
		maxSearch = std::max(maxSearch, searchTimes.back());
		const auto ref = reference.find(std::llround(scans[s0].event.timestamp * 1e6));
		if (g.state() != pmslam::GlobalLocalizer::State::Found || ref == reference.end())
		{
			++undecided;
			continue;
		}
		const auto p = g.best()->origin;
		const bool right = std::hypot(p.x - ref->second.x, p.y - ref->second.y) <= 0.3 &&
						   std::abs(mrpt::math::wrapToPi(p.phi - ref->second.phi)) <= 5 * M_PI / 180;
		if (!right)
			std::fprintf(stderr, "start %zu (t %.3f): decided at %.2f %.2f %.1f deg, reference %.2f %.2f %.1f deg\n", s0,
						 scans[s0].event.timestamp, p.x, p.y, p.phi * 180 / M_PI, ref->second.x, ref->second.y,
						 ref->second.phi * 180 / M_PI);
		(right ? found : wrong) += 1;
		needed.push_back(double(g.scansUsed()));
	}
	const double area = map.grid.getSizeX() * map.grid.getSizeY() * std::pow(map.grid.getResolution(), 2);
	std::printf("| %s | %zu | %zu / %zu / %zu | %.0f / %.0f | %.2f / %.2f s | %.0f m² |\n", pos[1].c_str(), starts, found,
				wrong, undecided, median(needed), needed.empty() ? 0.0 : *std::max_element(needed.begin(), needed.end()),
				searches ? std::accumulate(searchTimes.begin(), searchTimes.end(), 0.0) / double(searchTimes.size()) : 0.0,
				maxSearch, area);
	return 0;
}
