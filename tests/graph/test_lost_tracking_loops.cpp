// Loop closure after lost tracking. The front-end lost the robot and picked it up again 2.5 m off
// (a drop-out, a wrong re-localisation), then mapped a dead end on its own, coming back along its
// own path (a loop of the stretch onto itself), and returned to the corridor it had mapped before.
// That loop onto itself says nothing of where the stretch is relative to the corridor: the search
// window towards the corridor must keep growing from the last loop before the loss, so that the
// loops back onto the corridor are found and the graph puts the stretch back. Keyframes are fed to
// the back-end as the front-end would: scans taken at the true poses, placed where the front-end
// put them, and moved by each correction the back-end hands over.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/graph/LoopClosure.h>

#include <algorithm>
#include <cmath>

#include "SyntheticWorld.h"

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;
using pmslam::testing::SyntheticWorld;

namespace
{
// A corridor 40 m x 2.4 m along x with pilasters at irregular spacing, and a dead end 2 m wide
// branching north at x = 20 for 14 m, with its own alcoves.
SyntheticWorld corridorWithDeadEnd()
{
	SyntheticWorld w;
	// The corridor's walls, the north one open from x = 19 to 21.
	w.segments.push_back({0, -1.2, 40, -1.2});
	w.segments.push_back({0, 1.2, 19, 1.2});
	w.segments.push_back({21, 1.2, 40, 1.2});
	w.segments.push_back({0, -1.2, 0, 1.2});
	w.segments.push_back({40, -1.2, 40, 1.2});
	for (double x : {2.0, 5.5, 7.0, 11.0, 14.5, 16.0, 23.5, 27.0, 31.0, 33.0, 37.5}) w.addBox(x, -1.2, x + 0.3, -0.9);
	for (double x : {3.5, 8.5, 12.0, 17.5, 25.5, 29.0, 34.5, 36.0}) w.addBox(x, 0.9, x + 0.3, 1.2);
	// The dead end.
	w.segments.push_back({19, 1.2, 19, 15.2});
	w.segments.push_back({21, 1.2, 21, 15.2});
	w.segments.push_back({19, 15.2, 21, 15.2});
	for (double y : {3.0, 6.5, 8.0, 12.5}) w.addBox(19, y, 19.3, y + 0.4);
	for (double y : {4.5, 9.5, 11.0, 14.0}) w.addBox(20.7, y, 21, y + 0.3);
	return w;
}

struct Leg
{
	std::vector<TPose2D> poses;
	void straight(TPose2D from, TPose2D to, double step = 0.5)
	{
		const double d = std::hypot(to.x - from.x, to.y - from.y);
		const int n = static_cast<int>(std::round(d / step));
		for (int k = 0; k < n; ++k)
			poses.push_back({from.x + (to.x - from.x) * k / n, from.y + (to.y - from.y) * k / n, from.phi});
	}
	void spin(const TPose2D& at, double from, double to)
	{
		const int n = static_cast<int>(std::ceil(std::abs(to - from) / (M_PI / 4)));
		for (int k = 0; k < n; ++k) poses.push_back({at.x, at.y, from + (to - from) * k / n});
	}
};
}  // namespace

TEST(LostTrackingLoops, AStretchLoopingOntoItselfIsStillBroughtBackToWhatCameBefore)
{
	const SyntheticWorld world = corridorWithDeadEnd();
	// East to x = 35 and back to the dead end: the way back closes loops onto the way out.
	Leg path;
	path.straight({1, 0, 0}, {35, 0, 0});
	path.spin({35, 0, 0}, 0, M_PI);
	path.straight({35, 0, M_PI}, {20, 0, M_PI});
	const std::size_t lost = path.poses.size();	 // tracking lost here
	// Up the dead end and back down: the way down closes loops onto the way up.
	path.spin({20, 0, M_PI}, M_PI, M_PI / 2);
	path.straight({20, 0, M_PI / 2}, {20, 14, M_PI / 2});
	path.spin({20, 14, M_PI / 2}, M_PI / 2, -M_PI / 2);
	path.straight({20, 14, -M_PI / 2}, {20, 0, -M_PI / 2});
	// West along the corridor mapped before.
	path.spin({20, 0, -M_PI / 2}, -M_PI / 2, -M_PI);
	path.straight({20, 0, -M_PI}, {2, 0, -M_PI});
	const std::size_t n = path.poses.size();

	pmslam::LoopClosureOptions o;
	o.background = false;
	pmslam::LoopClosure lc(o, pmslam::PerfectMatchMatcher::TConfigParams{}, pmslam::OccupancyGridUpdateOptions{});
	const Eigen::Matrix3d H = Eigen::Vector3d(2e4, 2e4, 2e5).asDiagonal();
	// From the loss on the front-end has the robot 2.5 m east of where it is (along the corridor,
	// where a wrong placement survives longest); the back-end's corrections move its frame.
	const CPose2D offset(2.5, 0, 0);
	CPose2D frame;
	for (std::size_t k = 0; k < n; ++k)
	{
		if (auto u = lc.sync()) frame = u->correction + frame;
		const CPose2D truth(path.poses[k]);
		const CPose2D placed = frame + (k >= lost ? offset + truth : truth);
		const auto scan = world.scan(path.poses[k], 361, 2 * M_PI, 20.0, 0.005, unsigned(k + 1));
		lc.addKeyframe(placed.asTPose(), 100 + k, pmslam::scanToPoints(scan), H, k != lost, false);
	}
	lc.finish();
	// Where the graph has each keyframe since the loss relative to the first, against the truth: the
	// last one, and the worst (the dead end is placed only by the front-end and the loops).
	const auto off = [&](std::size_t k) {
		const CPose2D r = CPose2D(lc.nodePose(k)) - CPose2D(lc.nodePose(0));
		const CPose2D t = CPose2D(path.poses[k]) - CPose2D(path.poses[0]);
		return std::hypot(r.x() - t.x(), r.y() - t.y());
	};
	const double error = off(n - 1);
	double worst = 0;
	for (std::size_t k = lost; k < n; ++k) worst = std::max(worst, off(k));
	std::printf("%zu keyframes, lost at %zu: last keyframe %.3f m off, worst since the loss %.3f m (front-end: 2.5 m); "
				"%zu loops closed, %zu loop edges\n",
				n, lost, error, worst, lc.stats().closures, lc.stats().accepted);
	EXPECT_LT(error, 0.1);
	EXPECT_LT(worst, 0.2);
}

