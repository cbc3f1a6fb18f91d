// Micro-benchmarks of scan-to-map alignment: PerfectMatchAligner versus mrpt::slam::CICP
// on the same inputs.
//
// World: a synthetic 20 m × 12 m office (corridor, rooms with doors, desks, pillars).
// Map: 10 scans (361 beams, 1 cm range noise) taken at known poses along the corridor,
// facing both ways. Queries: 20 poses along the corridor path; each query scan (180
// beams at 1° or 361 beams at 0.5°, 180° fan, 1 cm noise) is aligned starting from the
// true pose plus (0.1 m, −0.05 m, 3°). One benchmark iteration aligns all 20 scans.
//
//  PM_<optimizer>   PerfectMatchAligner::AlignPDF(OccupancyDistanceGridMap, scan points)
//                   with the default options (σ 0.05 m, truncation 0.5 m) and the given
//                   optimizer; the grid is built by insertScan of the map scans and its
//                   live distance layer is used as is.
//  CICP_points      CICP::AlignPDF(points map, scan points), as CMetricMapBuilderICP uses it
//                   with matchAgainstTheGrid = false: the map is a CSimplePointsMap of the
//                   same map scans (minDistBetweenLaserPoints 0.05), the scan a
//                   CSimplePointsMap (minDistBetweenLaserPoints 0.02). CICP options:
//                   maxIterations 80, thresholdDist 0.75, thresholdAng 0.15°, ALFA 0.5,
//                   smallestThresholdDist 0.05 (closest-only correspondences are MRPT 2.x's
//                   fixed behaviour), other options at their defaults.
//  CICP_points_ini  the same, with the [ICP] section of MRPT's icp-slam_demo_classic.ini
//                   (thresholdDist 0.3, thresholdAng 5°, ALFA 0.8, onlyUniqueRobust).
//  CICP_grid        CICP::AlignPDF(occupancy grid, scan points), as with
//                   matchAgainstTheGrid = true, against the very grid PM uses, with the
//                   [ICP] section of icp-slam_demo_classic_gridmatch.ini.
//
// Counters: time_per_align (seconds), err_mm / max_err_mm (position error w.r.t. the
// true pose over the 20 scans), err_deg (mean |heading error|), iters (mean iterations),
// fails (scans with error > 50 mm or > 1°).
#include <benchmark/benchmark.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CICP.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/PerfectMatchAligner.h>
#include <pmslam/sensor/ScanPoints.h>

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "SyntheticWorld.h"

