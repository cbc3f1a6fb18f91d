/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * RelativePoseEvaluation: the relative-displacement metric of Kümmerle et al.,
 * "On measuring the accuracy of SLAM algorithms" (Autonomous Robots, 2009),
 * against the Freiburg ".relations" ground truth.
 *
 * For every relation (t1, t2, δ*): δ = pose(t1)⁻¹ ⊕ pose(t2) from the evaluated
 * trajectory, e = δ*⁻¹ ⊕ δ; translational error |(e.x, e.y)| in metres,
 * rotational error |wrap(e.yaw)| in degrees (wrap to (−180°, 180°], so 179° vs
 * −179° is 2°). Statistics over the matched relations: mean, population
 * standard deviation, mean of squares and maximum of the absolute errors.
 *
 * Timestamps: each of t1, t2 takes the trajectory pose with the nearest
 * timestamp, if it is within a tolerance (default 0.1 s, as Freiburg's
 * metricEvaluator); a relation with a stamp farther than that from every pose
 * is missing. Public relations files are not always written with the log's
 * six decimals (one with five matched 120 of its 1,172 relations to the
 * microsecond); how far the matched stamps were is reported with the errors.
 * Stamps equal to a pose's give the same numbers whatever the tolerance.
 */
#pragma once

#include <pmslam/io/Trajectory.h>

#include <cstddef>
#include <string>
#include <vector>

namespace pmslam
{
/** True pose of the robot at t2 expressed in its frame at t1 (metres, radians). */
struct Relation
{
	double t1, t2;
	double x, y, yaw;
};

/** Read a relations file: lines `t1 t2 x y z roll pitch yaw` (z, roll, pitch are
 * read and ignored), '#' and blank lines skipped. Throws std::runtime_error
 * "PATH: cannot open: ..." or "PATH:LINE: expected 't1 t2 x y z roll pitch yaw', got '...'". */
std::vector<Relation> loadRelations(const std::string& path);

/** How far (s) a relation's timestamp may be from the pose it is matched to, unless told otherwise. */
constexpr double kDefaultMaxTimeOffset = 0.1;
/** A stamp within this (s) of its pose's counts as exact: logs and trajectories are written to the microsecond. */
constexpr double kExactTimeOffset = 1e-6;

struct RelativePoseErrors
{
	std::size_t matched = 0;  // relations with a pose at both t1 and t2
	std::size_t missing = 0;  // relations whose t1 or t2 has no pose
	// |pose timestamp − relation timestamp| (s) over the 2·matched stamps of the matched relations: max, mean,
	// and how many of them are not exact (farther than kExactTimeOffset).
	double timeOffsetMax = 0, timeOffsetMean = 0;
	std::size_t inexactStamps = 0;
	// Translational error (metres): mean, population std, mean of squares (m²), max.
	double transMean = 0, transStd = 0, transMeanSq = 0, transMax = 0;
	// Rotational error (degrees): mean, population std, mean of squares (deg²), max.
	double rotMeanDeg = 0, rotStdDeg = 0, rotMeanSqDeg2 = 0, rotMaxDeg = 0;
	// Per matched relation, in the order of the relations: its index in `relations`, its errors.
	std::vector<std::size_t> matchedRelations;
	std::vector<double> transErrors, rotErrorsDeg;
};

/** Score `trajectory` against `relations`. A relation's timestamp matches the
 * pose whose timestamp is nearest, if within `maxTimeOffset` seconds; otherwise the relation counts as missing.
 * The trajectory need not be sorted. All statistics are 0 when nothing
 * matched. O((n + m) log n). */
RelativePoseErrors evaluateRelativePoses(const Trajectory& trajectory, const std::vector<Relation>& relations,
										 double maxTimeOffset = kDefaultMaxTimeOffset);

/** Write the trajectory as a Carmen log readable by the Freiburg metricEvaluator,
 * atomically: one line per pose,
 * `FLASER 0 x y theta x y theta timestamp pmslam timestamp`. */
void writeCarmenLog(const std::string& path, const Trajectory& trajectory);

}  // namespace pmslam
