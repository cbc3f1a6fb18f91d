/* pmslam — forwarding header for the old include path <pmslam/RawlogReader.h>.
 * Deprecated since 0.2: include <pmslam/io/RawlogReader.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/io/RawlogReader.h>
