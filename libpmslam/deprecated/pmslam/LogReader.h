/* pmslam — forwarding header for the old include path <pmslam/LogReader.h>.
 * Deprecated since 0.2: include <pmslam/io/LogReader.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/io/LogReader.h>
