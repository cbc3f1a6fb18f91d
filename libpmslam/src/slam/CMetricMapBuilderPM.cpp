/* pmslam — PerfectMatchSlam as an MRPT map builder (see CMetricMapBuilderPM.h). */
#include <pmslam/slam/CMetricMapBuilderPM.h>

namespace pmslam
{
CMetricMapBuilderPM::CMetricMapBuilderPM() { setLoggerName("CMetricMapBuilderPM"); }

CMetricMapBuilderPM::~CMetricMapBuilderPM() = default;

void CMetricMapBuilderPM::initialize(const mrpt::maps::CSimpleMap& initialMap, const mrpt::poses::CPosePDF* x0)
{
	PerfectMatchSlam::initialize(initialMap, x0);
}

mrpt::poses::CPose3DPDF::Ptr CMetricMapBuilderPM::getCurrentPoseEstimation() const
{
	return PerfectMatchSlam::getCurrentPoseEstimation();
}

void CMetricMapBuilderPM::processActionObservation(mrpt::obs::CActionCollection& action,
												   mrpt::obs::CSensoryFrame& in_SF)
{
	PerfectMatchSlam::processActionObservation(action, in_SF);
}

void CMetricMapBuilderPM::getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const
{
	PerfectMatchSlam::getCurrentlyBuiltMap(out_map);
}

unsigned int CMetricMapBuilderPM::getCurrentlyBuiltMapSize() { return PerfectMatchSlam::getCurrentlyBuiltMapSize(); }

const mrpt::maps::CMultiMetricMap* CMetricMapBuilderPM::getCurrentlyBuiltMetricMap() const
{
	return PerfectMatchSlam::getCurrentlyBuiltMetricMap();
}

void CMetricMapBuilderPM::saveCurrentEstimationToImage(const std::string& file, bool formatEMF_BMP)
{
	PerfectMatchSlam::saveCurrentEstimationToImage(file, formatEMF_BMP);
}

void CMetricMapBuilderPM::warn(const std::string& message) const { MRPT_LOG_WARN(message); }

}  // namespace pmslam
