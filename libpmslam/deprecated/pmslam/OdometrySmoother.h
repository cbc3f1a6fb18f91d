/* pmslam — forwarding header for the old include path <pmslam/OdometrySmoother.h>.
 * Deprecated since 0.2: include <pmslam/slam/OdometrySmoother.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/slam/OdometrySmoother.h>
