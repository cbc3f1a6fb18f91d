/* pmslam — a robot that odometry says stands still (see StandstillCheck.h). */
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <pmslam/slam/StandstillCheck.h>

#include <cmath>

namespace pmslam
{
bool StandstillCheck::stillThere(const mrpt::math::TPose2D& matched, const mrpt::math::TPose2D& predicted)
{
	return std::hypot(matched.x - predicted.x, matched.y - predicted.y) < 0.05 &&
		   std::abs(mrpt::math::wrapToPi(matched.phi - predicted.phi)) < mrpt::DEG2RAD(1.0);
}

void StandstillCheck::keep(const mrpt::obs::CObservation2DRangeScan& scan)
{
	const std::size_t n = scan.getScanSize();
	m_referenceRanges.resize(n);
	for (std::size_t i = 0; i < n; ++i) m_referenceRanges[i] = scan.getScanRangeValidity(i) ? scan.getScanRange(i) : 0.0f;
}

double StandstillCheck::changedFraction(const mrpt::obs::CObservation2DRangeScan& scan) const
{
	// Beams valid in both scans whose range moved by more than 0.1 m.
	const std::size_t n = scan.getScanSize();
	std::size_t both = 0, moved = 0;
	if (m_referenceRanges.size() != n) return 1.0;	// another sensor, or none yet: unknown, so check
	for (std::size_t i = 0; i < n; ++i)
		if (scan.getScanRangeValidity(i) && m_referenceRanges[i] > 0)
		{
			++both;
			moved += std::abs(scan.getScanRange(i) - m_referenceRanges[i]) > 0.1f;
		}
	return both >= 10 ? double(moved) / double(both) : 0.0;
}

}  // namespace pmslam
