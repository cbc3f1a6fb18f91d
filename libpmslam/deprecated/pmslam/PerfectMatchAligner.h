/* pmslam — forwarding header for the old include path <pmslam/PerfectMatchAligner.h>.
 * Deprecated since 0.2: include <pmslam/match/PerfectMatchAligner.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/match/PerfectMatchAligner.h>
