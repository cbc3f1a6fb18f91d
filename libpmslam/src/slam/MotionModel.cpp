/* pmslam — odometry as a measurement (see MotionModel.h). */
#include <mrpt/system/datetime.h>
#include <mrpt/math/wrap2pi.h>
#include <pmslam/slam/MotionModel.h>

#include <algorithm>

namespace pmslam
{
namespace
{
// An odometry step between two scans longer than this, and than kMaxSpeed times the time between
// them, is a glitch (a reset, a corrupt reading), not motion.
constexpr double kMaxOdometryStep = 10.0;  // m
constexpr double kMaxSpeed = 3.0;  // m/s
// odometryToScanTime: two readings closer in time than this are a burst (no usable velocity),
// farther apart than kMaxOdometryGap a pause; a scan this far beyond the newest reading is
// extrapolated no further than kMaxOdometryGap.
constexpr double kMinOdometryGap = 0.01, kMaxOdometryGap = 0.5;  // s
// A lidar alone: the velocity is measured over the matches of the last kVelocityWindow s (long
// enough to average the matches' jitter, short enough to follow a turn), once they span at least
// kMinVelocitySpan s; it is extrapolated at most kMaxExtrapolation s past the last match.
// Two predictions closer than this are one (m, rad).
constexpr double kSameLinear = 0.02, kSameAngular = 0.5 * M_PI / 180;
bool same(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b) { return a.x == b.x && a.y == b.y && a.phi == b.phi; }
constexpr double kVelocityWindow = 0.5, kMinVelocitySpan = 0.1, kMaxExtrapolation = 10.0;  // s
}

void MotionModel::addReading(const mrpt::math::TPose2D& odometry, double timestamp)
{
	m_odometry = odometry;
	if (!std::isfinite(timestamp)) return;
	++m_timedReadings;
	if (m_timedOdometry[1] && timestamp - m_timedOdometry[1]->first < kMinOdometryGap) ++m_burstReadings;
	// A reading that does not advance in time (bursts, logs stepping back) is no velocity sample.
	if (m_timedOdometry[1] && timestamp <= m_timedOdometry[1]->first)
	{
		m_timedOdometry[0].reset();
		m_timedOdometry[1] = {timestamp, odometry};
		return;
	}
	m_timedOdometry[0] = m_timedOdometry[1];
	m_timedOdometry[1] = {{timestamp, odometry}};
}

void MotionModel::addIncrement(const mrpt::poses::CPose2D& change)
{
	const mrpt::poses::CPose2D base = m_odometry ? mrpt::poses::CPose2D(*m_odometry) : mrpt::poses::CPose2D();
	m_odometry = (base + change).asTPose();
	if (!m_odometryAtLastScan) m_odometryAtLastScan = base.asTPose();
}

std::optional<mrpt::math::TPose2D> MotionModel::odometryAtTime(double t) const
{
	if (!m_timedOdometry[0] || !m_timedOdometry[1] || !std::isfinite(t)) return std::nullopt;
	if (m_timedReadings < 10 || 20 * m_burstReadings > m_timedReadings) return std::nullopt;  // bursty stream
	const auto& [ta, pa] = *m_timedOdometry[0];
	const auto& [tb, pb] = *m_timedOdometry[1];
	const double gap = tb - ta;
	if (gap < kMinOdometryGap || gap > kMaxOdometryGap) return std::nullopt;
	// Constant velocity over the last interval, from the newer reading, at most kMaxOdometryGap
	// ahead (and never before the older reading).
	const double f = std::clamp((t - tb) / gap, -1.0, kMaxOdometryGap / gap);
	const mrpt::poses::CPose2D d = mrpt::poses::CPose2D(pb) - mrpt::poses::CPose2D(pa);
	const mrpt::poses::CPose2D step(f * d.x(), f * d.y(), f * d.phi());
	return (mrpt::poses::CPose2D(pb) + step).asTPose();
}

MotionPrediction MotionModel::predict(const mrpt::Clock::time_point& stamp,
									  const std::optional<mrpt::math::TPose2D>& odometryAtScan,
									  const mrpt::math::TPose2D& estimate)
{
	MotionPrediction m;
	m.odometry = odometryAtScan ? odometryAtScan : m_odometry;
	// A scan's own odometry that is just the latest reading copied carries no timing of its own.
	// The reported trajectory's smoother gets it moved to the scan's time; the prediction keeps
	// the reading as it is: moving the predictions too changed which revisits snap back onto the
	// map (aces: loops missed in 4 of 15 perturbed runs instead of 3) for no gain of the median.
	m.odometryAtScanTime = m.odometry;
	const bool copied = !odometryAtScan || (m_odometry && odometryAtScan->x == m_odometry->x &&
											odometryAtScan->y == m_odometry->y && odometryAtScan->phi == m_odometry->phi);
	if (m_options.odometryToScanTime && copied && stamp != INVALID_TIMESTAMP)
		if (const auto o = odometryAtTime(mrpt::Clock::toDouble(stamp) - m_options.scanLatency))
			m.odometryAtScanTime = o;
	m.pose = m.previous = estimate;
	m.time = stamp != INVALID_TIMESTAMP ? mrpt::Clock::toDouble(stamp) : std::nan("");
	m.sincePrevious = m.time - m_lastScanTime;	// NaN when unknown
	if (m.odometry && m_odometryAtLastScan)
	{
		const mrpt::poses::CPose2D delta = mrpt::poses::CPose2D(*m.odometry) - mrpt::poses::CPose2D(*m_odometryAtLastScan);
		m.step = std::hypot(delta.x(), delta.y());
		m.turn = delta.phi();
		// No robot moves 10 m between two scans, nor faster than kMaxSpeed across a logging gap:
		// such a jump is an odometry glitch, and following it would throw the robot (and the grid) away.
		const double plausible =
			std::max(kMaxOdometryStep, std::isfinite(m.sincePrevious) ? kMaxSpeed * m.sincePrevious : 0.0);
		if (m.step < plausible)
			m.pose = (mrpt::poses::CPose2D(estimate) + delta).asTPose();
		else
			m.glitch = true;
	}
	if (!m.odometry && std::isfinite(m.sincePrevious))
		if (const auto p = extrapolate(estimate, m.sincePrevious))
		{
			m.pose = *p;
			m.extrapolated = true;
		}
	if (m.odometry)
		if (const auto alt = sinceStoodStill(*m.odometry, estimate, m.pose); alt && !m.glitch) m.alternative = alt;
	if (m.odometry) m_odometryAtLastScan = m.odometry;
	// Where the prediction cannot be trusted, the match searches a wider window: after a time gap
	// or an odometry jump. No odometry at all (a lidar alone, live): across a gap the robot went
	// anywhere it could drive in that time (a sensor unplugged and back, scans lost), so the
	// prediction is stale.
	m.gap = m.sincePrevious > m_options.relocalizeAfterGap;
	m.jump = m.step > m_options.relocalizeAfterJump;
	m.stale = m.gap && !m.odometry && std::isfinite(m.sincePrevious);
	m.travelled = m.step;
	m.turned = std::abs(m.turn);
	if (m.gap && m.odometry && !m.glitch && m_drivingTime > 0)
	{
		m.travelled = std::max(m.travelled, m_path / m_drivingTime * m.sincePrevious);
		m.turned = std::max(m.turned, m_turning / m_drivingTime * m.sincePrevious);
	}
	else if (m.odometry && !m.glitch && std::isfinite(m.sincePrevious) && m.sincePrevious > 0)
	{
		m_path += m.step;
		m_turning += std::abs(m.turn);
		m_drivingTime += m.sincePrevious;
	}
	if (std::isfinite(m.time)) m_lastScanTime = m.time;
	return m;
}

void MotionModel::matched(const mrpt::math::TPose2D& pose, double time)
{
	if (!std::isfinite(time)) return;
	if (!m_matches.empty() && time <= m_matches.back().first) m_matches.clear();	// a log stepping back
	m_matches.emplace_back(time, pose);
	while (m_matches.size() > 2 && time - m_matches[1].first >= kVelocityWindow) m_matches.pop_front();
}

void MotionModel::correct(const mrpt::poses::CPose2D& T)
{
	for (auto& [t, p] : m_matches) p = (T + mrpt::poses::CPose2D(p)).asTPose();
	if (m_anchor) m_anchor->first = (T + mrpt::poses::CPose2D(m_anchor->first)).asTPose();
}

std::optional<mrpt::math::TPose2D> MotionModel::sinceStoodStill(const mrpt::math::TPose2D& odometry,
																const mrpt::math::TPose2D& estimate,
																const mrpt::math::TPose2D& predicted)
{
	if (m_anchorPending) m_anchor.emplace(estimate, *m_anchorPending);  // the estimate of the scan it was first seen at
	m_anchorPending.reset();
	const bool fresh = !m_odometryAtLastScan || !same(odometry, *m_odometryAtLastScan);
	if (!fresh) return std::nullopt;
	m_anchorPending = odometry;
	// Only after a reading that stood still (the previous scan's is the anchor's) while the estimate moved.
	if (!m_anchor || !same(m_anchor->second, *m_odometryAtLastScan)) return std::nullopt;
	const mrpt::poses::CPose2D delta = mrpt::poses::CPose2D(odometry) - mrpt::poses::CPose2D(m_anchor->second);
	const mrpt::math::TPose2D alt = (mrpt::poses::CPose2D(m_anchor->first) + delta).asTPose();
	const bool differs = std::hypot(alt.x - predicted.x, alt.y - predicted.y) > kSameLinear ||
						 std::abs(mrpt::math::wrapToPi(alt.phi - predicted.phi)) > kSameAngular;
	return differs ? std::optional<mrpt::math::TPose2D>(alt) : std::nullopt;
}

std::optional<mrpt::math::TPose2D> MotionModel::velocity() const
{
	if (m_matches.size() < 2) return std::nullopt;
	const auto& [ta, pa] = m_matches.front();
	const auto& [tb, pb] = m_matches.back();
	// Matches far apart (a gap between them) say nothing of the velocity at either.
	if (tb - ta < kMinVelocitySpan || tb - ta > 2 * kVelocityWindow) return std::nullopt;
	const mrpt::poses::CPose2D d = mrpt::poses::CPose2D(pb) - mrpt::poses::CPose2D(pa);
	return mrpt::math::TPose2D(d.x() / (tb - ta), d.y() / (tb - ta), d.phi() / (tb - ta));
}

std::optional<mrpt::math::TPose2D> MotionModel::extrapolate(const mrpt::math::TPose2D& estimate, double dt) const
{
	const auto v = velocity();
	if (!v || !(dt > 0)) return std::nullopt;
	const double sinceMatch = m_lastScanTime - m_matches.back().first;	// at the previous scan
	const double t = std::clamp(kMaxExtrapolation - sinceMatch, 0.0, dt);
	if (t <= 0) return std::nullopt;
	const mrpt::poses::CPose2D step(v->x * t, v->y * t, v->phi * t);
	return (mrpt::poses::CPose2D(estimate) + step).asTPose();
}

}  // namespace pmslam
