// The map writers stream from the sparse live map: the files are what the same cells in a plain
// MRPT grid give (byte for byte), and the PNG is the picture renderMap() draws.
#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <pmslam/io/MapExport.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "SyntheticLogs.h"
#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using pmslam::testing::ScratchDir;

namespace
{
pmslam::OccupancyDistanceGridMap roomMap(pmslam::Trajectory* path = nullptr)
{
	const auto world = pmslam::testing::furnishedRoom();
	pmslam::OccupancyDistanceGridMap m;
	double t = 0;
	for (const TPose2D p : {TPose2D(0, 0, 0), TPose2D(1.5, -1, 1.2), TPose2D(-2, 1, -2.0), TPose2D(3, 0.5, 2.8)})
	{
		m.insertScan(pmslam::scanToPoints(world.scan(p, 361)), p);
		if (path) path->push_back({t += 1, p.x, p.y, p.phi});
	}
	return m;
}

// The same cells in a plain MRPT grid one block wider on every side than the sparse map's blocks
// (so no writer's crop is clamped by the grid's edge).
mrpt::maps::COccupancyGridMap2D paddedDense(const pmslam::OccupancyDistanceGridMap& m)
{
	const double r = m.updateOptions().resolution;
	int x0, y0, x1, y1;
	EXPECT_TRUE(m.cells().allocatedBounds(x0, y0, x1, y1));
	x0 -= 32, y0 -= 32, x1 += 32, y1 += 32;
	mrpt::maps::COccupancyGridMap2D g(float(x0 * r), float((x1 + 1) * r), float(y0 * r), float((y1 + 1) * r), float(r));
	for (int y = y0; y <= y1; ++y) m.cells().readRow(y, x0, x1 - x0 + 1, g.getRow(y - y0));
	return g;
}

std::string gunzip(const std::string& path)
{
	mrpt::io::CFileGZInputStream in(path);
	std::string out;
	char buf[65536];
	for (std::size_t n; (n = in.Read(buf, sizeof(buf))) > 0;) out.append(buf, n);
	return out;
}

std::string slurp(const std::string& path)
{
	std::ifstream f(path, std::ios::binary);
	std::ostringstream s;
	s << f.rdbuf();
	return s.str();
}
}  // namespace

TEST(MapExport, GridmapStreamedFromTheSparseCellsIsWhatMrptWritesForThem)
{
	ScratchDir d("export-gridmap");
	const auto m = roomMap();
	pmslam::saveGridMapGz(m, d.path("sparse.gridmap.gz"));
	pmslam::saveGridMapGz(m.denseCopy(), d.path("dense.gridmap.gz"));	// MRPT's own serialiser
	const std::string a = gunzip(d.path("sparse.gridmap.gz")), b = gunzip(d.path("dense.gridmap.gz"));
	EXPECT_GT(a.size(), 10000u);
	EXPECT_TRUE(a == b) << "streamed " << a.size() << " bytes, MRPT " << b.size() << " bytes";
	// And MRPT reads it back: the same cells.
	mrpt::maps::COccupancyGridMap2D loaded;
	pmslam::loadGridMapGz(d.path("sparse.gridmap.gz"), loaded);
	EXPECT_EQ(loaded.getRawMap(), m.denseCopy().getRawMap());
}

TEST(MapExport, PgmAndYamlFromTheSparseCellsEqualThoseOfThePlainGrid)
{
	ScratchDir d("export-pgm");
	const auto m = roomMap();
	pmslam::saveMapPgmYaml(m, d.path("a.pgm"), d.path("a.yaml"));
	pmslam::saveMapPgmYaml(paddedDense(m), d.path("b.pgm"), d.path("b.yaml"));
	EXPECT_TRUE(slurp(d.path("a.pgm")) == slurp(d.path("b.pgm")));
	// The YAMLs differ only in the image's name; the origins agree to the float precision of an MRPT grid.
	std::string ya = slurp(d.path("a.yaml")), yb = slurp(d.path("b.yaml"));
	auto origin = [](const std::string& y) {
		double ox, oy;
		EXPECT_EQ(std::sscanf(y.c_str() + y.find("origin: [") + 9, "%lf, %lf", &ox, &oy), 2);
		return std::make_pair(ox, oy);
	};
	EXPECT_NEAR(origin(ya).first, origin(yb).first, 1e-5);
	EXPECT_NEAR(origin(ya).second, origin(yb).second, 1e-5);
	// Unknown cells are 205, observed ones the MRPT probability × 255, rows top-down.
	const std::string pgm = slurp(d.path("a.pgm"));
	int w, h;
	ASSERT_EQ(std::sscanf(pgm.c_str(), "P5\n# pmslam occupancy grid\n%d %d", &w, &h), 2);
	const std::size_t start = pgm.size() - std::size_t(w) * h;
	const double r = 0.05, ox = origin(ya).first, oy = origin(ya).second;
	for (int py = 0; py < h; py += 7)
		for (int px = 0; px < w; px += 5)
		{
			const int cx = int(std::lround(ox / r)) + px, cy = int(std::lround(oy / r)) + (h - 1 - py);
			const auto c = m.cells().get(cx, cy);
			const int want = c == 0 ? 205 : int(std::lround(255.0 * mrpt::maps::COccupancyGridMap2D::l2p(c)));
			ASSERT_EQ(int(uint8_t(pgm[start + std::size_t(py) * w + px])), want) << px << "," << py;
		}
}

