/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * Trajectory: the time-stamped 2D poses a SLAM run produces (one per laser
 * scan, stamped with the scan's ipc_timestamp), and their text file format:
 *
 *   # comment lines (any number, anywhere) and blank lines are ignored
 *   timestamp x y yaw
 *
 * timestamp in seconds (written with 6 decimals: exact for epoch times such as
 * 976052857.123456), x y in metres (6 decimals), yaw in radians (8 decimals).
 */
#pragma once

#include <string>
#include <vector>

namespace pmslam
{
struct TimedPose2D
{
	double timestamp;  // seconds
	double x, y;	   // metres
	double yaw;		   // radians
};

using Trajectory = std::vector<TimedPose2D>;

/** Write atomically (see AtomicFile.h). `headerComment` may span several lines;
 * each is written prefixed with "# ". Throws std::invalid_argument for a
 * non-finite value and std::runtime_error on an I/O failure. */
void saveTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& headerComment = "");

/** Read a file written by saveTrajectory() (or any file of that format, in file
 * order). Throws std::runtime_error "PATH: cannot open: ..." or
 * "PATH:LINE: expected 'timestamp x y yaw', got '...'" on a malformed line. */
Trajectory loadTrajectory(const std::string& path);

}  // namespace pmslam
