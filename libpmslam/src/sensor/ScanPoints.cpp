/* pmslam — scan to robot-frame points (see ScanPoints.h). */
#include <mrpt/poses/CPose3D.h>
#include <pmslam/sensor/ScanPoints.h>

#include <cmath>

namespace pmslam
{
ScanPoints scanToPoints(const mrpt::obs::CObservation2DRangeScan& scan, const ScanPointsOptions& opts)
{
	ScanPoints out;
	// Rebuilt from x, y, z, yaw, pitch, roll: a deserialised CPose3D carries its rotation
	// matrix as stored, which a damaged file can make non-orthonormal or huge.
	const mrpt::poses::CPose3D sp(scan.sensorPose.x(), scan.sensorPose.y(), scan.sensorPose.z(),
								  scan.sensorPose.yaw(), scan.sensorPose.pitch(), scan.sensorPose.roll());
	out.sensorOrigin = {sp.x(), sp.y()};
	const std::size_t n = scan.getScanSize();
	out.hits.reserve(n);
	const double maxHit = opts.maxHitRange > 0 ? opts.maxHitRange : std::numeric_limits<double>::infinity();
	// The full 3D sensor pose maps the scan plane into the robot frame; dropping z
	// afterwards handles lasers mounted upside down (roll = pi) or yawed.
	const auto R = sp.getRotationMatrix();
	auto toRobot = [&](double r, double a) {
		const double lx = r * std::cos(a), ly = r * std::sin(a);
		return mrpt::math::TPoint2Df(static_cast<float>(sp.x() + R(0, 0) * lx + R(0, 1) * ly),
									 static_cast<float>(sp.y() + R(1, 0) * lx + R(1, 1) * ly));
	};
	for (std::size_t i = 0; i < n; ++i)
	{
		const double r = scan.getScanRange(i);
		if (!std::isfinite(r) || r <= 0) continue;
		const double a = scan.getScanAngle(i);
		if (scan.getScanRangeValidity(i))
		{
			if (r < opts.minRange) continue;
			const auto q = toRobot(r, a);
			if (!std::isfinite(q.x) || !std::isfinite(q.y)) continue;
			if (r <= maxHit)
				out.hits.push_back(q);
			else if (opts.noReturnCarveRange > 0)
				out.freeEnds.push_back(toRobot(std::min(r, opts.noReturnCarveRange), a));
		}
		else if (opts.noReturnCarveRange > 0 && r >= scan.maxRange)
			out.freeEnds.push_back(toRobot(opts.noReturnCarveRange, a));
	}
	return out;
}

}  // namespace pmslam
