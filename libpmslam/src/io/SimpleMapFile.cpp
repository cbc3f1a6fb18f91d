/* pmslam — an MRPT simple map file (see SimpleMapFile.h). */
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/SimpleMapFile.h>
#include <pmslam/util/ExceptionText.h>
#include <pmslam/util/TextCase.h>

namespace pmslam
{
bool isSimpleMapName(const std::string& path)
{
	return endsWithIgnoringCase(path, ".simplemap") || endsWithIgnoringCase(path, ".simplemap.gz");
}

mrpt::maps::CSimpleMap readSimpleMapFile(const std::string& path)
{
	mrpt::maps::CSimpleMap keyframes;
	mrpt::io::CFileGZInputStream in;  // reads plain files as well as gzip ones
	if (!in.open(path)) throw SimpleMapFileError(path + ": cannot open");
	try
	{
		mrpt::serialization::archiveFrom(in) >> keyframes;
	}
	catch (const std::exception& e)
	{
		throw SimpleMapFileError(path + ": not an MRPT simple map (" + exceptionSummary(e.what()) + ")");
	}
	if (keyframes.empty()) throw SimpleMapFileError(path + ": the simple map has no keyframe");
	return keyframes;
}
}  // namespace pmslam
