/* pmslam — the fixed map of a localisation run (see PriorMap.h). */
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/io/PriorMap.h>
#include <pmslam/util/ExceptionText.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace pmslam
{
namespace
{
const char* const kExpected =
	"expected a ROS map.yaml, an MRPT .gridmap[.gz] or .simplemap[.gz], or a pm-slam-app output folder";

bool endsWith(std::string s, const std::string& tail)
{
	std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
	return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

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
	mrpt::maps::CSimpleMap sm;
	mrpt::io::CFileGZInputStream in;
	if (!in.open(path)) throw PriorMapError(path + ": cannot open (" + kExpected + ")");
	try
	{
		mrpt::serialization::archiveFrom(in) >> sm;
	}
	catch (const std::exception& e)
	{
		throw PriorMapError(path + ": not an MRPT simple map (" + exceptionSummary(e.what()) + ")");
	}
	if (sm.empty()) throw PriorMapError(path + ": the simple map has no keyframe");
	mrpt::maps::COccupancyGridMap2D g(-10, 10, -10, 10, static_cast<float>(resolution));
	g.loadFromSimpleMap(sm);
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
	if (endsWith(m.source, ".yaml") || endsWith(m.source, ".yml"))
	{
		m.grid = fromYaml(m.source);
		m.kind = "ROS map_server map";
	}
	else if (endsWith(m.source, ".simplemap") || endsWith(m.source, ".simplemap.gz"))
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
