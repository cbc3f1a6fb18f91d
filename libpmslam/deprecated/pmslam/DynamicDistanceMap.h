/* pmslam — forwarding header for the old include path <pmslam/DynamicDistanceMap.h>.
 * Deprecated since 0.2: include <pmslam/map/DynamicDistanceMap.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/map/DynamicDistanceMap.h>
