// PerfectMatchAligner on scans ray-cast in synthetic worlds and in MRPT's shipped Malaga map.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/slam/CICP.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/PerfectMatchAligner.h>
#include <pmslam/sensor/ScanPoints.h>

#include <filesystem>
#include <random>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using pmslam::PerfectMatchAligner;
using pmslam::testing::angleDiff;

namespace
{
mrpt::maps::CSimplePointsMap toPointsMap(const mrpt::obs::CObservation2DRangeScan& scan)
{
	mrpt::maps::CSimplePointsMap pts;
	for (const auto& p : pmslam::scanToPoints(scan).hits) pts.insertPoint(p.x, p.y);
	return pts;
}

struct Trial
{
	double dx, dy, dphi;
};

std::vector<Trial> randomTrials(int n, double maxXY, double maxPhi, unsigned seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(-1, 1);
	std::vector<Trial> out;
	for (int i = 0; i < n; ++i)
	{
		// Put half the trials on the boundary of the allowed error box.
		double dx = u(rng) * maxXY, dy = u(rng) * maxXY;
		const double r = std::hypot(dx, dy);
		if (r > maxXY || i % 2 == 0)
		{
			dx *= maxXY / std::max(r, 1e-9);
			dy *= maxXY / std::max(r, 1e-9);
		}
		out.push_back({dx, dy, (i % 2 == 0 ? (u(rng) > 0 ? 1 : -1) : u(rng)) * maxPhi});
	}
	return out;
}

mrpt::maps::COccupancyGridMap2D roomGrid(const pmslam::testing::SyntheticWorld& w)
{
	mrpt::maps::COccupancyGridMap2D grid(-6, 7, -5, 5, 0.05f);
	w.rasterise(grid);
	return grid;
}

void expectConverges(PerfectMatchAligner& aligner, const mrpt::maps::CMetricMap& map,
					 const mrpt::maps::CSimplePointsMap& pts, const TPose2D& truth, const std::vector<Trial>& trials,
					 double tolXY, double tolPhiDeg)
{
	for (const auto& t : trials)
	{
		mrpt::poses::CPosePDFGaussian init;
		init.mean = mrpt::poses::CPose2D(truth.x + t.dx, truth.y + t.dy, truth.phi + t.dphi);
		PerfectMatchAligner::TReturnInfo info;
		const auto pdf = aligner.AlignPDF(&map, &pts, init, info);
		const auto est = pdf->getMeanVal();
		EXPECT_LT(std::hypot(est.x() - truth.x, est.y() - truth.y), tolXY)
			<< "start error (" << t.dx << ", " << t.dy << ", " << mrpt::RAD2DEG(t.dphi) << " deg) -> " << est;
		EXPECT_LT(std::abs(mrpt::RAD2DEG(angleDiff(est.phi(), truth.phi))), tolPhiDeg)
			<< "start error (" << t.dx << ", " << t.dy << ", " << mrpt::RAD2DEG(t.dphi) << " deg) -> " << est;
		EXPECT_GT(info.goodness, 0.3);
		EXPECT_GT(info.nIterations, 0u);
	}
}
}  // namespace

TEST(PerfectMatchAligner, ConvergesFromLargeInitialErrorsInSyntheticRoom)
{
	const auto world = pmslam::testing::furnishedRoom();
	const auto grid = roomGrid(world);
	for (const TPose2D truth : {TPose2D(0.3, -0.2, 0.4), TPose2D(-1.5, 1.4, -2.0), TPose2D(2.2, -1.0, 3.0)})
	{
		const auto pts = toPointsMap(world.scan(truth, 361));
		for (auto opt : {PerfectMatchAligner::Optimizer::RPROP, PerfectMatchAligner::Optimizer::GaussNewton,
						 PerfectMatchAligner::Optimizer::LevenbergMarquardt})
		{
			SCOPED_TRACE(pmslam::toString(opt));
			PerfectMatchAligner aligner;
			aligner.options.optimizer = opt;
			aligner.options.maxIterations = 100;
			expectConverges(aligner, grid, pts, truth, randomTrials(24, 0.3, mrpt::DEG2RAD(10.0), 11), 0.01, 0.2);
		}
	}
}

