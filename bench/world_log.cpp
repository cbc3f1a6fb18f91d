/* pm-world-log — synthetic worlds for the memory and speed benchmarks (bench/memory.sh, bench/speed.sh), written
 * as Carmen logs.
 *
 *   pm-world-log campus OUT.clf   a 1 km × 1 km campus: a loop of 3 m corridors 1300 m and 114 m long
 *                                 at 45° to the first pose (the robot starts at a corner facing between
 *                                 the two corridors), walls with doorways and pilasters every 3–8 m
 *   pm-world-log hall OUT.clf     an open 60 m × 40 m hall with a pillar every 6 m, driven in lanes
 *   pm-world-log hospital OUT.clf a 120 m × 60 m floor for bench/speed.sh: 2.4 m corridors round it and
 *                                 across its middle, glass along the middle corridor (60 % of the beams
 *                                 that meet it go through), driven round twice (loops to close), with two
 *                                 logging gaps of 10 s (the robot drives on, nothing is logged)
 *
 * Beside OUT.clf, OUT.relations holds the ground truth for pm-slam-eval.
 *
 * The robot drives at 1 m/s, a 181-beam 180° laser at 10 Hz (30 m range, 1 cm noise, or --range-noise M); the odometry is
 * 1 % long and turns 0.1°/m too much, so the map has to come from the matching. The area mapped grows
 * with the distance driven, while the campus's bounding box is a square kilometre from its first
 * kilometre on: what a dense grid pays for and a sparse one does not.
 */
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
struct Segment
{
	double x0, y0, x1, y1;
	bool glass = false;	 // a beam meeting it returns with probability kGlassReturns, else goes through
};
constexpr double kGlassReturns = 0.4;

// Segments bucketed in square cells, so a ray only meets the segments near its robot.
class World
{
   public:
	std::vector<Segment> segments;

	void index(double cell)
	{
		m_cell = cell;
		m_x0 = m_y0 = std::numeric_limits<double>::infinity();
		double x1 = -m_x0, y1 = -m_y0;
		for (const auto& s : segments)
		{
			m_x0 = std::min({m_x0, s.x0, s.x1});
			m_y0 = std::min({m_y0, s.y0, s.y1});
			x1 = std::max({x1, s.x0, s.x1});
			y1 = std::max({y1, s.y0, s.y1});
		}
		m_nx = int((x1 - m_x0) / cell) + 1;
		m_ny = int((y1 - m_y0) / cell) + 1;
		m_cells.assign(std::size_t(m_nx) * m_ny, {});
		for (std::size_t k = 0; k < segments.size(); ++k)
		{
			const auto& s = segments[k];
			const double len = std::hypot(s.x1 - s.x0, s.y1 - s.y0);
			const int n = int(len / (cell / 4)) + 1;
			int last = -1;
			for (int i = 0; i <= n; ++i)
			{
				const double t = double(i) / n;
				const int c = cellIndex(s.x0 + t * (s.x1 - s.x0), s.y0 + t * (s.y1 - s.y0));
				if (c != last && (m_cells[c].empty() || m_cells[c].back() != k)) m_cells[c].push_back(k);
				last = c;
			}
		}
	}

	// Ranges of a fan of beams from (x, y) facing `heading`; misses are `noReturn`.
	std::vector<double> scan(double x, double y, double heading, int beams, double maxRange, double noReturn,
							 std::mt19937& rng) const
	{
		std::bernoulli_distribution returns(kGlassReturns);
		std::vector<std::size_t> near;
		const int r = int(maxRange / m_cell) + 1;
		const int cx = int((x - m_x0) / m_cell), cy = int((y - m_y0) / m_cell);
		for (int j = std::max(0, cy - r); j <= std::min(m_ny - 1, cy + r); ++j)
			for (int i = std::max(0, cx - r); i <= std::min(m_nx - 1, cx + r); ++i)
				for (std::size_t k : m_cells[std::size_t(j) * m_nx + i]) near.push_back(k);
		std::sort(near.begin(), near.end());
		near.erase(std::unique(near.begin(), near.end()), near.end());
		std::vector<double> out(std::size_t(beams), noReturn);
		for (int b = 0; b < beams; ++b)
		{
			const double a = heading - M_PI / 2 + M_PI * b / (beams - 1);
			const double dx = std::cos(a), dy = std::sin(a);
			double best = maxRange;
			for (std::size_t k : near)
			{
				const auto& s = segments[k];
				const double ex = s.x1 - s.x0, ey = s.y1 - s.y0, den = dx * ey - dy * ex;
				if (std::abs(den) < 1e-12) continue;
				const double wx = s.x0 - x, wy = s.y0 - y;
				const double t = (wx * ey - wy * ex) / den, u = (wx * dy - wy * dx) / den;
				if (t > 1e-9 && u >= 0 && u <= 1 && t < best && (!s.glass || returns(rng))) best = t;
			}
			if (best < maxRange) out[std::size_t(b)] = best;
		}
		return out;
	}

