/* pmslam — forwarding header for the old include path <pmslam/MapExport.h>.
 * Deprecated since 0.2: include <pmslam/io/MapExport.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/io/MapExport.h>
