/* pmslam — a 2D laser scan out of a 3D observation.
 *
 * 3D lidars and RGB-D cameras are mapped through a horizontal slice: the observation's points
 * (robot frame) whose height lies in [minHeight, maxHeight] become a 360-degree 2D scan seen from
 * the robot's origin, the nearest point in each angular bin of `resolution` giving the range.
 * The points come from MRPT's own conversions: CObservation3DRangeScan::convertTo2DScan
 * (reprojected to the robot origin, height band z_min/z_max) for range images, and a
 * CSimplePointsMap filled by MRPT's insertObservation for CObservationPointCloud and
 * CObservationVelodyneScan (its point cloud generated first when the log did not store one).
 * CObservationRotatingScan cannot be sliced with MRPT 2.5: it does not carry its rings'
 * elevation angles, so no point has a known height.
 *
 * Units: metres, radians; the slice's sensorPose is the identity (the robot origin).
 */
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <string>

namespace pmslam
{
struct ScanSliceOptions
{
	double minHeight = 0.1;	 ///< m above the robot's origin: floor returns stay out
	double maxHeight = 1.8;	 ///< m: ceilings and overhangs stay out
	double resolution = 0.5 * M_PI / 180;  ///< rad per beam of the slice
	double maxRange = 80.0;	 ///< m; farther points are left out
};

/** Whether `o` is a 3D observation sliceObservation() converts (false for 2D scans). */
bool isSliceable(const mrpt::obs::CObservation& o);

/** The 2D slice of a 3D observation, stamped and labelled as it ("<label>_slice"); nullptr when
 * `o` is not one (or is a CObservationRotatingScan: `why` then says so) or has no point in the band. */
mrpt::obs::CObservation2DRangeScan::Ptr sliceObservation(const mrpt::obs::CObservation& o, const ScanSliceOptions& opts,
														   std::string* why = nullptr);

}  // namespace pmslam
