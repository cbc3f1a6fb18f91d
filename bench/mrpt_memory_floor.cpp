// The least memory a program built on MRPT 2.5 can peak at: it creates an empty occupancy grid
// (mrpt-maps) and, when built as mrpt-memory-floor-slam, also an ICP aligner (mrpt-slam). Loading
// MRPT maps the shared libraries it depends on (OpenCV, GDAL, ffmpeg, ...), and the dynamic linker
// touches their relocation and symbol tables before main(): bench/run.sh reports the peak RSS of
// both next to pm-slam-app's.
#include <mrpt/maps/COccupancyGridMap2D.h>
#ifdef PMSLAM_FLOOR_WITH_SLAM
#include <mrpt/slam/CICP.h>
#endif

#include <cstdio>

int main()
{
	mrpt::maps::COccupancyGridMap2D grid(-1.0f, 1.0f, -1.0f, 1.0f, 0.05f);
	unsigned used = grid.getSizeX();
#ifdef PMSLAM_FLOOR_WITH_SLAM
	mrpt::slam::CICP icp;
	used += icp.options.maxIterations;
#endif
	std::printf("%u\n", used);	// keeps both objects alive and used
	return 0;
}
