/* pmslam — matched poses fused with odometry increments (see OdometrySmoother.h). */
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/OdometrySmoother.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pmslam
{
namespace
{
using mrpt::poses::CPose2D;

// Along/across-track variances as a world-frame covariance for heading phi.
Eigen::Matrix2d alongCross(const Eigen::Vector2d& v, double phi)
{
	const double c = std::cos(phi), s = std::sin(phi);
	Eigen::Matrix2d Rot;
	Rot << c, -s, s, c;
	return Rot * v.asDiagonal() * Rot.transpose();
}

constexpr double kMinVariance = 1e-10;	// m²: keeps S invertible when a noise level learns to 0
constexpr double kMinMotion = 0.02;	 // m per scan of span: slower spans say little about the track
}  // namespace

OdometrySmoother::OdometrySmoother(const OdometrySmootherOptions& o) : m_opts(o)
{
	if (m_opts.varianceLag < 2) throw std::invalid_argument("OdometrySmoother: varianceLag must be >= 2");
}

bool OdometrySmoother::warmedUp() const { return m_n1 >= m_opts.warmup && m_nK >= m_opts.warmup; }

Eigen::Vector2d OdometrySmoother::odometrySigma() const
{
	if (!warmedUp()) return Eigen::Vector2d::Zero();
	const Eigen::Vector2d v1 = m_sum1 / double(m_n1), vK = m_sumK / double(m_nK);
	return ((vK - v1) / double(m_opts.varianceLag - 1)).cwiseMax(0.0).cwiseSqrt();
}

Eigen::Vector2d OdometrySmoother::matchSigma() const
{
	if (!warmedUp()) return Eigen::Vector2d::Zero();
	const Eigen::Vector2d q = odometrySigma().cwiseAbs2();
	return ((m_sum1 / double(m_n1) - q) / 2.0).cwiseMax(0.0).cwiseSqrt();
}

void OdometrySmoother::updateStatistics()
{
	// Discrepancy of the matched increment from the odometry increment over the last `span` scans,
	// in the robot frame at the start of the span (x along the track).
	auto accumulate = [&](std::size_t span, Eigen::Vector2d& sum, std::size_t& n) {
		if (m_history.size() <= span) return;
		const auto& [ma, oa] = m_history[m_history.size() - 1 - span];
		const auto& [mb, ob] = m_history.back();
		const CPose2D dOdo = CPose2D(ob) - CPose2D(oa);
		if (std::hypot(dOdo.x(), dOdo.y()) < kMinMotion * double(span)) return;
		const CPose2D e = (CPose2D(mb) - CPose2D(ma)) - dOdo;
		sum += Eigen::Vector2d(e.x() * e.x(), e.y() * e.y());
		++n;
	};
	accumulate(1, m_sum1, m_n1);
	accumulate(m_opts.varianceLag, m_sumK, m_nK);
}

void OdometrySmoother::add(std::size_t index, const mrpt::math::TPose2D& matched,
						   const std::optional<mrpt::math::TPose2D>& odometry)
{
	if (odometry)
	{
		m_history.emplace_back(matched, *odometry);
		while (m_history.size() > m_opts.varianceLag + 1) m_history.pop_front();
		updateStatistics();
	}
	else
		m_history.clear();	// a gap in the odometry: spans must not cross it

	Entry e;
	e.index = index;
	e.matched = matched;
	e.odometry = odometry;
	const Eigen::Vector2d z(matched.x, matched.y);
	const Eigen::Vector2d r = matchSigma().cwiseAbs2().cwiseMax(kMinVariance);
	const Eigen::Matrix2d R = alongCross(r, matched.phi);
	e.x = z;
	e.P = R;
	if (!m_window.empty() && odometry && m_window.back().odometry && warmedUp())
	{
		const Entry& prev = m_window.back();
		const CPose2D u = CPose2D(*odometry) - CPose2D(*prev.odometry);
		const double c = std::cos(prev.matched.phi), s = std::sin(prev.matched.phi);
		e.pred = prev.x + Eigen::Vector2d(c * u.x() - s * u.y(), s * u.x() + c * u.y());
		e.Ppred = prev.P;
		// Odometry noise accrues only while the robot moves.
		if (std::hypot(u.x(), u.y()) > 1e-4 || std::abs(u.phi()) > 1e-4)
			e.Ppred += alongCross(odometrySigma().cwiseAbs2(), matched.phi);
		const Eigen::Matrix2d S = e.Ppred + R;
		const Eigen::Matrix2d Sinv = S.inverse();
		const Eigen::Vector2d nu = z - e.pred;
		if (Sinv.allFinite() && nu.dot(Sinv * nu) <= m_opts.gate * m_opts.gate)
		{
			const Eigen::Matrix2d K = e.Ppred * Sinv;
			e.x = e.pred + K * nu;
			e.P = (Eigen::Matrix2d::Identity() - K) * e.Ppred;
			e.restart = false;
		}
	}
	m_window.push_back(e);
	if (m_window.size() > m_opts.lag) emitOldest();
}

Eigen::Vector2d OdometrySmoother::smoothedPosition(std::size_t i) const
{
	Eigen::Vector2d xs = m_window.back().x;
	for (std::size_t j = m_window.size() - 1; j-- > i;)
	{
		const Entry& next = m_window[j + 1];
		if (next.restart)
		{
			xs = m_window[j].x;	 // nothing links j to what follows
			continue;
		}
		const Eigen::Matrix2d C = m_window[j].P * next.Ppred.inverse();
		xs = m_window[j].x + C * (xs - next.pred);
	}
	return xs;
}

void OdometrySmoother::emitOldest()
{
	const Eigen::Vector2d xs = smoothedPosition(0);
	const Entry& e = m_window.front();
	m_final.emplace_back(e.index, mrpt::math::TPose2D(xs.x(), xs.y(), e.matched.phi));
	m_window.pop_front();
}

void OdometrySmoother::finish()
{
	while (!m_window.empty()) emitOldest();
}

std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> OdometrySmoother::takeFinal()
{
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> out;
	out.swap(m_final);
	return out;
}

}  // namespace pmslam
