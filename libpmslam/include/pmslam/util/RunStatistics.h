/* pmslam — small statistics the programs report about a run. */
#pragma once

#include <vector>

namespace pmslam
{
/** The q-quantile (0..1, nearest rank) of `values`; 0 for none. */
double percentile(std::vector<double> values, double q);

/** Peak resident memory of this process so far, in MiB. */
double peakResidentMemoryMB();

/** Resident memory now, in MiB, split into the process's own (anonymous: heap, stacks,
 * relocated library data) and file-backed pages (mostly shared-library code, shared with
 * every other process that maps it). Zeros where /proc is not available. */
struct ResidentMemory
{
	double anonymousMB = 0, fileMB = 0;
};
ResidentMemory residentMemoryNow();

}  // namespace pmslam
