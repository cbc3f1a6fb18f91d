/* pmslam — writing a built map in the formats people open.
 *
 * Every writer is atomic (temporary file + rename): an interrupted run never
 * leaves a half-written map behind, and the previous file survives a failure.
 * Every writer streams: images row by row, the gridmap cell row by cell row, so
 * writing a map costs a row of memory, not a second copy of the map. pmslam's live
 * map (OccupancyDistanceGridMap) is read from its sparse cells; any other
 * COccupancyGridMap2D from its dense array.
 *
 * Frames and units: everything is in the grid's own (map) frame, metres and
 * radians; trajectories are robot base poses in that frame. Images show one
 * pixel per cell, x to the right and y up (north at the top); the ROS YAML's
 * `origin` is the map-frame position (m) of the image's lower-left corner.
 */
#pragma once

#include <mrpt/img/CImage.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <pmslam/io/Trajectory.h>

#include <mrpt/math/TPoint2D.h>

#include <string>
#include <utility>
#include <vector>

namespace pmslam
{
/** ROS map_server pair: an 8-bit PGM (white free, black occupied, 205 unknown)
 * cropped to the mapped area, and its YAML (resolution, origin, thresholds). */
void saveMapPgmYaml(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& pgmPath,
					const std::string& yamlPath);

/** The mapped area as an RGB image (grey occupancy, trajectory in red, and optionally the current scan's
 * endpoints in the map frame in green), for display or saving. With maxSide > 0 a larger area is shrunk by a
 * whole factor until neither side exceeds it: each pixel shows the darkest cell of its block (walls stay
 * visible), or a drawn colour if the block has one. */
mrpt::img::CImage renderMap(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& path,
							const std::vector<mrpt::math::TPoint2D>& scanInMap = {},
							const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links = {},
							int maxSide = 0);

/** A PNG picture of the mapped area with the trajectory drawn over it (and loop closures, in blue). */
void saveMapPng(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& path, const std::string& pngPath,
				const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links = {});

/** MRPT's own formats, gz-compressed: a serialised COccupancyGridMap2D
 * (opens in RawLogViewer / grid-matching) and a CSimpleMap of keyframes. */
void saveGridMapGz(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path);
void saveSimpleMapGz(const mrpt::maps::CSimpleMap& map, const std::string& path);

/** Loads a map written by saveGridMapGz (or any serialised COccupancyGridMap2D .gridmap[.gz]). */
void loadGridMapGz(const std::string& path, mrpt::maps::COccupancyGridMap2D& grid);

}  // namespace pmslam