   private:
	int cellIndex(double x, double y) const
	{
		const int i = std::clamp(int((x - m_x0) / m_cell), 0, m_nx - 1), j = std::clamp(int((y - m_y0) / m_cell), 0, m_ny - 1);
		return j * m_nx + i;
	}
	double m_cell = 5, m_x0 = 0, m_y0 = 0;
	int m_nx = 0, m_ny = 0;
	std::vector<std::vector<std::size_t>> m_cells;
};

// A wall from a to b (outside on its right) with features 0.9 m wide every 3–8 m: doorways 0.6 m deep
// and pilasters 0.3 m proud in turn, so the matcher has something along the corridor.
void featuredWall(World& w, double ax, double ay, double bx, double by, std::mt19937& rng)
{
	const double len = std::hypot(bx - ax, by - ay), ux = (bx - ax) / len, uy = (by - ay) / len;
	const double nx = uy, ny = -ux;
	auto at = [&](double s, double d) { return std::pair<double, double>(ax + ux * s + nx * d, ay + uy * s + ny * d); };
	std::uniform_real_distribution<double> gap(3, 8);
	double s = 0;
	int n = 0;
	for (double f = gap(rng); f + 0.9 < len - 1; f += 0.9 + gap(rng))
	{
		const double depth = n++ % 2 ? -0.3 : 0.6;
		const auto p0 = at(s, 0), p1 = at(f, 0), p2 = at(f, depth), p3 = at(f + 0.9, depth), p4 = at(f + 0.9, 0);
		w.segments.push_back({p0.first, p0.second, p1.first, p1.second});
		w.segments.push_back({p1.first, p1.second, p2.first, p2.second});
		w.segments.push_back({p2.first, p2.second, p3.first, p3.second});
		w.segments.push_back({p3.first, p3.second, p4.first, p4.second});
		s = f + 0.9;
	}
	const auto p0 = at(s, 0), p1 = at(len, 0);
	w.segments.push_back({p0.first, p0.second, p1.first, p1.second});
}

struct Pose
{
	double x, y, phi;
};

// Poses every `step` m along straight legs joined by turns on the spot (`turnSteps` poses per turn).
class PathBuilder
{
   public:
	PathBuilder(double x, double y, double phi) { poses.push_back({x, y, phi}); }
	void turnTo(double phi, int turnSteps)
	{
		const Pose p = poses.back();
		const double d = std::remainder(phi - p.phi, 2 * M_PI);
		for (int i = 1; i <= turnSteps; ++i) poses.push_back({p.x, p.y, p.phi + d * i / turnSteps});
	}
	void forward(double length, double step)
	{
		const Pose p = poses.back();
		const int n = int(length / step);
		for (int i = 1; i <= n; ++i) poses.push_back({p.x + i * step * std::cos(p.phi), p.y + i * step * std::sin(p.phi), p.phi});
	}
	std::vector<Pose> poses;
};

double g_rangeNoise = 0.01;  // m, Gaussian range noise (--range-noise)

