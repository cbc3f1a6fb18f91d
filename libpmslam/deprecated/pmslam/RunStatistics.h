/* pmslam — forwarding header for the old include path <pmslam/RunStatistics.h>.
 * Deprecated since 0.2: include <pmslam/util/RunStatistics.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/util/RunStatistics.h>
