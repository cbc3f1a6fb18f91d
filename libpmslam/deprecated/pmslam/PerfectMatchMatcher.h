/* pmslam — forwarding header for the old include path <pmslam/PerfectMatchMatcher.h>.
 * Deprecated since 0.2: include <pmslam/match/PerfectMatchMatcher.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/match/PerfectMatchMatcher.h>
