/* pmslam — forwarding header for the old include path <pmslam/CMetricMapBuilderPM.h>.
 * Deprecated since 0.2: include <pmslam/slam/CMetricMapBuilderPM.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/slam/CMetricMapBuilderPM.h>
