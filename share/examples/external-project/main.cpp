// Maps an MRPT rawlog with pmslam's builder, the way one would with CMetricMapBuilderICP.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/slam/CMetricMapBuilderPM.h>
#include <pmslam/io/MapExport.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv)
{
	const std::string log = argc > 1 ? argv[1]
		: "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
	mrpt::io::CFileGZInputStream file;
	if (!file.open(log)) return std::fprintf(stderr, "cannot open %s\n", log.c_str()), 1;
	auto in = mrpt::serialization::archiveFrom(file);

	pmslam::CMetricMapBuilderPM slam;	  // a mrpt::slam::CMetricMapBuilder
	slam.PM_params.sigma = 0.1;			  // matcher options, INI section [PerfectMatch]
	slam.PM_options.grid.resolution = 0.05;  // builder and grid options, [MappingApplication]
	slam.initialize();

	mrpt::obs::CActionCollection::Ptr action;
	mrpt::obs::CSensoryFrame::Ptr frame;
	mrpt::obs::CObservation::Ptr obs;
	std::size_t entry = 0;
	while (mrpt::obs::CRawlog::getActionObservationPairOrObservation(in, action, frame, obs, entry))
	{
		if (obs) slam.processObservation(obs);	// observation-only rawlogs
		else slam.processActionObservation(*action, *frame);
	}

	const mrpt::math::TPose2D pose = slam.currentPose();  // robot base in the map frame (m, rad)
	std::printf("scans %zu, matched %zu, inserted %zu, final pose %.3f %.3f %.2f deg\n", slam.scansProcessed(),
				slam.scansMatched(), slam.scansInserted(), pose.x, pose.y, mrpt::RAD2DEG(pose.phi));
	if (argc > 2) pmslam::saveGridMapGz(slam.grid(), argv[2]);  // opens in MRPT's tools
	return 0;
}
