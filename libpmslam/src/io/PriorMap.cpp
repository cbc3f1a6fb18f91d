/* pmslam — the fixed map of a localisation run (see PriorMap.h). */
#include <pmslam/io/MapExport.h>
#include <pmslam/io/PriorMap.h>
#include <pmslam/io/SimpleMapFile.h>
#include <pmslam/util/ExceptionText.h>
#include <pmslam/util/TextCase.h>

#include <algorithm>
#include <filesystem>

namespace pmslam
{
namespace
{
const char* const kExpected =
	"expected a ROS map.yaml, an MRPT .gridmap[.gz] or .simplemap[.gz], or a pm-slam-app output folder";

bool hasOccupiedCell(const mrpt::maps::COccupancyGridMap2D& g)
{
	const auto& cells = g.getRawMap();
	// MRPT stores the log-odds of a cell being free: negative = occupancy above 0.5.
	return std::any_of(cells.begin(), cells.end(), [](auto c) { return c < 0; });
}

mrpt::maps::COccupancyGridMap2D fromYaml(const std::string& path)
{
	mrpt::maps::COccupancyGridMap2D g;
	bool ok = false;
	try
	{
		ok = g.loadFromROSMapServerYAML(path);
	}
	catch (const std::exception& e)
	{
		throw PriorMapError(path + ": not a readable ROS map_server map (" + exceptionSummary(e.what()) + ")");
	}
	if (!ok) throw PriorMapError(path + ": not a readable ROS map_server map (its image or keys)");
	return g;
}

mrpt::maps::COccupancyGridMap2D fromSimpleMap(const std::string& path, double resolution)
{
	mrpt::maps::CSimpleMap keyframes;
	try
	{
		keyframes = readSimpleMapFile(path);
	}
	catch (const SimpleMapFileError& e)
	{
		throw PriorMapError(e.what());
	}
	mrpt::maps::COccupancyGridMap2D g(-10, 10, -10, 10, static_cast<float>(resolution));
	g.loadFromSimpleMap(keyframes);
	return g;
}

/** What a pm-slam-app output folder holds, best first. */
std::string inFolder(const std::filesystem::path& dir)
{
	for (const char* name : {"map.gridmap.gz", "map.yaml"})
		if (std::filesystem::is_regular_file(dir / name)) return (dir / name).string();
	throw PriorMapError(dir.string() + ": a folder without map.gridmap.gz or map.yaml (" + kExpected + ")");
}
}  // namespace

PriorMap loadPriorMap(const std::string& path, double simplemapResolution)
{
	std::error_code ec;
	if (!std::filesystem::exists(path, ec)) throw PriorMapError(path + ": does not exist (" + kExpected + ")");
	PriorMap m;
	m.source = std::filesystem::is_directory(path, ec) ? inFolder(path) : path;
	if (endsWithIgnoringCase(m.source, ".yaml") || endsWithIgnoringCase(m.source, ".yml"))
	{
		m.grid = fromYaml(m.source);
		m.kind = "ROS map_server map";
	}
	else if (isSimpleMapName(m.source))
	{
		m.grid = fromSimpleMap(m.source, simplemapResolution);
		m.kind = "MRPT simple map";
	}
	else
	{
		try
		{
			loadGridMapGz(m.source, m.grid);
		}
		catch (const std::exception& e)
		{
			throw PriorMapError(exceptionSummary(e.what()) + " (" + kExpected + ")");
		}
		m.kind = "MRPT grid";
	}
	if (!hasOccupiedCell(m.grid)) throw PriorMapError(m.source + ": the map has no occupied cell");
	return m;
}

}  // namespace pmslam