TEST(PerfectMatchAligner, ToleratesTwentyPercentOutliers)
{
	const auto world = pmslam::testing::furnishedRoom();
	const auto grid = roomGrid(world);
	const TPose2D truth(0.5, 0.2, -0.3);
	auto scan = world.scan(truth, 361, M_PI, 30.0, 0.01, 3);
	// Replace every fifth reading by a random one, as people and clutter do.
	std::mt19937 rng(5);
	std::uniform_real_distribution<float> u(0.3f, 6.0f);
	std::size_t replaced = 0;
	for (std::size_t i = 0; i < scan.getScanSize(); i += 5, ++replaced) scan.setScanRange(i, u(rng)), scan.setScanRangeValidity(i, true);
	ASSERT_GE(replaced * 5, scan.getScanSize());
	const auto pts = toPointsMap(scan);
	PerfectMatchAligner aligner;
	aligner.options.maxIterations = 100;
	expectConverges(aligner, grid, pts, truth, randomTrials(20, 0.3, mrpt::DEG2RAD(10.0), 17), 0.01, 0.2);
}

TEST(PerfectMatchAligner, LiveDistanceLayerMatchesStockGridResult)
{
	// Build the SLAM map type by inserting scans, then match a new scan both ways.
	const auto world = pmslam::testing::furnishedRoom();
	pmslam::OccupancyDistanceGridMap live;
	for (const TPose2D p : {TPose2D(0, 0, 0), TPose2D(1, -1, 1.5), TPose2D(-2, 1, -1.0), TPose2D(3.5, 0, 2.5)})
		live.insertScan(pmslam::scanToPoints(world.scan(p, 361)), p);
	live.materialize();	 // the dense MRPT view of the sparse cells
	const mrpt::maps::COccupancyGridMap2D& stock = live;  // the same cells seen as a plain MRPT grid
	mrpt::maps::COccupancyGridMap2D copy = stock;  // a plain copy: the aligner builds its own layer
	const TPose2D truth(0.8, 0.4, 0.7);
	const auto pts = toPointsMap(world.scan(truth, 361));
	PerfectMatchAligner aligner;
	aligner.options.maxIterations = 100;
	// A map made of quantised scan hits is itself only good to a fraction of a cell, and
	// the SLAM default sigma (0.1 m) is wide for that; match it with the sharper field.
	aligner.options.sigma = 0.05;
	expectConverges(aligner, live, pts, truth, randomTrials(10, 0.3, mrpt::DEG2RAD(10.0), 23), 0.01, 0.2);
	expectConverges(aligner, copy, pts, truth, randomTrials(10, 0.3, mrpt::DEG2RAD(10.0), 23), 0.01, 0.2);
	// Both layers are the same distance field.
	const auto rebuilt = PerfectMatchAligner::distanceMapFromGrid(copy, 0.5, 0.5);
	int x0, y0, x1, y1;
	ASSERT_TRUE(live.distanceMap().touchedBounds(x0, y0, x1, y1));
	for (int y = y0; y <= y1; y += 3)
		for (int x = x0; x <= x1; x += 3)
			ASSERT_EQ(rebuilt.squaredDistanceCells(x, y), live.distanceMap().squaredDistanceCells(x, y)) << x << "," << y;
}

