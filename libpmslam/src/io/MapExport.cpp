/* pmslam — map writers (see MapExport.h). */
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/MapExport.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <stdexcept>

namespace pmslam
{
namespace
{
struct Crop
{
	int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive cell bounds
	int width() const { return x1 - x0 + 1; }
	int height() const { return y1 - y0 + 1; }
};

// The part of the grid that holds any evidence, plus a small margin.
Crop mappedArea(const mrpt::maps::COccupancyGridMap2D& grid)
{
	Crop c;
	c.x0 = int(grid.getSizeX());
	c.y0 = int(grid.getSizeY());
	const auto& raw = grid.getRawMap();
	for (int y = 0; y < int(grid.getSizeY()); ++y)
		for (int x = 0; x < int(grid.getSizeX()); ++x)
			if (raw[std::size_t(y) * grid.getSizeX() + x] != 0)
			{
				c.x0 = std::min(c.x0, x);
				c.x1 = std::max(c.x1, x);
				c.y0 = std::min(c.y0, y);
				c.y1 = std::max(c.y1, y);
			}
	if (c.x1 < c.x0)
		return Crop{0, 0, std::min(9, int(grid.getSizeX()) - 1), std::min(9, int(grid.getSizeY()) - 1)};
	const int m = 10;
	c.x0 = std::max(0, c.x0 - m);
	c.y0 = std::max(0, c.y0 - m);
	c.x1 = std::min(int(grid.getSizeX()) - 1, c.x1 + m);
	c.y1 = std::min(int(grid.getSizeY()) - 1, c.y1 + m);
	return c;
}

uint8_t grey(const mrpt::maps::COccupancyGridMap2D& grid, int x, int y)
{
	const auto l = grid.getRawMap()[std::size_t(y) * grid.getSizeX() + x];
	if (l == 0) return 205;	 // never observed
	return static_cast<uint8_t>(std::lround(255.0 * grid.getCell(x, y)));
}

// Writes through a temporary file in the same folder whose name keeps the extension (for writers
// that pick the format from it), then renames it over the target.
template <typename F>
void viaTemporary(const std::string& path, F&& write)
{
	namespace fs = std::filesystem;
	const fs::path target(path);
	const fs::path tmp = target.parent_path() / (target.stem().string() + ".tmp" + std::to_string(::getpid()) +
												 target.extension().string());
	try
	{
		write(tmp.string());
		fs::rename(tmp, target);
	}
	catch (...)
	{
		std::error_code ec;
		fs::remove(tmp, ec);
		throw;
	}
}
}  // namespace

void saveMapPgmYaml(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& pgmPath,
					const std::string& yamlPath)
{
	const Crop c = mappedArea(grid);
	writeFileAtomically(pgmPath, [&](std::ostream& out) {
		out << "P5\n# pmslam occupancy grid\n" << c.width() << " " << c.height() << "\n255\n";
		std::string row(std::size_t(c.width()), '\0');
		for (int y = c.y1; y >= c.y0; --y)	// image rows top-down = map y descending
		{
			for (int x = c.x0; x <= c.x1; ++x) row[std::size_t(x - c.x0)] = static_cast<char>(grey(grid, x, y));
			out.write(row.data(), std::streamsize(row.size()));
		}
	});
	const std::string image = std::filesystem::path(pgmPath).filename().string();
	writeFileAtomically(yamlPath, [&](std::ostream& out) {
		out << std::setprecision(9) << "image: " << image << "\nresolution: " << grid.getResolution()
			<< "\norigin: [" << grid.idx2x(c.x0) - 0.5 * grid.getResolution() << ", "
			<< grid.idx2y(c.y0) - 0.5 * grid.getResolution() << ", 0.0]\n"
			<< "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
	});
}

mrpt::img::CImage renderMap(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& path,
							const std::vector<mrpt::math::TPoint2D>& scanInMap,
							const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links)
{
	const Crop c = mappedArea(grid);
	mrpt::img::CImage img(c.width(), c.height(), mrpt::img::CH_RGB);
	for (int y = c.y0; y <= c.y1; ++y)
		for (int x = c.x0; x <= c.x1; ++x)
		{
			const uint8_t g = grey(grid, x, y);
			uint8_t* px = img(x - c.x0, c.y1 - y);
			px[0] = px[1] = px[2] = g;
		}
	// Trajectory in red, one segment per consecutive pose pair.
	const mrpt::img::TColor red(220, 30, 30);
	auto toPixel = [&](double wx, double wy) {
		return std::pair<int, int>(grid.x2idx(wx) - c.x0, c.y1 - grid.y2idx(wy));
	};
	for (std::size_t i = 1; i < path.size(); ++i)
	{
		const auto [ax, ay] = toPixel(path[i - 1].x, path[i - 1].y);
		const auto [bx, by] = toPixel(path[i].x, path[i].y);
		img.line(ax, ay, bx, by, red, 1);
	}
	// Loop closures in blue, between the two keyframes each joins.
	const mrpt::img::TColor blue(30, 80, 230);
	for (const auto& [a, b] : links)
	{
		const auto [ax, ay] = toPixel(a.x, a.y);
		const auto [bx, by] = toPixel(b.x, b.y);
		img.line(ax, ay, bx, by, blue, 1);
	}
	const mrpt::img::TColor green(20, 170, 40);
	for (const auto& p : scanInMap)
	{
		const auto [px, py] = toPixel(p.x, p.y);
		if (px > 0 && py > 0 && px + 1 < c.width() && py + 1 < c.height()) img.filledRectangle(px - 1, py - 1, px + 1, py + 1, green);
	}
	return img;
}

void saveMapPng(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& path, const std::string& pngPath,
				const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links)
{
	const mrpt::img::CImage img = renderMap(grid, path, {}, links);
	viaTemporary(pngPath, [&](const std::string& tmp) {
		if (!img.saveToFile(tmp)) throw std::runtime_error("cannot write '" + pngPath + "': image encoder failed");
	});
}

void saveGridMapGz(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path)
{
	viaTemporary(path, [&](const std::string& tmp) {
		mrpt::io::CFileGZOutputStream f;
		if (!f.open(tmp)) throw std::runtime_error("cannot write '" + path + "'");
		// Serialised as a plain COccupancyGridMap2D whatever subclass holds it. A subclass without RTTI
		// of its own (OccupancyDistanceGridMap) already is one to MRPT's serialiser: written as it is,
		// without a second full copy of the grid; any other is copied into a plain one first.
		auto out = mrpt::serialization::archiveFrom(f);
		if (std::string(grid.GetRuntimeClass()->className) == "COccupancyGridMap2D")
			out << static_cast<const mrpt::serialization::CSerializable&>(grid);
		else
		{
			const mrpt::maps::COccupancyGridMap2D plain = grid;
			out << plain;
		}
	});
}

void saveSimpleMapGz(const mrpt::maps::CSimpleMap& map, const std::string& path)
{
	viaTemporary(path, [&](const std::string& tmp) {
		mrpt::io::CFileGZOutputStream f;
		if (!f.open(tmp)) throw std::runtime_error("cannot write '" + path + "'");
		mrpt::serialization::archiveFrom(f) << map;
	});
}

void loadGridMapGz(const std::string& path, mrpt::maps::COccupancyGridMap2D& grid)
{
	mrpt::io::CFileGZInputStream f;
	if (!f.open(path)) throw std::runtime_error(path + ": cannot open");
	try
	{
		mrpt::serialization::archiveFrom(f) >> grid;
	}
	catch (const std::exception&)
	{
		throw std::runtime_error(path + ": expected a serialised COccupancyGridMap2D (.gridmap.gz)");
	}
}

}  // namespace pmslam
