/* pmslam example: replacing MRPT's CICP with pmslam::PerfectMatchAligner.
 *
 * A typical MRPT program aligns a laser scan (a CSimplePointsMap in the robot frame) to an occupancy
 * grid through the CMetricMapsAlignmentAlgorithm interface. The only change to use Perfect Match is
 * the object behind that reference: the call, the maps and the result type stay the same.
 *
 *   example-replace-icp [MAP.gridmap.gz]
 *
 * The map defaults to MRPT's 2006-MalagaCampus.gridmap.gz; without it a synthetic room is drawn.
 * A scan is simulated in the map at a known pose (the truth); both aligners start from the same
 * wrong guess (20 cm, 15 cm and 3° off). Output lines: "truth X Y YAW_DEG", "guess ...",
 * "CICP X Y YAW_DEG", "PerfectMatchAligner X Y YAW_DEG" (metres, degrees, map frame).
 */
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/slam/CICP.h>
#include <mrpt/slam/CMetricMapsAlignmentAlgorithm.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/match/PerfectMatchAligner.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace
{
// Aligns `scan` (robot frame) to `grid` with whatever algorithm is behind `aligner`.
mrpt::poses::CPose2D align(mrpt::slam::CMetricMapsAlignmentAlgorithm& aligner,
						   const mrpt::maps::COccupancyGridMap2D& grid, const mrpt::maps::CSimplePointsMap& scan,
						   const mrpt::poses::CPose2D& guess)
{
	return aligner.Align(&grid, &scan, guess)->getMeanVal();
}

void print(const char* what, const mrpt::poses::CPose2D& p)
{
	std::printf("%s %.4f %.4f %.3f\n", what, p.x(), p.y(), mrpt::RAD2DEG(p.phi()));
}

// A 12 m × 8 m room with a few pieces of furniture, 5 cm cells (when MRPT's map is absent).
void drawRoom(mrpt::maps::COccupancyGridMap2D& grid)
{
	grid.setSize(-7, 7, -5, 5, 0.05f, 0.5f);
	auto box = [&](double x0, double y0, double x1, double y1, float pFree) {
		for (int y = grid.y2idx(y0); y <= grid.y2idx(y1); ++y)
			for (int x = grid.x2idx(x0); x <= grid.x2idx(x1); ++x) grid.setCell(x, y, pFree);
	};
	box(-6, -4, 6, 4, 0.05f);  // walls...
	box(-5.95, -3.95, 5.95, 3.95, 0.95f);  // ...around free space
	box(1, 1, 2, 1.6, 0.05f);
	box(-3, -2.5, -2.6, -1.8, 0.05f);
	box(3.5, -3.95, 3.6, -1.5, 0.05f);
}
}  // namespace

int main(int argc, char** argv)
{
	const std::string mapFile = argc > 1 ? argv[1] : "/usr/share/mrpt/datasets/2006-MalagaCampus.gridmap.gz";
	mrpt::maps::COccupancyGridMap2D grid;
	mrpt::poses::CPose2D truth;
	if (std::filesystem::exists(mapFile))
	{
		pmslam::loadGridMapGz(mapFile, grid);
		truth = mrpt::poses::CPose2D(63.5, 34.0, mrpt::DEG2RAD(30.0));	// a hall of the Malaga campus map
		std::printf("map %s\n", mapFile.c_str());
	}
	else
	{
		drawRoom(grid);
		truth = mrpt::poses::CPose2D(-1.0, 0.5, mrpt::DEG2RAD(30.0));
		std::printf("map synthetic room\n");
	}

	// The scan: 270°, 541 beams, 1 cm range noise, simulated in the map at the true pose.
	mrpt::obs::CObservation2DRangeScan obs;
	obs.aperture = static_cast<float>(mrpt::DEG2RAD(270.0));
	obs.maxRange = 30.0f;
	grid.laserScanSimulator(obs, truth, 0.5f, 541, 0.01f);
	mrpt::maps::CSimplePointsMap scan;
	scan.insertObservation(obs);  // robot-frame points (sensorPose applied)

	const mrpt::poses::CPose2D guess = truth + mrpt::poses::CPose2D(0.20, -0.15, mrpt::DEG2RAD(3.0));
	print("truth", truth);
	print("guess", guess);

	mrpt::slam::CICP icp;
	icp.options.maxIterations = 200;
	print("CICP", align(icp, grid, scan, guess));

	pmslam::PerfectMatchAligner pm;	 // the one-line swap
	print("PerfectMatchAligner", align(pm, grid, scan, guess));
	return 0;
}