TEST(PerfectMatchAligner, CorridorCovarianceIsLargeAlongTheCorridor)
{
	pmslam::testing::SyntheticWorld corridor;
	corridor.segments.push_back({-40.025, -1.025, 40.025, -1.025});
	corridor.segments.push_back({-40.025, 0.975, 40.025, 0.975});
	mrpt::maps::COccupancyGridMap2D grid(-45, 45, -3, 3, 0.05f);
	corridor.rasterise(grid);
	const TPose2D truth(0.0, 0.0, 0.05);
	const auto pts = toPointsMap(corridor.scan(truth, 361, M_PI, 8.0));
	PerfectMatchAligner aligner;
	mrpt::poses::CPosePDFGaussian init;
	init.mean = mrpt::poses::CPose2D(truth.x + 0.05, truth.y + 0.1, truth.phi + 0.05);
	const auto pdf = aligner.AlignPDF(&grid, &pts, init);
	const auto* g = dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(pdf.get());
	ASSERT_NE(g, nullptr);
	// Across the corridor and in heading the scan pins the pose; along it, nothing does.
	EXPECT_NEAR(g->mean.y(), truth.y, 0.01);
	EXPECT_NEAR(angleDiff(g->mean.phi(), truth.phi), 0.0, mrpt::DEG2RAD(0.2));
	EXPECT_GT(g->cov(0, 0), 1000.0 * g->cov(1, 1));
	EXPECT_GT(g->cov(0, 0), 1.0);
	EXPECT_LT(g->cov(1, 1), 1e-3);
}

TEST(PerfectMatchAligner, MalagaCampusMapShippedWithMrpt)
{
	const std::string path = "/usr/share/mrpt/datasets/2006-MalagaCampus.gridmap.gz";
	if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not installed (package mrpt-common / libmrpt-dev)";
	mrpt::maps::COccupancyGridMap2D grid;
	mrpt::io::CFileGZInputStream f(path);
	mrpt::serialization::archiveFrom(f) >> grid;
	ASSERT_GT(grid.getSizeX(), 100u);
	PerfectMatchAligner aligner;
	aligner.options.maxIterations = 100;
	aligner.options.maxDistance = 1.0;  // sparse outdoor map seen to 30 m: a wider basin
	int poses = 0;
	std::mt19937 rng(3);
	std::uniform_real_distribution<double> ux(grid.getXMin() + 5, grid.getXMax() - 5), uy(grid.getYMin() + 5, grid.getYMax() - 5), ua(-M_PI, M_PI);
	for (int attempt = 0; attempt < 4000 && poses < 5; ++attempt)
	{
		const TPose2D truth(ux(rng), uy(rng), ua(rng));
		if (grid.getPos(truth.x, truth.y) < 0.7f) continue;	 // robot must stand in known free space
		mrpt::maps::CSimplePointsMap pts;
		for (const auto& p : pmslam::testing::castCellCentresInGrid(grid, truth, 361)) pts.insertPoint(p.x, p.y);
		if (pts.size() < 250) continue;	 // need a scan that sees structure
		++poses;
		SCOPED_TRACE("pose " + truth.asString());
		expectConverges(aligner, grid, pts, truth, randomTrials(8, 0.3, mrpt::DEG2RAD(10.0), 31 + poses), 0.01, 0.2);
	}
	EXPECT_EQ(poses, 5);
}

TEST(PerfectMatchAligner, RejectsWhatItCannotAlign)
{
	PerfectMatchAligner aligner;
	mrpt::maps::CSimplePointsMap pts, other;
	pts.insertPoint(1, 0);
	mrpt::poses::CPosePDFGaussian init;
	EXPECT_THROW(aligner.AlignPDF(&other, &pts, init), std::invalid_argument);
	EXPECT_THROW(aligner.Align3DPDF(&other, &pts, mrpt::poses::CPose3DPDFGaussian()), std::logic_error);
}

TEST(PerfectMatchAligner, IgnoresNonFinitePoints)
{
	// A corrupt scan must not poison the sums (a NaN once made the GN solver spin forever).
	const auto world = pmslam::testing::furnishedRoom();
	const auto grid = roomGrid(world);
	const auto dm = PerfectMatchAligner::distanceMapFromGrid(grid, 0.5, 0.5);
	const TPose2D truth(0.3, -0.2, 0.4);
	auto pts = pmslam::scanToPoints(world.scan(truth, 361)).hits;
	pts[10].x = std::numeric_limits<float>::quiet_NaN();
	pts[20].y = std::numeric_limits<float>::infinity();
	for (auto opt : {PerfectMatchAligner::Optimizer::RPROP, PerfectMatchAligner::Optimizer::GaussNewton,
					 PerfectMatchAligner::Optimizer::LevenbergMarquardt})
	{
		PerfectMatchAligner aligner;
		aligner.options.optimizer = opt;
		aligner.options.rpropRefineIterations = 3;
		PerfectMatchAligner::TReturnInfo info;
		const TPose2D est = aligner.alignPoints(dm, pts, TPose2D(0.35, -0.15, 0.45), &info);
		EXPECT_NEAR(est.x, truth.x, 0.01) << pmslam::toString(opt);
		EXPECT_NEAR(est.y, truth.y, 0.01) << pmslam::toString(opt);
		EXPECT_EQ(info.nPoints, pts.size() - 2);
	}
	PerfectMatchAligner aligner;
	EXPECT_THROW(aligner.alignPoints(dm, pts, TPose2D(std::nan(""), 0, 0)), std::invalid_argument);
}

