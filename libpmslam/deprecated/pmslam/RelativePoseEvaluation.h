/* pmslam — forwarding header for the old include path <pmslam/RelativePoseEvaluation.h>.
 * Deprecated since 0.2: include <pmslam/eval/RelativePoseEvaluation.h>;
 * this forwarding header will be removed in the next release. */
#pragma once

#include <pmslam/eval/RelativePoseEvaluation.h>
