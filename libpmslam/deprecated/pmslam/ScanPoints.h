/* pmslam — forwarding header for the old include path <pmslam/ScanPoints.h>.
 * Deprecated since 0.2: include <pmslam/sensor/ScanPoints.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/sensor/ScanPoints.h>
