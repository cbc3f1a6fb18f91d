/* pmslam — a robot that odometry says stands still, while its scans say it moves.
 *
 * A robot carried or pushed, or a logger that repeats a stale odometry reading:
 * odometry stands still, below the keyframe gate, yet most ranges changed since the
 * scan that last matched or went into the map (the reference). Such a scan is
 * matched all the same (matchWhenScanChanged). A match that then finds the robot
 * where odometry says is no evidence of motion: the scan keeps the prediction, so
 * that only a real displacement moves the robot, not matching jitter.
 */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <vector>

namespace pmslam
{
/** The MapBuilderOptions field of the same name (see there for its default and why). */
struct StandstillCheckOptions
{
	double matchWhenScanChanged = 0;  ///< fraction of the ranges (0 = never)
};

class StandstillCheck
{
   public:
	explicit StandstillCheck(const StandstillCheckOptions& options) : m_options(options) {}

	/** More than matchWhenScanChanged of the beams changed since the reference: the robot moves. */
	bool scansSayMoved(const mrpt::obs::CObservation2DRangeScan& scan) const
	{
		return m_options.matchWhenScanChanged > 0 && changedFraction(scan) > m_options.matchWhenScanChanged;
	}
	/** A match at `matched` confirms the prediction: the robot stood still after all. */
	static bool stillThere(const mrpt::math::TPose2D& matched, const mrpt::math::TPose2D& predicted);

	/** `scan` is the new reference (it was matched or inserted). */
	void keep(const mrpt::obs::CObservation2DRangeScan& scan);
	bool hasReference() const { return !m_referenceRanges.empty(); }

	/** Fraction of the beams valid in this scan and the reference whose range changed by > 0.1 m. */
	double changedFraction(const mrpt::obs::CObservation2DRangeScan& scan) const;

   private:
	StandstillCheckOptions m_options;
	std::vector<float> m_referenceRanges;  // of the reference scan (0 = invalid)
};

}  // namespace pmslam