namespace
{
using mrpt::math::TPose2D;
using pmslam::testing::SyntheticWorld;

constexpr int kQueries = 20;
constexpr double kNoise = 0.01;	 // m, range noise of every scan
constexpr double kMaxRange = 30.0;
const TPose2D kInitialError{0.10, -0.05, mrpt::DEG2RAD(3.0)};

SyntheticWorld officeWorld()
{
	SyntheticWorld w;
	w.addBox(0, 0, 20, 12);
	// Corridor y ∈ [5, 7]; its walls have a 1 m door into every room.
	auto wallWithDoors = [&](double y, const std::vector<double>& doors) {
		double x = 0;
		for (double d : doors)
		{
			w.segments.push_back({x, y, d, y});
			x = d + 1.0;
		}
		w.segments.push_back({x, y, 20, y});
	};
	wallWithDoors(5.0, {2.0, 7.0, 12.0, 17.0});
	wallWithDoors(7.0, {1.0, 5.5, 9.0, 13.5, 17.5});
	for (double x : {5.0, 10.0, 15.0}) w.segments.push_back({x, 0, x, 5});	 // south rooms
	for (double x : {4.0, 8.0, 12.0, 16.0}) w.segments.push_back({x, 7, x, 12});	// north rooms
	// Furniture and pillars.
	w.addBox(0.8, 1.0, 2.6, 1.8);
	w.addBox(6.2, 2.5, 7.4, 3.3);
	w.addBox(11.0, 0.5, 13.0, 1.1);
	w.addBox(17.5, 3.0, 18.3, 4.2);
	w.addBox(1.5, 9.0, 2.7, 9.6);
	w.addBox(6.0, 10.5, 7.2, 11.5);
	w.addBox(9.5, 8.5, 10.1, 9.1);
	w.addBox(13.2, 9.8, 14.8, 10.6);
	w.addBox(17.0, 8.0, 18.5, 8.6);
	w.addBox(6.0, 5.2, 6.3, 5.5);  // pillars in the corridor
	w.addBox(14.0, 6.45, 14.3, 6.75);
	return w;
}

/** The 20 query poses: along the corridor, weaving a little. */
std::vector<TPose2D> queryPoses()
{
	std::vector<TPose2D> out;
	for (int i = 0; i < kQueries; ++i)
		out.push_back({1.0 + 0.9 * i, 6.0 + 0.3 * std::sin(0.7 * i), 0.15 * std::sin(0.5 * i)});
	return out;
}

/** Where the map scans were taken: along the corridor, facing both ways. */
std::vector<TPose2D> mapPoses()
{
	std::vector<TPose2D> out;
	for (double x : {0.6, 4.5, 8.5, 12.5, 16.5}) out.push_back({x, 6.1, 0.05});
	for (double x : {19.4, 15.0, 11.0, 7.0, 3.0}) out.push_back({x, 5.9, M_PI - 0.05});
	return out;
}

mrpt::obs::CObservation2DRangeScan makeScan(const SyntheticWorld& w, const TPose2D& pose, int beams, unsigned seed)
{
	// 180 beams → 1° spacing (179° fan), 361 beams → 0.5° (180° fan).
	const double step = beams == 361 ? mrpt::DEG2RAD(0.5) : mrpt::DEG2RAD(1.0);
	return w.scan(pose, std::size_t(beams), step * (beams - 1), kMaxRange, kNoise, seed);
}

struct Scenario
{
	SyntheticWorld world;
	std::vector<TPose2D> truth;
	pmslam::OccupancyDistanceGridMap grid;	// PM's map (and CICP_grid's)
	mrpt::maps::CSimplePointsMap pointsMap;	 // CICP's map
	std::vector<mrpt::maps::CSimplePointsMap> scans;	// the query scans, robot frame
	std::vector<mrpt::poses::CPosePDFGaussian> initial;
};

const Scenario& scenario(int beams)
{
	static std::map<int, std::unique_ptr<Scenario>> cache;
	auto& s = cache[beams];
	if (s) return *s;
	s = std::make_unique<Scenario>();
	s->world = officeWorld();
	s->truth = queryPoses();
	s->pointsMap.insertionOptions.minDistBetweenLaserPoints = 0.05f;
	s->pointsMap.insertionOptions.fuseWithExisting = false;
	s->pointsMap.insertionOptions.isPlanarMap = true;
	const auto mp = mapPoses();
	for (std::size_t k = 0; k < mp.size(); ++k)
	{
		const auto scan = makeScan(s->world, mp[k], 361, 100 + unsigned(k));
		s->grid.insertScan(pmslam::scanToPoints(scan), mp[k]);
		s->pointsMap.insertObservation(scan, mrpt::poses::CPose3D(mrpt::poses::CPose2D(mp[k])));
	}
	for (int i = 0; i < kQueries; ++i)
	{
		const auto scan = makeScan(s->world, s->truth[i], beams, 1 + unsigned(i));
		mrpt::maps::CSimplePointsMap pts;
		pts.insertionOptions.minDistBetweenLaserPoints = 0.02f;	// as CMetricMapBuilderICP
		pts.insertObservation(scan);
		s->scans.push_back(std::move(pts));
		const TPose2D& t = s->truth[i];
		mrpt::poses::CPosePDFGaussian init;
		init.mean = mrpt::poses::CPose2D(t.x + kInitialError.x, t.y + kInitialError.y, t.phi + kInitialError.phi);
		s->initial.push_back(init);
	}
	return *s;
}

/** Aligns scan i; returns the estimate and the iteration count. */
using AlignFn = std::function<mrpt::poses::CPose2D(std::size_t i, unsigned& iterations)>;

void runAlignment(benchmark::State& state, int beams, const AlignFn& align)
{
	const Scenario& sc = scenario(beams);
	// Accuracy pass (identical to the timed work: the matchers are deterministic).
	double errSum = 0, errMax = 0, angSum = 0, itSum = 0, points = 0;
	int fails = 0;
	for (std::size_t i = 0; i < sc.scans.size(); ++i)
	{
		unsigned it = 0;
		const auto est = align(i, it);
		const double e = std::hypot(est.x() - sc.truth[i].x, est.y() - sc.truth[i].y);
		const double a = std::abs(pmslam::testing::angleDiff(est.phi(), sc.truth[i].phi));
		errSum += e;
		errMax = std::max(errMax, e);
		angSum += a;
		itSum += it;
		points += double(sc.scans[i].size());
		if (e > 0.05 || a > mrpt::DEG2RAD(1.0)) ++fails;
	}
	for (auto _ : state)
		for (std::size_t i = 0; i < sc.scans.size(); ++i)
		{
			unsigned it = 0;
			benchmark::DoNotOptimize(align(i, it));
		}
	const double n = double(sc.scans.size());
	state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(sc.scans.size()));  // alignments/s
	state.counters["time_per_align"] =
		benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
	state.counters["err_mm"] = 1000.0 * errSum / n;
	state.counters["max_err_mm"] = 1000.0 * errMax;
	state.counters["err_deg"] = mrpt::RAD2DEG(angSum / n);
	state.counters["iters"] = itSum / n;
	state.counters["points"] = points / n;
	state.counters["fails"] = fails;
}

