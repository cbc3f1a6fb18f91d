/* pmslam — forwarding header for the old include path <pmslam/KeyframeStore.h>.
 * Deprecated since 0.2: include <pmslam/slam/KeyframeStore.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/slam/KeyframeStore.h>
