/* pmslam — the keyframe gate (see KeyframeGate.h). */
#include <mrpt/math/wrap2pi.h>
#include <pmslam/slam/KeyframeGate.h>

#include <cmath>

namespace pmslam
{
bool KeyframeGate::moved(const mrpt::math::TPose2D& predicted) const
{
	const double lin = std::hypot(predicted.x - m_lastInsertPose.x, predicted.y - m_lastInsertPose.y);
	const double ang = std::abs(mrpt::math::wrapToPi(predicted.phi - m_lastInsertPose.phi));
	return lin >= m_options.matchLinDistance || ang >= m_options.matchAngDistance;
}

bool KeyframeGate::admits(const mrpt::math::TPose2D& pose, double inlierFraction)
{
	if (!(m_options.mapInsertLinDistance > 0)) return true;
	// Keyframe-like insertion: a scan the map already explains is matched but not inserted,
	// so the map is not redrawn (and blurred) at every slightly drifted pose.
	const double ml = std::hypot(pose.x - m_lastMapPose.x, pose.y - m_lastMapPose.y);
	const double ma = std::abs(mrpt::math::wrapToPi(pose.phi - m_lastMapPose.phi));
	if (ml < m_options.mapInsertLinDistance && ma < m_options.mapInsertAngDistance &&
		inlierFraction >= m_options.mapInsertBelowInliers)
	{
		m_lastInsertPose = pose;  // the next match is gated from here
		return false;
	}
	return true;
}

void KeyframeGate::inserted(const mrpt::math::TPose2D& pose)
{
	m_lastInsertPose = pose;
	m_lastMapPose = pose;
}

void KeyframeGate::correct(const mrpt::poses::CPose2D& correction)
{
	const auto move = [&](mrpt::math::TPose2D& p) { p = (correction + mrpt::poses::CPose2D(p)).asTPose(); };
	move(m_lastInsertPose);
	move(m_lastMapPose);
}

}  // namespace pmslam
