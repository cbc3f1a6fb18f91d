/* pmslam — map writers (see MapExport.h). */
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/map/GridLine.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <png.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <stdexcept>

namespace pmslam
{
namespace
{
using Cell = mrpt::maps::COccupancyGridMap2D::cellType;

// What the writers read of a grid: a lattice and its raw cells, one row at a time.
class CellRows
{
   public:
	virtual ~CellRows() = default;
	double resolution = 0.05;
	double originX = 0, originY = 0;  // map-frame corner of cell (0, 0)
	// Inclusive bounds of the cells holding evidence (false when none).
	virtual bool evidenceBounds(int& x0, int& y0, int& x1, int& y1) const = 0;
	// Inclusive bounds of the cells that exist (false when unbounded).
	virtual bool extent(int& x0, int& y0, int& x1, int& y1) const = 0;
	// Cells cx0 .. cx0+n-1 of row cy (0 = never observed outside the extent).
	virtual void readRow(int cy, int cx0, int n, Cell* out) const = 0;
	int cellX(double wx) const { return static_cast<int>(std::floor((wx - originX) / resolution)); }
	int cellY(double wy) const { return static_cast<int>(std::floor((wy - originY) / resolution)); }
};

class DenseRows : public CellRows
{
   public:
	explicit DenseRows(const mrpt::maps::COccupancyGridMap2D& g) : m_g(g)
	{
		resolution = g.getResolution();
		originX = g.getXMin();
		originY = g.getYMin();
	}
	bool evidenceBounds(int& x0, int& y0, int& x1, int& y1) const override
	{
		const auto& raw = m_g.getRawMap();
		const int sx = int(m_g.getSizeX()), sy = int(m_g.getSizeY());
		CellBounds b;
		for (int y = 0; y < sy; ++y)
			for (int x = 0; x < sx; ++x)
				if (raw[std::size_t(y) * sx + x] != 0) b.add(x, y);
		return b.get(x0, y0, x1, y1);
	}
	bool extent(int& x0, int& y0, int& x1, int& y1) const override
	{
		x0 = y0 = 0;
		x1 = int(m_g.getSizeX()) - 1;
		y1 = int(m_g.getSizeY()) - 1;
		return true;
	}
	void readRow(int cy, int cx0, int n, Cell* out) const override
	{
		const int sx = int(m_g.getSizeX()), sy = int(m_g.getSizeY());
		const Cell* row = cy >= 0 && cy < sy ? &m_g.getRawMap()[std::size_t(cy) * sx] : nullptr;
		for (int i = 0; i < n; ++i)
		{
			const int cx = cx0 + i;
			out[i] = row && cx >= 0 && cx < sx ? row[cx] : Cell(0);
		}
	}

   private:
	const mrpt::maps::COccupancyGridMap2D& m_g;
};

class SparseRows : public CellRows
{
   public:
	explicit SparseRows(const OccupancyDistanceGridMap& g) : m_cells(g.cells())
	{
		resolution = g.updateOptions().resolution;
	}
	bool evidenceBounds(int& x0, int& y0, int& x1, int& y1) const override
	{
		return m_cells.evidenceBounds(x0, y0, x1, y1);
	}
	bool extent(int&, int&, int&, int&) const override { return false; }
	void readRow(int cy, int cx0, int n, Cell* out) const override { m_cells.readRow(cy, cx0, n, out); }

