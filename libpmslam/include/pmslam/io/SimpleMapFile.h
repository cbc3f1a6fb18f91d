/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * An MRPT simple map file (.simplemap, plain or gzip: a CSimpleMap of keyframes, each a pose and its
 * observations), read in one place for its three users: a localisation map (PriorMap), the keyframes of a
 * session (Session) and a simple map replayed as a log (SimpleMapLogReader). Each user wraps the error into its
 * own, so a damaged file reads the same everywhere: "PATH: not an MRPT simple map (why)".
 */
#pragma once

#include <mrpt/maps/CSimpleMap.h>

#include <stdexcept>
#include <string>

namespace pmslam
{
/** A simple map file that cannot be read; what() is one line naming the file. */
class SimpleMapFileError : public std::runtime_error
{
   public:
	using std::runtime_error::runtime_error;
};

/** True when the name says a simple map: ".simplemap" or ".simplemap.gz", any case. */
bool isSimpleMapName(const std::string& path);

/** The keyframes of `path`; throws SimpleMapFileError when it cannot be opened, is not a simple map, or holds
 * no keyframe. */
mrpt::maps::CSimpleMap readSimpleMapFile(const std::string& path);
}  // namespace pmslam
