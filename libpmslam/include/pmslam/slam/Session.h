/* pmslam — a session: what a mapping run leaves in its output folder so that a later run can continue
 * its map (pm-slam-app --continue DIR).
 *
 * The folder holds, besides what any run writes:
 *   - session.ini: the format number, the map's resolution, and the parts (one per run that mapped
 *     into this map: its log and how many scans it had), oldest first (docs/formats.md);
 *   - trajectory.txt: every scan of every part in the one map frame, the parts' lines in order;
 *   - map.simplemap.gz: the keyframes of every part with their scans (MRPT's CSimpleMap), the map a
 *     continuing run re-inserts;
 *   - map.gridmap.gz: the map as a grid, on which a continuing run searches where it starts;
 *   - graph.graph (with loop closure): the pose graph over those keyframes, every part's.
 * A folder written before session.ini existed is read as one part (its log unknown).
 */
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <pmslam/graph/PoseGraph.h>
#include <pmslam/io/Trajectory.h>

#include <optional>

#include <stdexcept>
#include <string>
#include <vector>

namespace pmslam
{
class SessionError : public std::runtime_error
{
   public:
	using std::runtime_error::runtime_error;
};

struct SessionPart
{
	std::string log;  ///< the log the part was mapped from, as given on its command line
	std::size_t scans = 0;	///< its lines in trajectory.txt
	std::size_t keyframes = 0;	///< its keyframes in map.simplemap.gz (the next ones after the earlier parts')
};

struct Session
{
	static constexpr int kFormat = 1;  ///< the session.ini format this pmslam writes and reads
	std::string folder;
	double resolution = 0.05;  ///< m, of the map
	std::vector<SessionPart> parts;	 ///< oldest first
	Trajectory trajectory;	///< every scan of every part
	mrpt::maps::CSimpleMap keyframes;
	mrpt::maps::COccupancyGridMap2D grid;
	/** graph.graph, when it covers exactly the keyframes (a run with loop closure): its edges are the
	 * constraints the continuing run keeps between them. */
	std::optional<PoseGraph> graph;
};

/** Reads the session in `folder`. Throws SessionError, one line naming the file and what was expected:
 * not a folder, a file missing or unreadable, a format newer than kFormat, parts that do not add up to
 * trajectory.txt. */
Session loadSession(const std::string& folder);

/** Writes `folder`/session.ini (atomically). */
void saveSessionIndex(const std::string& folder, double resolution, const std::vector<SessionPart>& parts);

/** The comment line of trajectory.txt that says which lines are which part. */
std::string sessionPartsComment(const std::vector<SessionPart>& parts);

}  // namespace pmslam
