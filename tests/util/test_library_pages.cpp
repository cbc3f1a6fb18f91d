// Giving back the start-up library pages: the resident set shrinks, and the program (and the
// libraries whose pages went) keeps working and computing the same.
#include <gtest/gtest.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/util/LibraryPages.h>
#include <pmslam/util/RunStatistics.h>

#include <cmath>
#include <fstream>
#include <string>

namespace
{
double workload()
{
	// Code from MRPT's libraries and libstdc++, run before and after the pages go.
	mrpt::maps::COccupancyGridMap2D g(-5, 5, -5, 5, 0.05f);
	for (int i = 0; i < 200; ++i) g.setCell(i % 200, (i * 7) % 200, 0.1f);
	mrpt::poses::CPose2D p(1, 2, 0.3);
	for (int i = 0; i < 100; ++i) p = p + mrpt::poses::CPose2D(0.01, 0.0, 0.001);
	double s = p.x() + p.y() + p.phi();
	for (int i = 0; i < 200; ++i) s += g.getCell(i % 200, (i * 7) % 200);
	return s + std::to_string(s).size();
}
}  // namespace

TEST(LibraryPages, ResidentSetShrinksAndTheLibrariesKeepWorking)
{
	if (!std::ifstream("/proc/self/smaps")) GTEST_SKIP() << "/proc/self/smaps is not available here";
	const double before = workload();
	const double fileBefore = pmslam::residentMemoryNow().fileMB;
	const double released = pmslam::releaseStartupLibraryPages();
	const double fileAfter = pmslam::residentMemoryNow().fileMB;
	EXPECT_GT(released, 1.0) << "a test linked with MRPT maps megabytes of library files";
	EXPECT_LT(fileAfter, fileBefore - 0.5 * released);
	EXPECT_EQ(workload(), before);	// the same code, faulted back in from the page cache
	// A second call finds little left to give back (only what the workload touched again).
	EXPECT_LT(pmslam::releaseStartupLibraryPages(), released);
}
