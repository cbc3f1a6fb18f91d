/* pmslam — the fixed map of a localisation run, from what users have.
 *
 * `--localize MAP` takes any of:
 *   - a ROS map_server map, `map.yaml` with its image (MRPT's own reader: resolution, origin, negate,
 *     occupied_thresh and free_thresh honoured), as pm-slam-app writes and ROS users keep;
 *   - an MRPT grid, `.gridmap` or `.gridmap.gz` (a serialised COccupancyGridMap2D);
 *   - an MRPT simple map, `.simplemap` or `.simplemap.gz` (keyframes and their scans: MRPT's own
 *     localisation demo ships its map as one), rendered into a grid at `simplemapResolution`;
 *   - a pm-slam-app output folder (its map.gridmap.gz, else its map.yaml).
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <stdexcept>
#include <string>

namespace pmslam
{
class PriorMapError : public std::runtime_error
{
   public:
	using std::runtime_error::runtime_error;
};

struct PriorMap
{
	mrpt::maps::COccupancyGridMap2D grid;
	std::string source;	 ///< the file read (inside a folder: the file chosen)
	std::string kind;  ///< "ROS map_server map", "MRPT grid", "MRPT simple map"
};

/** Throws PriorMapError (one line naming the path and what was expected). */
PriorMap loadPriorMap(const std::string& path, double simplemapResolution = 0.05);

}  // namespace pmslam