// `unlogged`: ranges [first, last) of poses driven but not logged (a logging gap).
void writeCarmen(const World& w, const std::vector<Pose>& truth, const std::string& path,
				 const std::vector<std::pair<std::size_t, std::size_t>>& unlogged = {})
{
	const auto logged = [&](std::size_t k) {
		return std::none_of(unlogged.begin(), unlogged.end(), [&](const auto& g) { return k >= g.first && k < g.second; });
	};
	std::ofstream out(path);
	if (!out) throw std::runtime_error("cannot write " + path);
	out << "# synthetic world log written by pm-world-log (pmslam bench)\nPARAM robot_front_laser_max 30 nohost 0\n";
	std::mt19937 rng(7);
	std::normal_distribution<double> noise(0, g_rangeNoise);
	// Odometry: 1 % long, 0.1°/m of extra turn, integrated from the true increments.
	mrpt::poses::CPose2D odo(0, 0, 0);
	char buf[64];
	for (std::size_t k = 0; k < truth.size(); ++k)
	{
		if (k > 0)
		{
			const mrpt::poses::CPose2D a(truth[k - 1].x, truth[k - 1].y, truth[k - 1].phi),
				b(truth[k].x, truth[k].y, truth[k].phi);
			const mrpt::poses::CPose2D d = b - a;
			const double dist = std::hypot(d.x(), d.y());
			odo = odo + mrpt::poses::CPose2D(1.01 * d.x(), 1.01 * d.y(), d.phi() + dist * 0.1 * M_PI / 180);
		}
		if (!logged(k)) continue;
		const auto r = w.scan(truth[k].x, truth[k].y, truth[k].phi, 181, 30.0, 81.9, rng);
		const double t = 1000.0 + 0.1 * double(k);
		out << "FLASER 181";
		for (double v : r)
		{
			std::snprintf(buf, sizeof(buf), " %.3f", v < 81 ? v + noise(rng) : v);
			out << buf;
		}
		std::snprintf(buf, sizeof(buf), " %.6f %.6f %.6f", odo.x(), odo.y(), odo.phi());
		out << buf << buf;
		std::snprintf(buf, sizeof(buf), " %.6f nohost %.6f\n", t, t);
		out << buf;
	}
	if (!out.flush()) throw std::runtime_error("write failed: " + path);
	// Ground truth as relations (Kuemmerle et al.: the pose of the second scan in the first's frame): every
	// 10th scan to the one 1 s later, and every 100th to the one 100 s later (drift along a corridor).
	const std::string relPath = path.substr(0, path.rfind('.')) + ".relations";
	std::ofstream rel(relPath);
	for (std::size_t k = 0; k < truth.size(); k += 10)
		for (std::size_t gap : {std::size_t(10), std::size_t(1000)})
		{
			if ((gap == 1000 && k % 100) || k + gap >= truth.size() || !logged(k) || !logged(k + gap)) continue;
			const mrpt::poses::CPose2D a(truth[k].x, truth[k].y, truth[k].phi),
				b(truth[k + gap].x, truth[k + gap].y, truth[k + gap].phi);
			const mrpt::poses::CPose2D d = b - a;
			std::snprintf(buf, sizeof(buf), "%.6f %.6f ", 1000.0 + 0.1 * double(k), 1000.0 + 0.1 * double(k + gap));
			rel << buf;
			std::snprintf(buf, sizeof(buf), "%.6f %.6f 0 0 0 %.6f\n", d.x(), d.y(), d.phi());
			rel << buf;
		}
	if (!rel.flush()) throw std::runtime_error("write failed: " + relPath);
}

void campus(const std::string& path)
{
	World w;
	std::mt19937 rng(11);
	// The loop's corners in the (u, v) frame of its corridors; the world is that frame turned by 45°.
	const double a = 1300, b = 114, half = 1.5;
	const double c = std::cos(M_PI / 4), s = std::sin(M_PI / 4);
	auto toWorld = [&](double u, double v) { return std::pair<double, double>(c * u - s * v, s * u + c * v); };
	auto wall = [&](double u0, double v0, double u1, double v1) {
		const auto p = toWorld(u0, v0), q = toWorld(u1, v1);
		featuredWall(w, p.first, p.second, q.first, q.second, rng);
	};
	// Outer walls counter-clockwise (outside on the right), inner walls clockwise.
	wall(-half, -half, a + half, -half);
	wall(a + half, -half, a + half, b + half);
	wall(a + half, b + half, -half, b + half);
	wall(-half, b + half, -half, -half);
	wall(a - half, half, half, half);
	wall(a - half, b - half, a - half, half);
	wall(half, b - half, a - half, b - half);
	wall(half, half, half, b - half);
	w.index(5.0);
	// Start at the corner facing 0 in the world (45° between both corridors), then once around and on.
	PathBuilder p(0, 0, 0);
	const double step = 0.1;  // 1 m/s at 10 Hz
	p.turnTo(M_PI / 4, 20);
	p.forward(a, step);
	p.turnTo(3 * M_PI / 4, 20);
	p.forward(b, step);
	p.turnTo(5 * M_PI / 4, 20);
	p.forward(a, step);
	p.turnTo(7 * M_PI / 4, 20);
	p.forward(b, step);
	p.turnTo(M_PI / 4, 20);
	p.forward(30, step);
	writeCarmen(w, p.poses, path);
}

