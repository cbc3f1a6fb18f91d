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

struct RelativePoseErrors
{
	std::size_t matched = 0;  // relations with a pose at both t1 and t2
	std::size_t missing = 0;  // relations whose t1 or t2 has no pose
	// Translational error (metres): mean, population std, mean of squares (m²), max.
	double transMean = 0, transStd = 0, transMeanSq = 0, transMax = 0;
	// Rotational error (degrees): mean, population std, mean of squares (deg²), max.
	double rotMeanDeg = 0, rotStdDeg = 0, rotMeanSqDeg2 = 0, rotMaxDeg = 0;
	// Per matched relation, in the order of the relations.
	std::vector<double> transErrors, rotErrorsDeg;
};

/** Score `trajectory` against `relations`. A relation's timestamp matches the
 * pose whose timestamp is nearest, if within `timeTolerance` seconds; otherwise
 * the relation counts as missing. The trajectory need not be sorted. All
 * statistics are 0 when nothing matched. O((n + m) log n). */
RelativePoseErrors evaluateRelativePoses(const Trajectory& trajectory, const std::vector<Relation>& relations,
										 double timeTolerance = 1e-6);

/** Write the trajectory as a Carmen log readable by the Freiburg metricEvaluator,
 * atomically: one line per pose,
 * `FLASER 0 x y theta x y theta timestamp pmslam timestamp`. */
void writeCarmenLog(const std::string& path, const Trajectory& trajectory);

}  // namespace pmslam