void registerPM(pmslam::PerfectMatchAligner::Optimizer opt, int beams)
{
	const std::string name = "PM_" + pmslam::toString(opt) + "/beams:" + std::to_string(beams);
	benchmark::RegisterBenchmark(name.c_str(), [opt, beams](benchmark::State& state) {
		const Scenario& sc = scenario(beams);
		pmslam::PerfectMatchAligner::TConfigParams p;
		p.optimizer = opt;
		pmslam::PerfectMatchAligner pm(p);
		runAlignment(state, beams, [&](std::size_t i, unsigned& iterations) {
			pmslam::PerfectMatchAligner::TReturnInfo info;
			const auto pdf = pm.AlignPDF(&sc.grid, &sc.scans[i], sc.initial[i], info);
			iterations = info.nIterations;
			return pdf->getMeanVal();
		});
	})->Unit(benchmark::kMicrosecond);
}

enum class IcpVariant
{
	Points,
	PointsIni,
	Grid
};

mrpt::slam::CICP::TConfigParams icpOptions(IcpVariant v)
{
	mrpt::slam::CICP::TConfigParams o;
	switch (v)
	{
		case IcpVariant::Points:
			o.maxIterations = 80;
			o.thresholdDist = 0.75;
			o.thresholdAng = mrpt::DEG2RAD(0.15);
			o.ALFA = 0.5;
			o.smallestThresholdDist = 0.05;
			break;
		case IcpVariant::PointsIni:	 // icp-slam_demo_classic.ini, [ICP]
			o.maxIterations = 80;
			o.thresholdDist = 0.3;
			o.thresholdAng = mrpt::DEG2RAD(5.0);
			o.ALFA = 0.8;
			o.smallestThresholdDist = 0.05;
			o.onlyUniqueRobust = true;
			o.corresponding_points_decimation = 5;
			break;
		case IcpVariant::Grid:	// icp-slam_demo_classic_gridmatch.ini, [ICP]
			o.maxIterations = 60;
			o.thresholdDist = 0.5;
			o.thresholdAng = mrpt::DEG2RAD(7.0);
			o.ALFA = 0.5;
			o.smallestThresholdDist = 0.06;
			o.corresponding_points_decimation = 3;
			break;
	}
	o.ICP_algorithm = mrpt::slam::icpClassic;
	return o;
}

void registerICP(IcpVariant v, int beams)
{
	const char* base = v == IcpVariant::Points ? "CICP_points" : v == IcpVariant::PointsIni ? "CICP_points_ini" : "CICP_grid";
	const std::string name = std::string(base) + "/beams:" + std::to_string(beams);
	benchmark::RegisterBenchmark(name.c_str(), [v, beams](benchmark::State& state) {
		const Scenario& sc = scenario(beams);
		mrpt::slam::CICP icp(icpOptions(v));
		const mrpt::maps::CMetricMap* ref =
			v == IcpVariant::Grid ? static_cast<const mrpt::maps::CMetricMap*>(&sc.grid) : &sc.pointsMap;
		runAlignment(state, beams, [&](std::size_t i, unsigned& iterations) {
			mrpt::slam::CICP::TReturnInfo info;
			const auto pdf = icp.AlignPDF(ref, &sc.scans[i], sc.initial[i], info);
			iterations = info.nIterations;
			return pdf->getMeanVal();
		});
	})->Unit(benchmark::kMicrosecond);
}

}  // namespace

int main(int argc, char** argv)
{
	using Opt = pmslam::PerfectMatchAligner::Optimizer;
	for (int beams : {180, 361})
	{
		for (Opt o : {Opt::RPROP, Opt::GaussNewton, Opt::LevenbergMarquardt}) registerPM(o, beams);
		for (IcpVariant v : {IcpVariant::Points, IcpVariant::PointsIni, IcpVariant::Grid}) registerICP(v, beams);
	}
	benchmark::Initialize(&argc, argv);
	if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
	benchmark::AddCustomContext("world", "synthetic 20 m x 12 m office; map from 10 scans at known poses");
	benchmark::AddCustomContext("queries", std::to_string(kQueries) + " scans per iteration, initial error (0.1 m, -0.05 m, 3 deg)");
	benchmark::RunSpecifiedBenchmarks();
	benchmark::Shutdown();
	return 0;
}