TEST(MapExport, PngIsThePictureRenderMapDraws)
{
	ScratchDir d("export-png");
	pmslam::Trajectory path;
	const auto m = roomMap(&path);
	const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>> links = {{{0, 0}, {3, 0.5}}};
	pmslam::saveMapPng(m, path, d.path("map.png"), links);
	mrpt::img::CImage png;
	ASSERT_TRUE(png.loadFromFile(d.path("map.png")));
	const mrpt::img::CImage drawn = pmslam::renderMap(m, path, {}, links);
	ASSERT_EQ(png.getWidth(), drawn.getWidth());
	ASSERT_EQ(png.getHeight(), drawn.getHeight());
	std::size_t red = 0, blue = 0;
	for (unsigned y = 0; y < png.getHeight(); ++y)
		for (unsigned x = 0; x < png.getWidth(); ++x)
		{
			for (unsigned ch = 0; ch < 3; ++ch) ASSERT_EQ(*png(int(x), int(y), ch), *drawn(int(x), int(y), ch)) << x << "," << y;
			const uint8_t b = *png(int(x), int(y), 0u), g = *png(int(x), int(y), 1u), r = *png(int(x), int(y), 2u);
			red += r == 220 && g == 30 && b == 30;
			blue += r == 30 && g == 80 && b == 230;
		}
	// The map part is the same picture from the same cells in a plain MRPT grid (the overlay is left
	// out there: a pose exactly on a cell edge may fall in either cell with the grid's float origin).
	const mrpt::img::CImage plain = pmslam::renderMap(m, {}, {}, {}), dense = pmslam::renderMap(paddedDense(m), {}, {}, {});
	ASSERT_EQ(plain.getWidth(), dense.getWidth());
	ASSERT_EQ(plain.getHeight(), dense.getHeight());
	std::size_t differ = 0;
	for (unsigned y = 0; y < plain.getHeight(); ++y)
		for (unsigned x = 0; x < plain.getWidth(); ++x) differ += *plain(int(x), int(y), 0u) != *dense(int(x), int(y), 0u);
	EXPECT_EQ(differ, 0u);
	EXPECT_GT(red, 60u);	// the trajectory: about 2.8 + 3.8 + 5.1 m at 5 cm per pixel
	EXPECT_GT(blue, 40u);  // the loop-closure link, 3 m
}

TEST(MapExport, AShrunkViewShowsEachBlocksDarkestCellOrItsDrawing)
{
	pmslam::Trajectory path;
	const auto m = roomMap(&path);
	const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>> links = {{{0, 0}, {3, 0.5}}};
	const mrpt::img::CImage full = pmslam::renderMap(m, path, {}, links);
	const int W = int(full.getWidth()), H = int(full.getHeight());
	const int maxSide = std::max(W, H) / 3 - 1;	 // a factor of 4
	const mrpt::img::CImage small = pmslam::renderMap(m, path, {}, links, maxSide);
	const int k = (std::max(W, H) + maxSide - 1) / maxSide;
	ASSERT_EQ(k, 4);
	ASSERT_EQ(int(small.getWidth()), (W + k - 1) / k);
	ASSERT_EQ(int(small.getHeight()), (H + k - 1) / k);
	EXPECT_LE(std::max(small.getWidth(), small.getHeight()), unsigned(maxSide));
	std::size_t walls = 0, drawn = 0;
	for (int oy = 0; oy < int(small.getHeight()); ++oy)
		for (int ox = 0; ox < int(small.getWidth()); ++ox)
		{
			// Brute force over the block of the full picture: the last drawn pixel in row order, else the darkest.
			int darkest = 255;
			const uint8_t* colour = nullptr;
			for (int y = oy * k; y < std::min(H, (oy + 1) * k); ++y)
				for (int x = ox * k; x < std::min(W, (ox + 1) * k); ++x)
				{
					const uint8_t* p = full(x, y);
					if (p[0] != p[1] || p[1] != p[2])
						colour = p;
					else
						darkest = std::min(darkest, int(p[0]));
				}
			const uint8_t* q = small(ox, oy);
			if (colour)
			{
				for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(q[ch], colour[ch]) << ox << "," << oy;
				++drawn;
			}
			else
			{
				for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(int(q[ch]), darkest) << ox << "," << oy;
				walls += darkest < 100;
			}
		}
	EXPECT_GT(walls, 50u);	// the room's walls survive the shrinking
	EXPECT_GT(drawn, 15u);
	// No limit, or one the picture fits in: the full picture.
	const mrpt::img::CImage same = pmslam::renderMap(m, path, {}, links, std::max(W, H));
	ASSERT_EQ(int(same.getWidth()), W);
	ASSERT_EQ(int(same.getHeight()), H);
}