   private:
	const SparseOccupancyGrid& m_cells;
};

std::unique_ptr<CellRows> rowsOf(const mrpt::maps::COccupancyGridMap2D& grid)
{
	if (const auto* live = dynamic_cast<const OccupancyDistanceGridMap*>(&grid))
		return std::make_unique<SparseRows>(*live);
	return std::make_unique<DenseRows>(grid);
}

struct Crop
{
	int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive cell bounds
	int width() const { return x1 - x0 + 1; }
	int height() const { return y1 - y0 + 1; }
};

// The part of the grid that holds any evidence, plus a small margin.
Crop mappedArea(const CellRows& rows)
{
	Crop c;
	int ex0 = 0, ey0 = 0, ex1 = 0, ey1 = 0;
	const bool bounded = rows.extent(ex0, ey0, ex1, ey1);
	if (!rows.evidenceBounds(c.x0, c.y0, c.x1, c.y1))
	{
		if (bounded) return Crop{ex0, ey0, std::min(ex0 + 9, ex1), std::min(ey0 + 9, ey1)};
		return Crop{0, 0, 9, 9};
	}
	const int m = 10;
	c.x0 -= m;
	c.y0 -= m;
	c.x1 += m;
	c.y1 += m;
	if (bounded)
	{
		c.x0 = std::max(ex0, c.x0);
		c.y0 = std::max(ey0, c.y0);
		c.x1 = std::min(ex1, c.x1);
		c.y1 = std::min(ey1, c.y1);
	}
	return c;
}

uint8_t grey(Cell l)
{
	if (l == 0) return 205;	 // never observed
	return static_cast<uint8_t>(std::lround(255.0 * mrpt::maps::COccupancyGridMap2D::l2p(l)));
}

// The picture of a map, one RGB row at a time: grey cells with lines and dots drawn over them.
class MapPicture
{
   public:
	MapPicture(const CellRows& rows, const Trajectory& path, const std::vector<mrpt::math::TPoint2D>& scanInMap,
			   const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links)
		: m_rows(rows), m_crop(mappedArea(rows)), m_cells(std::size_t(m_crop.width()))
	{
		// Trajectory in red, one segment per consecutive pose pair; loop closures in blue between
		// the two keyframes each joins; the current scan's endpoints as green 3×3 dots.
		const Colour red{220, 30, 30}, blue{30, 80, 230}, green{20, 170, 40};
		for (std::size_t i = 1; i < path.size(); ++i) line(path[i - 1].x, path[i - 1].y, path[i].x, path[i].y, red);
		for (const auto& [a, b] : links) line(a.x, a.y, b.x, b.y, blue);
		for (const auto& p : scanInMap)
		{
			const auto [px, py] = toPixel(p.x, p.y);
			if (px > 0 && py > 0 && px + 1 < width() && py + 1 < height())
				for (int dy = -1; dy <= 1; ++dy)
					for (int dx = -1; dx <= 1; ++dx) m_marks.push_back({py + dy, px + dx, green});
		}
		// By row, keeping the drawing order within a row (later marks paint over earlier ones).
		std::stable_sort(m_marks.begin(), m_marks.end(), [](const Mark& a, const Mark& b) { return a.py < b.py; });
	}
	int width() const { return m_crop.width(); }
	int height() const { return m_crop.height(); }
	const Crop& crop() const { return m_crop; }

	// Image row py (0 = top = the largest map y) as RGB triplets.
	void rgbRow(int py, uint8_t* rgb)
	{
		m_rows.readRow(m_crop.y1 - py, m_crop.x0, width(), m_cells.data());
		for (int x = 0; x < width(); ++x) rgb[3 * x] = rgb[3 * x + 1] = rgb[3 * x + 2] = grey(m_cells[std::size_t(x)]);
		auto it = std::lower_bound(m_marks.begin(), m_marks.end(), py, [](const Mark& m, int y) { return m.py < y; });
		for (; it != m_marks.end() && it->py == py; ++it)
			std::memcpy(rgb + 3 * it->px, it->colour.rgb, 3);
	}

   private:
	struct Colour
	{
		uint8_t rgb[3];
	};
	struct Mark
	{
		int py, px;
		Colour colour;
	};
	std::pair<int, int> toPixel(double wx, double wy) const
	{
		return {m_rows.cellX(wx) - m_crop.x0, m_crop.y1 - m_rows.cellY(wy)};
	}
	// A one-pixel line between two map points, clipped to the picture.
	void line(double ax, double ay, double bx, double by, Colour colour)
	{
		const auto [x, y] = toPixel(ax, ay);
		const auto [ex, ey] = toPixel(bx, by);
		const int w = width(), h = height();
		if ((x < 0 && ex < 0) || (y < 0 && ey < 0) || (x >= w && ex >= w) || (y >= h && ey >= h)) return;
		const int dx = std::abs(ex - x), dy = -std::abs(ey - y);
		if (dx > 4 * (w + h) || -dy > 4 * (w + h)) return;	// a wild pose: not a line to draw
		auto mark = [&](int px, int py) {
			if (px >= 0 && py >= 0 && px < w && py < h) m_marks.push_back({py, px, colour});
			return true;
		};
		forEachCellOnLine(x, y, ex, ey, mark);
		mark(ex, ey);
	}

