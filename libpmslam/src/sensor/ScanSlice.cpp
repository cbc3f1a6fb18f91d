/* pmslam — a 2D laser scan out of a 3D observation (see ScanSlice.h). */
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/poses/CPose3D.h>
#include <pmslam/sensor/ScanSlice.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace pmslam
{
namespace
{
mrpt::obs::CObservation2DRangeScan::Ptr emptySlice(const mrpt::obs::CObservation& o, const ScanSliceOptions& opts)
{
	auto s = mrpt::obs::CObservation2DRangeScan::Create();
	const std::size_t n = static_cast<std::size_t>(std::lround(2 * M_PI / opts.resolution));
	s->aperture = static_cast<float>(2 * M_PI);
	s->rightToLeft = true;
	s->maxRange = static_cast<float>(opts.maxRange);
	s->sensorPose = mrpt::poses::CPose3D();
	s->sensorLabel = o.sensorLabel + "_slice";
	s->timestamp = o.timestamp;
	s->resizeScan(n);
	for (std::size_t i = 0; i < n; ++i)
	{
		s->setScanRange(i, static_cast<float>(opts.maxRange));
		s->setScanRangeValidity(i, false);
	}
	return s;
}

// The nearest point of the band in each beam of the full-turn scan (MRPT's convention,
// getScanAngle(): beam i at -aperture/2 + i·aperture/(n-1)).
mrpt::obs::CObservation2DRangeScan::Ptr binPoints(const mrpt::obs::CObservation& o, const mrpt::maps::CPointsMap& pts,
												  const ScanSliceOptions& opts)
{
	auto s = emptySlice(o, opts);
	const std::size_t n = s->getScanSize();
	const auto& xs = pts.getPointsBufferRef_x();
	const auto& ys = pts.getPointsBufferRef_y();
	const auto& zs = pts.getPointsBufferRef_z();
	bool any = false;
	for (std::size_t k = 0; k < xs.size(); ++k)
	{
		if (!(zs[k] >= opts.minHeight && zs[k] <= opts.maxHeight)) continue;
		const double r = std::hypot(xs[k], ys[k]);
		if (!(r > 0.01 && r <= opts.maxRange)) continue;
		const double a = std::atan2(ys[k], xs[k]);
		const std::size_t i = std::min<std::size_t>(n - 1, static_cast<std::size_t>(std::lround((a + M_PI) / (2 * M_PI) * double(n - 1))));
		if (!s->getScanRangeValidity(i) || r < s->getScanRange(i))
		{
			s->setScanRange(i, static_cast<float>(r));
			s->setScanRangeValidity(i, true);
			any = true;
		}
	}
	return any ? s : nullptr;
}
}  // namespace

bool isSliceable(const mrpt::obs::CObservation& o)
{
	return dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&o) ||
		   dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&o) ||
		   dynamic_cast<const mrpt::obs::CObservationVelodyneScan*>(&o) ||
		   dynamic_cast<const mrpt::obs::CObservationRotatingScan*>(&o);
}

mrpt::obs::CObservation2DRangeScan::Ptr sliceObservation(const mrpt::obs::CObservation& o, const ScanSliceOptions& opts,
														   std::string* why)
{
	if (const auto* r = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&o))
	{
		if (!r->hasRangeImage)
		{
			if (why) *why = "a 3D range scan without a range image";
			return nullptr;
		}
		// MRPT's conversion trusts the image and the camera model: a damaged one is not handed to it.
		const auto& cp = r->cameraParams;
		const auto rows = r->rangeImage.rows(), cols = r->rangeImage.cols();
		if (rows <= 0 || cols <= 0 || rows > 8192 || cols > 8192 || std::size_t(rows) != cp.nrows ||
			std::size_t(cols) != cp.ncols || !(cp.fx() > 0) || !(cp.fy() > 0) || !std::isfinite(cp.cx()) ||
			!std::isfinite(cp.cy()) || !(r->rangeUnits > 0) || !std::isfinite(r->rangeUnits) ||
			!r->sensorPose.asVectorVal().array().isFinite().all())
		{
			if (why) *why = "a 3D range scan whose range image does not fit its camera model";
			return nullptr;
		}
		// MRPT's own conversion, reprojected to the robot origin, within the height band.
		mrpt::obs::T3DPointsTo2DScanParams p;
		p.sensorLabel = o.sensorLabel + "_slice";
		p.use_origin_sensor_pose = true;
		p.z_min = opts.minHeight;
		p.z_max = opts.maxHeight;
		auto s = mrpt::obs::CObservation2DRangeScan::Create();
		const_cast<mrpt::obs::CObservation3DRangeScan*>(r)->convertTo2DScan(*s, p);
		s->timestamp = o.timestamp;
		bool any = false;
		for (std::size_t i = 0; i < s->getScanSize(); ++i) any = any || s->getScanRangeValidity(i);
		return any ? s : nullptr;
	}
	if (dynamic_cast<const mrpt::obs::CObservationRotatingScan*>(&o))
	{
		if (why) *why = "a CObservationRotatingScan, which in MRPT 2.5 has no ring elevation angles (no point has a known height)";
		return nullptr;
	}
	mrpt::maps::CSimplePointsMap pts;
	pts.insertionOptions.minDistBetweenLaserPoints = 0;
	if (const auto* v = dynamic_cast<const mrpt::obs::CObservationVelodyneScan*>(&o))
	{
		if (v->point_cloud.size() == 0)
		{
			if (v->calibration.empty())
			{
				if (why) *why = "a Velodyne scan with neither a point cloud nor a calibration to make one";
				return nullptr;
			}
			// The log kept the raw packets only: MRPT generates the points from them.
			mrpt::obs::CObservationVelodyneScan copy = *v;
			copy.generatePointCloud();
			pts.insertObservation(copy, mrpt::poses::CPose3D());
		}
		else
			pts.insertObservation(o, mrpt::poses::CPose3D());
	}
	else if (dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&o))
		pts.insertObservation(o, mrpt::poses::CPose3D());
	else
		return nullptr;
	return binPoints(o, pts, opts);
}

}  // namespace pmslam
