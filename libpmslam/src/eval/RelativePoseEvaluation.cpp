/* pmslam — relative pose error metric of Kümmerle et al. 2009 (see RelativePoseEvaluation.h). */
#include <pmslam/io/AtomicFile.h>
#include <pmslam/eval/RelativePoseEvaluation.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include "../io/TextParsing.h"

namespace pmslam
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

struct Pose
{
	double x, y, yaw;
};

double wrapPi(double a)
{
	a = std::remainder(a, 2 * kPi);  // [−π, π]
	return a <= -kPi ? a + 2 * kPi : a;
}

/** a⁻¹ ⊕ b: pose b expressed in the frame of pose a. */
Pose inverseCompose(const Pose& a, const Pose& b)
{
	const double c = std::cos(a.yaw), s = std::sin(a.yaw);
	const double dx = b.x - a.x, dy = b.y - a.y;
	return Pose{c * dx + s * dy, -s * dx + c * dy, wrapPi(b.yaw - a.yaw)};
}

/** Indices of the poses sorted by timestamp, for O(log n) lookup. */
class TimeIndex
{
   public:
	explicit TimeIndex(const Trajectory& t) : m_traj(t), m_order(t.size())
	{
		std::iota(m_order.begin(), m_order.end(), std::size_t(0));
		std::stable_sort(m_order.begin(), m_order.end(),
						 [&](std::size_t a, std::size_t b) { return t[a].timestamp < t[b].timestamp; });
	}
	/** The pose nearest to `time` within `tol`, or nullptr. */
	const TimedPose2D* find(double time, double tol) const
	{
		auto it = std::lower_bound(m_order.begin(), m_order.end(), time,
								   [&](std::size_t i, double v) { return m_traj[i].timestamp < v; });
		const TimedPose2D* best = nullptr;
		double bestDiff = 0;
		auto consider = [&](std::size_t i) {
			const double d = std::abs(m_traj[i].timestamp - time);
			if (d <= tol && (!best || d < bestDiff)) best = &m_traj[i], bestDiff = d;
		};
		if (it != m_order.end()) consider(*it);	 // first pose at or after `time` (first in file order on ties)
		if (it != m_order.begin()) consider(*std::prev(it));
		return best;
	}

   private:
	const Trajectory& m_traj;
	std::vector<std::size_t> m_order;
};

/** Max, mean and inexact count of the time offsets of the matched stamps. */
void offsetStatistics(const std::vector<double>& offsets, RelativePoseErrors& r)
{
	for (double d : offsets)
	{
		r.timeOffsetMax = std::max(r.timeOffsetMax, d);
		r.timeOffsetMean += d;
		if (d > kExactTimeOffset) ++r.inexactStamps;
	}
	if (!offsets.empty()) r.timeOffsetMean /= static_cast<double>(offsets.size());
}

void statistics(const std::vector<double>& v, double& mean, double& stdev, double& meanSq, double& maxV)
{
	mean = stdev = meanSq = maxV = 0;
	if (v.empty()) return;
	const double n = static_cast<double>(v.size());
	for (double e : v)
	{
		mean += e;
		meanSq += e * e;
		maxV = std::max(maxV, e);
	}
	mean /= n;
	meanSq /= n;
	double var = 0;
	for (double e : v) var += (e - mean) * (e - mean);
	stdev = std::sqrt(var / n);
}
}  // namespace

std::vector<Relation> loadRelations(const std::string& path)
{
	std::ifstream in(path);
	if (!in)
	{
		const int err = errno;
		throw std::runtime_error(path + ": cannot open: " + std::strerror(err));
	}
	std::vector<Relation> out;
	std::string line;
	std::size_t lineNo = 0;
	while (std::getline(in, line))
	{
		++lineNo;
		if (detail::isCommentOrBlank(line)) continue;
		double v[8];
		if (!detail::parseNumbers(line, v, 8))
			throw std::runtime_error(path + ":" + std::to_string(lineNo) +
									 ": expected 't1 t2 x y z roll pitch yaw', got " + detail::quoteForError(line));
		out.push_back(Relation{v[0], v[1], v[2], v[3], v[7]});
	}
	if (in.bad()) throw std::runtime_error(path + ": read error");
	return out;
}

RelativePoseErrors evaluateRelativePoses(const Trajectory& trajectory, const std::vector<Relation>& relations,
										 double maxTimeOffset)
{
	RelativePoseErrors r;
	const TimeIndex index(trajectory);
	r.transErrors.reserve(relations.size());
	r.rotErrorsDeg.reserve(relations.size());
	std::vector<double> offsets;
	for (std::size_t i = 0; i < relations.size(); ++i)
	{
		const Relation& rel = relations[i];
		const TimedPose2D* p1 = index.find(rel.t1, maxTimeOffset);
		const TimedPose2D* p2 = index.find(rel.t2, maxTimeOffset);
		if (!p1 || !p2)
		{
			++r.missing;
			continue;
		}
		offsets.push_back(std::abs(p1->timestamp - rel.t1));
		offsets.push_back(std::abs(p2->timestamp - rel.t2));
		r.matchedRelations.push_back(i);
		const Pose delta = inverseCompose(Pose{p1->x, p1->y, p1->yaw}, Pose{p2->x, p2->y, p2->yaw});
		const Pose e = inverseCompose(Pose{rel.x, rel.y, rel.yaw}, delta);
		r.transErrors.push_back(std::hypot(e.x, e.y));
		r.rotErrorsDeg.push_back(std::abs(e.yaw) * (180.0 / kPi));
		++r.matched;
	}
	statistics(r.transErrors, r.transMean, r.transStd, r.transMeanSq, r.transMax);
	statistics(r.rotErrorsDeg, r.rotMeanDeg, r.rotStdDeg, r.rotMeanSqDeg2, r.rotMaxDeg);
	offsetStatistics(offsets, r);
	return r;
}

void writeCarmenLog(const std::string& path, const Trajectory& trajectory)
{
	writeFileAtomically(path, [&](std::ostream& os) {
		char buf[256];
		for (const TimedPose2D& p : trajectory)
		{
			const int n = std::snprintf(buf, sizeof(buf), "FLASER 0 %.6f %.6f %.8f %.6f %.6f %.8f %.6f pmslam %.6f\n",
										p.x, p.y, p.yaw, p.x, p.y, p.yaw, p.timestamp, p.timestamp);
			os.write(buf, n);
		}
	});
}

}  // namespace pmslam