TEST(PerfectMatchAligner, ConsecutiveRealScansFromIntel)
{
	const std::string path = PMSLAM_SOURCE_DIR "/../shared/datasets/intel/intel.clf";
	if (!std::filesystem::exists(path))
		GTEST_SKIP() << path << " absent: the benchmark logs live in ../shared/datasets beside the project";
	auto reader = pmslam::LogReader::open(path);
	reader->onWarning = [](const std::string&) {};
	std::vector<pmslam::LogEvent> scans;
	pmslam::LogEvent ev;
	while (reader->next(ev) && scans.size() < 3000)
		if (ev.kind == pmslam::LogEvent::Kind::Scan && ev.scanHasOdometry) scans.push_back(ev);
	ASSERT_EQ(scans.size(), 3000u);
	// Each scan is aligned to a map made of the scan before it, starting from the odometry
	// increment. Real scans of a real office: the correction to odometry stays small and the
	// match explains most points. Pairs the robot barely moved between are the easy ones, so
	// take pairs at least 5 cm or 3 degrees apart.
	PerfectMatchAligner aligner;
	int pairs = 0, good = 0;
	for (std::size_t i = 1000; i + 1 < scans.size() && pairs < 200; ++i)
	{
		const mrpt::poses::CPose2D odo = mrpt::poses::CPose2D(scans[i + 1].scanOdometry) - mrpt::poses::CPose2D(scans[i].scanOdometry);
		if (std::hypot(odo.x(), odo.y()) < 0.05 && std::abs(odo.phi()) < mrpt::DEG2RAD(3.0)) continue;
		++pairs;
		pmslam::OccupancyDistanceGridMap map;
		map.insertScan(pmslam::scanToPoints(*scans[i].scan), TPose2D(0, 0, 0));
		const auto pts = pmslam::scanToPoints(*scans[i + 1].scan).hits;
		PerfectMatchAligner::TReturnInfo info;
		const TPose2D est = aligner.alignPoints(map.distanceMap(), pts, odo.asTPose(), &info);
		// The same answer from a start 5 cm and 2 degrees off (a large odometry error between two
		// scans): the match, not the start, decides.
		const TPose2D off(odo.x() + 0.04, odo.y() - 0.03, odo.phi() + mrpt::DEG2RAD(2.0));
		const TPose2D est2 = aligner.alignPoints(map.distanceMap(), pts, off);
		const double dxy = std::hypot(est.x - odo.x(), est.y - odo.y()), dphi = std::abs(angleDiff(est.phi, odo.phi()));
		// A map of one real scan is sparse and its cost has shallow side minima, so agreement is
		// to 3 cm / 1 degree (measured: ~90 % of pairs within 2 cm / 0.5 degree).
		const bool agree = std::hypot(est2.x - est.x, est2.y - est.y) < 0.03 &&
						   std::abs(angleDiff(est2.phi, est.phi)) < mrpt::DEG2RAD(1.0);
		if (agree && dxy < 0.1 && dphi < mrpt::DEG2RAD(3.0) && info.inlierFraction > 0.8 && info.goodness > 0.6) ++good;
	}
	EXPECT_EQ(pairs, 200);
	EXPECT_GE(good, 180) << "of " << pairs << " consecutive pairs matched cleanly";
}
