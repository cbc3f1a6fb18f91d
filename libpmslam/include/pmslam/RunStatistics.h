/* pmslam — small statistics the programs report about a run. */
#pragma once

#include <vector>

namespace pmslam
{
/** The q-quantile (0..1, nearest rank) of `values`; 0 for none. */
double percentile(std::vector<double> values, double q);

/** Peak resident memory of this process so far, in MiB. */
double peakResidentMemoryMB();

}  // namespace pmslam