void hall(const std::string& path)
{
	World w;
	std::mt19937 rng(12);
	const double W = 60, H = 40;
	featuredWall(w, 0, 0, W, 0, rng);
	featuredWall(w, W, 0, W, H, rng);
	featuredWall(w, W, H, 0, H, rng);
	featuredWall(w, 0, H, 0, 0, rng);
	for (double x = 6; x < W - 1; x += 6)
		for (double y = 6; y < H - 1; y += 6)
		{
			const double h = 0.25;
			w.segments.push_back({x - h, y - h, x + h, y - h});
			w.segments.push_back({x + h, y - h, x + h, y + h});
			w.segments.push_back({x + h, y + h, x - h, y + h});
			w.segments.push_back({x - h, y + h, x - h, y - h});
		}
	w.index(5.0);
	// Lanes between the pillar rows, east then west, 3 m from the walls at the ends.
	PathBuilder p(3, 3, 0);
	const double step = 0.1;
	for (int lane = 0; lane < 6; ++lane)
	{
		p.forward(W - 6, step);
		p.turnTo(M_PI / 2, 20);
		p.forward(6, step);
		p.turnTo(lane % 2 ? 0 : M_PI, 20);
	}
	p.forward(W - 6, step);
	writeCarmen(w, p.poses, path);
}

void hospital(const std::string& path)
{
	World w;
	std::mt19937 rng(13);
	const double W = 120, H = 60, c = 2.4;	// floor and corridor width
	// Features go into the wall's right side: the outer wall counter-clockwise, the two blocks of rooms
	// between the corridors clockwise; the middle corridor's south side is glass over 40 m.
	featuredWall(w, 0, 0, W, 0, rng);
	featuredWall(w, W, 0, W, H, rng);
	featuredWall(w, W, H, 0, H, rng);
	featuredWall(w, 0, H, 0, 0, rng);
	const double mid = H / 2;
	for (const auto& [y0, y1] : {std::pair<double, double>(c, mid - c / 2), {mid + c / 2, H - c}})
	{
		featuredWall(w, c, y0, c, y1, rng);
		featuredWall(w, c, y1, W - c, y1, rng);
		featuredWall(w, W - c, y1, W - c, y0, rng);
		featuredWall(w, W - c, y0, c, y0, rng);
	}
	for (auto& seg : w.segments)
		if (seg.y0 == mid - c / 2 && seg.y1 == seg.y0 && std::min(seg.x0, seg.x1) > 40 && std::max(seg.x0, seg.x1) < 80)
			seg.glass = true;
	w.index(5.0);
	// Round the floor by the middle corridor and back by the outer ones, twice.
	PathBuilder p(c / 2, c / 2, 0);
	const double step = 0.1, lane = W - c, half = mid - c / 2;
	for (int round = 0; round < 2; ++round)
	{
		p.forward(lane, step);
		p.turnTo(M_PI / 2, 20);
		p.forward(half, step);
		p.turnTo(M_PI, 20);
		p.forward(lane, step);
		p.turnTo(M_PI / 2, 20);
		p.forward(H - c - half, step);
		p.turnTo(0, 20);
		p.forward(lane, step);
		p.turnTo(-M_PI / 2, 20);
		p.forward(H - c, step);
		p.turnTo(M_PI, 20);
		p.forward(lane, step);
		p.turnTo(0, 20);
	}
	// Two logging gaps of 10 s, on the first round's middle corridor and on the second round's top one.
	const std::size_t n = p.poses.size();
	writeCarmen(w, p.poses, path, {{n / 8, n / 8 + 100}, {n * 5 / 8, n * 5 / 8 + 100}});
}
}  // namespace

int main(int argc, char** argv)
{
	const bool noiseGiven = argc == 5 && std::string(argv[3]) == "--range-noise";
	const std::string world = argc == 3 || noiseGiven ? argv[1] : "";
	if (noiseGiven)
	{
		char* end = nullptr;
		g_rangeNoise = std::strtod(argv[4], &end);
		if (*end != '\0' || !(g_rangeNoise >= 0 && g_rangeNoise < 1))
		{
			std::cerr << "pm-world-log: --range-noise '" << argv[4] << "': expected metres in [0, 1)\n";
			return 2;
		}
	}
	if (world != "campus" && world != "hall" && world != "hospital")
	{
		std::cerr << "usage: pm-world-log campus|hall|hospital OUT.clf [--range-noise M]\n";
		return 2;
	}
	try
	{
		if (world == "campus")
			campus(argv[2]);
		else if (world == "hall")
			hall(argv[2]);
		else
			hospital(argv[2]);
	}
	catch (const std::exception& e)
	{
		std::cerr << "pm-world-log: " << e.what() << "\n";
		return 1;
	}
	return 0;
}