// D46. After a loss the front-end put the robot 90 degrees and metres off (a long gap across which the
// odometry turned wrong, a re-localisation onto a look-alike): beyond the widest drift window (10 m,
// 45 degrees), so no candidate the graph expects is ever near. The stretch's keyframes are searched on
// the whole map from before the loss; the places found are verified and accepted as any loop, and the
// stretch comes back. Without the whole-map search (globalSearchEvery 0) it stays where it was put.
TEST(LostTrackingLoops, AStretchPlacedBeyondEveryDriftWindowIsFoundByAWholeMapSearch)
{
	const SyntheticWorld world = corridorWithDeadEnd();
	Leg path;
	path.straight({1, 0, 0}, {35, 0, 0});
	path.spin({35, 0, 0}, 0, M_PI);
	path.straight({35, 0, M_PI}, {20, 0, M_PI});
	const std::size_t lost = path.poses.size();
	path.spin({20, 0, M_PI}, M_PI, M_PI / 2);
	path.straight({20, 0, M_PI / 2}, {20, 14, M_PI / 2});
	path.spin({20, 14, M_PI / 2}, M_PI / 2, -M_PI / 2);
	path.straight({20, 14, -M_PI / 2}, {20, 0, -M_PI / 2});
	path.spin({20, 0, -M_PI / 2}, -M_PI / 2, -M_PI);
	path.straight({20, 0, -M_PI}, {2, 0, -M_PI});
	const std::size_t n = path.poses.size();

	const auto run = [&](double globalSearchEvery) {
		pmslam::LoopClosureOptions o;
		o.background = false;
		o.globalSearchEvery = globalSearchEvery;
		pmslam::LoopClosure lc(o, pmslam::PerfectMatchMatcher::TConfigParams{}, pmslam::OccupancyGridUpdateOptions{});
		const Eigen::Matrix3d H = Eigen::Vector3d(2e4, 2e4, 2e5).asDiagonal();
		// From the loss on, the front-end's frame is turned by 90 degrees about a point 3 m off the
		// robot: the stretch lies 4-21 m from where it is, turned twice the widest heading window. (At
		// 60 degrees the verification's refinement can slide the first keyframes back from within
		// the window once the local map's distance layer reaches 0.75 m (D50), and the rest follows.)
		const CPose2D at(path.poses[lost]);
		const CPose2D offset = at + CPose2D(3, -2, 90.0 * M_PI / 180) + (-at);
		CPose2D frame;
		for (std::size_t k = 0; k < n; ++k)
		{
			if (auto u = lc.sync()) frame = u->correction + frame;
			const CPose2D truth(path.poses[k]);
			const CPose2D placed = frame + (k >= lost ? offset + truth : truth);
			const auto scan = world.scan(path.poses[k], 361, 2 * M_PI, 20.0, 0.005, unsigned(k + 1));
			lc.addKeyframe(placed.asTPose(), 100 + k, pmslam::scanToPoints(scan), H, k != lost, false);
		}
		lc.finish();
		double worst = 0;
		for (std::size_t k = lost; k < n; ++k)
		{
			const CPose2D r = CPose2D(lc.nodePose(k)) - CPose2D(lc.nodePose(0));
			const CPose2D t = CPose2D(path.poses[k]) - CPose2D(path.poses[0]);
			worst = std::max(worst, std::hypot(r.x() - t.x(), r.y() - t.y()));
		}
		std::printf("globalSearchEvery %.1f: worst keyframe since the loss %.3f m off; %zu whole-map searches, "
					"%zu places verified, %zu loop edges, %.2f s in them\n",
					globalSearchEvery, worst, lc.stats().globalSearches, lc.stats().globalVerified, lc.stats().accepted,
					lc.stats().globalSeconds);
		return worst;
	};
	EXPECT_GT(run(0), 5.0);	 // the drift window never reaches the truth
	EXPECT_LT(run(2.0), 0.2);
}
