// Code written for pmslam 0.1, with its include paths: the deprecated forwarding headers keep it compiling.
#include <pmslam/CMetricMapBuilderPM.h>
#include <pmslam/MapExport.h>

#include <string>

void saveMap(const pmslam::CMetricMapBuilderPM& slam, const std::string& path)
{
	pmslam::saveGridMapGz(slam.grid(), path);
}
