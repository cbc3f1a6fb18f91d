// pm-lidar-emulator: a simulated robot in a SyntheticWorld, and the sensor protocols that serve its scans.
// The world and the path are header-only so that a test can ray-cast the same world from the truth poses.
#pragma once

#include "../SyntheticWorld.h"

#include <mrpt/math/TPose2D.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace pmslam::testing
{
/** A loop of corridors, 20 m x 12 m, 2.5 m wide, around a 15 m x 7 m block, with doorways into two rooms,
 * an alcove, a cut corner, pillars and boxes along the walls: features along every stretch, so that a scan
 * matcher is not left sliding along a featureless corridor. An open door to the outside at the end of the
 * first corridor lets some beams go without a return from the start on. */
inline SyntheticWorld corridorsWorld()
{
	SyntheticWorld w;
	auto wall = [&w](double x0, double y0, double x1, double y1) { w.segments.push_back({x0, y0, x1, y1}); };
	// Outer wall, with doorways to a room below (x in [-3.5, -2.5]), a room on the right (y in [-0.5, 0.5]) and
	// the outside (x = 10, y in [-5, -4.5]), and a cut corner.
	wall(-10, -6, -3.5, -6);
	wall(-2.5, -6, 10, -6);
	wall(10, -6, 10, -5);
	wall(10, -4.5, 10, -0.5);
	wall(10, 0.5, 10, 6);
	wall(10, 6, -8.5, 6);
	wall(-8.5, 6, -10, 4.5);
	wall(-10, 4.5, -10, -6);
	// The rooms behind the doorways, each with something inside.
	wall(-5, -6, -5, -9);
	wall(-5, -9, -1, -9);
	wall(-1, -9, -1, -6);
	w.addBox(-4.5, -8.5, -3.8, -7.9);
	wall(10, -2, 13, -2);
	wall(13, -2, 13, 2);
	wall(13, 2, 10, 2);
	w.addBox(11.8, 0.8, 12.2, 1.2);
	// The block the corridors go around, with an alcove in its top side.
	wall(-7.5, -3.5, 7.5, -3.5);
	wall(7.5, -3.5, 7.5, 3.5);
	wall(7.5, 3.5, 1, 3.5);
	wall(1, 3.5, 1, 2.5);
	wall(1, 2.5, -1, 2.5);
	wall(-1, 2.5, -1, 3.5);
	wall(-1, 3.5, -7.5, 3.5);
	wall(-7.5, 3.5, -7.5, -3.5);
	// Pillars and boxes, at least 0.65 m from the path (which runs 1.25 m from the walls).
	w.addBox(-6.15, -5.7, -5.85, -5.4);
	w.addBox(3.85, -5.7, 4.15, -5.4);
	w.addBox(1.5, -3.9, 2.5, -3.5);
	w.addBox(-4.0, -3.8, -3.4, -3.5);
	w.addBox(9.4, 2.0, 9.7, 2.3);
	w.addBox(7.5, -1.5, 7.8, -0.7);
	w.addBox(3.0, 5.5, 4.2, 6.0);
	w.addBox(-5.5, 5.4, -4.9, 6.0);
	w.addBox(-2.15, 5.4, -1.85, 5.7);
	w.addBox(-9.7, -1.5, -9.4, -1.2);
	w.addBox(-9.7, 1.8, -9.4, 2.1);
	w.addBox(-7.8, 0.5, -7.5, 1.5);
	return w;
}

/** A closed path: a rectangle of half-sizes a x b centred on (cx, cy) with corners rounded to radius r, driven
 * counter-clockwise from the middle of its bottom side; the yaw follows the direction of travel. */
class LoopPath
{
   public:
	LoopPath(double cx, double cy, double a, double b, double r)
	{
		const double sa = 2 * (a - r), sb = 2 * (b - r), arc = M_PI / 2 * r;
		const double lens[] = {sa / 2, arc, sb, arc, sa, arc, sb, arc, sa / 2};
		const bool turns[] = {false, true, false, true, false, true, false, true, false};
		Piece p{cx, cy - b, 0.0, 0.0, 0.0};
		for (int i = 0; i < 9; ++i)
		{
			p.len = lens[i];
			p.curvature = turns[i] ? 1.0 / r : 0.0;
			m_pieces.push_back(p);
			const auto end = advance(p, p.len);
			p.x = end.x;
			p.y = end.y;
			p.yaw = end.phi;
			m_length += p.len;
		}
	}

	double length() const { return m_length; }

	/** The pose after driving a distance s (any real: it wraps around the loop). */
	mrpt::math::TPose2D at(double s) const
	{
		s = std::fmod(s, m_length);
		if (s < 0) s += m_length;
		for (const auto& p : m_pieces)
		{
			if (s <= p.len) return advance(p, s);
			s -= p.len;
		}
		return advance(m_pieces.back(), m_pieces.back().len);
	}

	/** The loop used in world `name` ("corridors" or "room") at `speed` m/s: corners are rounded so that the
	 * turn rate stays at 0.5 rad/s or below as far as the world leaves room for it. */
	static LoopPath forWorld(const std::string& name, double speed)
	{
		const double r = speed / 0.5;
		if (name == "room")	 // pmslam::testing::furnishedRoom(): between the pillar, the cabinet and the partition
			return LoopPath(0.6, -0.95, 1.8, 1.25, std::clamp(r, 1.0, 1.25));
		return LoopPath(0.0, 0.0, 8.75, 4.75, std::clamp(r, 1.25, 2.5));	// the corridors' centre lines
	}

   private:
	struct Piece
	{
		double x, y, yaw, len, curvature;
	};
	static mrpt::math::TPose2D advance(const Piece& p, double d)
	{
		if (p.curvature == 0.0) return {p.x + d * std::cos(p.yaw), p.y + d * std::sin(p.yaw), p.yaw};
		const double yaw = p.yaw + p.curvature * d;
		return {p.x + (std::sin(yaw) - std::sin(p.yaw)) / p.curvature,
				p.y - (std::cos(yaw) - std::cos(p.yaw)) / p.curvature, std::remainder(yaw, 2 * M_PI)};
	}
	std::vector<Piece> m_pieces;
	double m_length = 0;
};

namespace emulator
{
using Clock = std::chrono::steady_clock;

/** One scan: the pose it was taken from and its ranges (NaN: no return within range). */
struct Scan
{
	Clock::time_point time;
	mrpt::math::TPose2D pose;
	std::vector<double> ranges;
};

/** The simulated robot: its clock (started by the first scan request), its ray-cast scans and the truth log. */
class Robot
{
   public:
	Robot(SyntheticWorld world, LoopPath path, double speed, double noise, std::FILE* truth);

	/** Starts the robot's clock at the first call; later calls do nothing. */
	void startServing(Clock::time_point now);
	std::optional<Clock::time_point> servingSince() const { return m_start; }
	std::optional<Clock::time_point> firstScanServed() const { return m_firstServed; }

	/** The scan at time t (servingSince() must be set) of n beams at angles first + i * step (rad,
	 * counter-clockwise from the robot's heading), with range noise, no return beyond maxRange. */
	Scan scan(Clock::time_point t, int n, double first, double step, double maxRange);
	/** Logs a scan sent to the client: one truth line "t x y yaw". */
	void served(const Scan& s);

	/** Seconds since the Unix epoch at steady time t. */
	double epochSeconds(Clock::time_point t) const;
	/** Microseconds since the emulator started (a sensor's own clock). */
	std::uint64_t uptimeMicros(Clock::time_point t) const;

	std::mt19937& rng() { return m_rng; }

   private:
	SyntheticWorld m_world;
	LoopPath m_path;
	double m_speed, m_noise;
	std::FILE* m_truth;
	std::mt19937 m_rng{20240601};
	Clock::time_point m_boot = Clock::now();
	std::chrono::system_clock::time_point m_bootEpoch = std::chrono::system_clock::now();
	std::optional<Clock::time_point> m_start, m_firstServed;
};

/** A sensor protocol on one TCP stream: requests in, replies and streamed scans out. */
class Protocol
{
   public:
	Protocol(Robot& robot, bool garbage) : m_robot(robot), m_garbage(garbage) {}
	virtual ~Protocol() = default;

	/** A client connected: per-connection state starts afresh. */
	virtual void connected() = 0;
	/** Bytes from the client; replies are appended to out. */
	virtual void received(std::string_view bytes, Clock::time_point now, std::string& out) = 0;
	/** When due() must next be called (a scan to stream), if ever. */
	virtual std::optional<Clock::time_point> nextDue() const = 0;
	/** Streams what is due at `now`; with clientReading false the client lags, and scans are skipped. */
	virtual void due(Clock::time_point now, std::string& out, bool clientReading) = 0;

   protected:
	/** --garbage: random bytes instead of a reply to one request. */
	void garbageReply(std::string& out);

	Robot& m_robot;
	const bool m_garbage;
};

/** Hokuyo URG/UTM (SCIP 2.0): 1081 steps over 270 degrees, 40 Hz, 0.02-30 m. */
std::unique_ptr<Protocol> makeScip2(Robot& robot, bool garbage);
/** SICK LMS1xx (CoLa-A over TCP): 541 beams over 270 degrees, 25 Hz, 20 m. With mrptOrder the beams go
 * out left to right, the order MRPT's CLMS100Eth assumes, instead of the sensor's right to left. */
std::unique_ptr<Protocol> makeLms1xx(Robot& robot, bool garbage, bool mrptOrder);

}  // namespace emulator
}  // namespace pmslam::testing