	const CellRows& m_rows;
	Crop m_crop;
	std::vector<Cell> m_cells;	// one row
	std::vector<Mark> m_marks;
};

// libpng reports errors through longjmp; this keeps C++ objects out of the frame that jumps.
struct PngSink
{
	std::ostream* out;
	char message[200];
};
void pngWrite(png_structp png, png_bytep data, png_size_t n)
{
	auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
	sink->out->write(reinterpret_cast<const char*>(data), std::streamsize(n));
}
void pngFlush(png_structp) {}
void pngError(png_structp png, png_const_charp msg)
{
	auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
	std::snprintf(sink->message, sizeof(sink->message), "%s", msg);
	std::longjmp(png_jmpbuf(png), 1);
}
void pngWarning(png_structp, png_const_charp) {}

// Writes the picture as an 8-bit RGB PNG, row by row. Returns false (message set) on a libpng error.
bool writePngRows(MapPicture& pic, std::vector<uint8_t>& row, PngSink& sink)
{
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, pngError, pngWarning);
	if (!png) return false;
	png_infop info = png_create_info_struct(png);
	if (!info || setjmp(png_jmpbuf(png)))
	{
		png_destroy_write_struct(&png, &info);
		return false;
	}
	png_set_write_fn(png, &sink, pngWrite, pngFlush);
	png_set_IHDR(png, info, png_uint_32(pic.width()), png_uint_32(pic.height()), 8, PNG_COLOR_TYPE_RGB,
				 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_write_info(png, info);
	for (int y = 0; y < pic.height(); ++y)
	{
		pic.rgbRow(y, row.data());
		png_write_row(png, row.data());
	}
	png_write_end(png, info);
	png_destroy_write_struct(&png, &info);
	return true;
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

// MRPT's serialisation of a COccupancyGridMap2D is its header (cell size, then sizes, extent and
// resolution), the cells, then its options. A template grid of 2×3 cells with the same options,
// serialised by MRPT itself, gives every byte but the sizes, extent and cells: those are written
// here, so the file is what MRPT would write for the whole grid without the grid ever being dense.
void streamSerializedGrid(const mrpt::maps::COccupancyGridMap2D& options, double res, int x0, int y0, int sx, int sy,
						  const std::function<void(int, Cell*)>& readRow, mrpt::io::CStream& out)
{
	mrpt::maps::COccupancyGridMap2D tmpl(0.f, float(2 * res), 0.f, float(3 * res), float(res));
	tmpl.insertionOptions = options.insertionOptions;
	tmpl.likelihoodOptions = options.likelihoodOptions;
	tmpl.genericMapParams = options.genericMapParams;
	if (tmpl.getSizeX() != 2 || tmpl.getSizeY() != 3)
		throw std::logic_error("saveGridMapGz: MRPT sized the template grid unexpectedly");
	for (int i = 0; i < 6; ++i) tmpl.getRow(i / 2)[i % 2] = Cell(11 * (i + 1));  // row-major
	mrpt::io::CMemoryStream mem;
	mrpt::serialization::archiveFrom(mem) << tmpl;
	const auto* bytes = static_cast<const uint8_t*>(mem.getRawBufferData());
	const std::size_t n = mem.getTotalBytesCount();
	auto header = [](uint32_t sizeX, uint32_t sizeY, float xmin, float xmax, float ymin, float ymax, float r) {
		std::vector<uint8_t> h(28);
		const uint32_t u[2] = {sizeX, sizeY};
		const float f[5] = {xmin, xmax, ymin, ymax, r};
		std::memcpy(h.data(), u, 8);  // MRPT archives are little-endian, as is every target here
		std::memcpy(h.data() + 8, f, 20);
		return h;
	};
	std::vector<uint8_t> probe = header(2, 3, tmpl.getXMin(), tmpl.getXMax(), tmpl.getYMin(), tmpl.getYMax(),
										tmpl.getResolution());
	for (int i = 0; i < 6; ++i) probe.push_back(uint8_t(11 * (i + 1)));
	const auto at = std::search(bytes, bytes + n, probe.begin(), probe.end());
	if (at == bytes + n || std::search(at + 1, bytes + n, probe.begin(), probe.end()) != bytes + n)
		throw std::logic_error("saveGridMapGz: unexpected COccupancyGridMap2D serialisation layout");
	const std::size_t head = std::size_t(at - bytes);
	out.Write(bytes, head);
	const auto h = header(uint32_t(sx), uint32_t(sy), float(x0 * res), float((x0 + sx) * res), float(y0 * res),
						  float((y0 + sy) * res), float(res));
	out.Write(h.data(), h.size());
	std::vector<Cell> row(static_cast<std::size_t>(sx));
	for (int iy = 0; iy < sy; ++iy)
	{
		readRow(y0 + iy, row.data());
		out.Write(row.data(), row.size());
	}
	out.Write(bytes + head + probe.size(), n - head - probe.size());
}
}  // namespace

void saveMapPgmYaml(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& pgmPath,
					const std::string& yamlPath)
{
	const auto rows = rowsOf(grid);
	const Crop c = mappedArea(*rows);
	writeFileAtomically(pgmPath, [&](std::ostream& out) {
		out << "P5\n# pmslam occupancy grid\n" << c.width() << " " << c.height() << "\n255\n";
		std::vector<Cell> cells(std::size_t(c.width()));
		std::string row(std::size_t(c.width()), '\0');
		for (int y = c.y1; y >= c.y0; --y)	// image rows top-down = map y descending
		{
			rows->readRow(y, c.x0, c.width(), cells.data());
			for (int x = 0; x < c.width(); ++x) row[std::size_t(x)] = static_cast<char>(grey(cells[std::size_t(x)]));
			out.write(row.data(), std::streamsize(row.size()));
		}
	});
	const std::string image = std::filesystem::path(pgmPath).filename().string();
	writeFileAtomically(yamlPath, [&](std::ostream& out) {
		out << std::setprecision(9) << "image: " << image << "\nresolution: " << grid.getResolution()
			<< "\norigin: [" << rows->originX + c.x0 * rows->resolution << ", "
			<< rows->originY + c.y0 * rows->resolution << ", 0.0]\n"
			<< "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
	});
}

mrpt::img::CImage renderMap(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& path,
							const std::vector<mrpt::math::TPoint2D>& scanInMap,
							const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links, int maxSide)
{
	const auto rows = rowsOf(grid);
	MapPicture pic(*rows, path, scanInMap, links);
	const int k = maxSide > 0 ? std::max(1, (std::max(pic.width(), pic.height()) + maxSide - 1) / maxSide) : 1;
	const int w = (pic.width() + k - 1) / k, h = (pic.height() + k - 1) / k;
	mrpt::img::CImage img(w, h, mrpt::img::CH_RGB);
	std::vector<uint8_t> rgb(3 * std::size_t(pic.width())), out(3 * std::size_t(w));
	std::vector<bool> coloured(static_cast<std::size_t>(w));
	for (int oy = 0; oy < h; ++oy)
	{
		std::fill(out.begin(), out.end(), uint8_t(255));
		std::fill(coloured.begin(), coloured.end(), false);
		for (int y = oy * k; y < std::min(pic.height(), (oy + 1) * k); ++y)
		{
			pic.rgbRow(y, rgb.data());
			for (int x = 0; x < pic.width(); ++x)
			{
				const uint8_t* p = &rgb[3 * std::size_t(x)];
				uint8_t* q = &out[3 * std::size_t(x / k)];
				if (p[0] != p[1] || p[1] != p[2])  // drawn: wins over the map
				{
					std::memcpy(q, p, 3);
					coloured[std::size_t(x / k)] = true;
				}
				else if (!coloured[std::size_t(x / k)] && p[0] < q[0])
					q[0] = q[1] = q[2] = p[0];
			}
		}
		// CImage is BGR in memory.
		for (int x = 0; x < w; ++x)
		{
			uint8_t* px = img(x, oy);
			px[0] = out[3 * std::size_t(x) + 2];
			px[1] = out[3 * std::size_t(x) + 1];
			px[2] = out[3 * std::size_t(x)];
		}
	}
	return img;
}

void saveMapPng(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& path, const std::string& pngPath,
				const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& links)
{
	const auto rows = rowsOf(grid);
	MapPicture pic(*rows, path, {}, links);
	std::vector<uint8_t> row(3 * std::size_t(pic.width()));
	writeFileAtomically(pngPath, [&](std::ostream& out) {
		PngSink sink{&out, {}};
		if (!writePngRows(pic, row, sink))
			throw std::runtime_error("cannot write '" + pngPath + "': PNG encoder failed: " + sink.message);
	});
}

void saveGridMapGz(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path)
{
	viaTemporary(path, [&](const std::string& tmp) {
		mrpt::io::CFileGZOutputStream f;
		if (!f.open(tmp)) throw std::runtime_error("cannot write '" + path + "'");
		if (const auto* live = dynamic_cast<const OccupancyDistanceGridMap*>(&grid))
		{
			int x0, y0, x1, y1;
			live->denseExtent(x0, y0, x1, y1);  // what materialize() would hold
			const double r = live->updateOptions().resolution;
			streamSerializedGrid(
				grid, r, x0, y0, x1 - x0 + 1, y1 - y0 + 1,
				[&](int cy, Cell* out) { live->cells().readRow(cy, x0, x1 - x0 + 1, out); }, f);
		}
		else if (std::string(grid.GetRuntimeClass()->className) == "COccupancyGridMap2D")
			mrpt::serialization::archiveFrom(f) << static_cast<const mrpt::serialization::CSerializable&>(grid);
		else
		{
			const mrpt::maps::COccupancyGridMap2D plain = grid;
			mrpt::serialization::archiveFrom(f) << plain;
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
