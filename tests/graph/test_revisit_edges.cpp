// Revisit edges: a keyframe the front-end matched against the map gets an edge to the earlier
// visit's keyframe that sees the same returns, once the back-end's own loop detection has verified
// that the two visits are aligned. Keyframes are fed to the back-end at known poses. Along a
// corridor out and back, the way back links to the way out, with the relative pose the front-end
// had; back along a parallel corridor behind a wall, within reach but seeing the other face of the
// wall, it does not; after a re-localisation, not until a detected loop confirms it.
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
// A corridor 40 m x 2.4 m with pilasters at irregular spacing (so that the back-end's own loop
// detection has something to verify too).
SyntheticWorld corridor()
{
	SyntheticWorld w;
	w.addBox(0, -1.2, 40, 1.2);
	for (double x : {2.0, 5.5, 7.0, 11.0, 14.5, 16.0, 21.0, 23.5, 27.0, 31.0, 33.0, 37.5}) w.addBox(x, -1.2, x + 0.3, -0.9);
	for (double x : {3.5, 8.5, 12.0, 18.0, 20.0, 25.5, 29.0, 34.5, 36.0}) w.addBox(x, 0.9, x + 0.3, 1.2);
	return w;
}

// East from x = 1 to 35, turn on the spot, west back to x = 1 at y = `backY`: one keyframe every
// 0.5 m or 45 deg.
std::vector<TPose2D> outAndBack(double backY)
{
	std::vector<TPose2D> p;
	for (double x = 1; x <= 35; x += 0.5) p.push_back({x, 0, 0});
	for (int k = 1; k <= 4; ++k) p.push_back({35 + 0.5 * std::sin(k * M_PI / 4), backY / 2 * (1 - std::cos(k * M_PI / 4)), k * M_PI / 4});
	for (double x = 34.5; x >= 1; x -= 0.5) p.push_back({x, backY, M_PI});
	return p;
}

// Two such corridors side by side, 2.7 m apart, behind a 0.3 m wall open at the east end.
SyntheticWorld twinCorridors()
{
	SyntheticWorld w = corridor();
	w.segments.erase(w.segments.begin(), w.segments.begin() + 4);	// the corridor's own box
	w.addBox(0, -1.2, 40, 3.9);	 // outer walls of both
	w.addBox(0, 1.2, 36.5, 1.5);  // the dividing wall
	return w;
}

struct Drive
{
	std::vector<TPose2D> path;
	std::size_t outward = 0;  // keyframes before the turn
	std::vector<std::pair<std::size_t, std::size_t>> revisits;	// (from, to) of each revisit edge
	std::vector<TPose2D> measured;	// their relative poses
	std::vector<std::size_t> loopTo;	// the newer node of each detected loop edge
	pmslam::LoopClosureStats stats;
};

// `searchedAt`: the keyframe the front-end placed by a re-localisation search (none by default);
// loop detection tried every `detectEvery` metres.
Drive drive(const SyntheticWorld& world, double backY, double aperture, std::size_t searchedAt = SIZE_MAX,
			double detectEvery = pmslam::LoopClosureOptions{}.detectEvery)
{
	Drive r;
	r.path = outAndBack(backY);
	pmslam::LoopClosureOptions o;
	o.background = false;
	o.detectEvery = detectEvery;
	pmslam::LoopClosure lc(o, pmslam::PerfectMatchMatcher::TConfigParams{}, pmslam::OccupancyGridUpdateOptions{});
	// A well-conditioned match curvature, as the front-end reports it (map frame).
	const Eigen::Matrix3d H = Eigen::Vector3d(2e4, 2e4, 2e5).asDiagonal();
	for (std::size_t k = 0; k < r.path.size(); ++k)
	{
		if (r.path[k].phi == 0) r.outward = k + 1;	// the way out
		const auto scan = world.scan(r.path[k], 361, aperture, 20.0, 0.005, unsigned(k + 1));
		lc.sync();
		lc.addKeyframe(r.path[k], 100 + k, pmslam::scanToPoints(scan), H, true, k == searchedAt);
	}
	lc.finish();
	const auto& edges = lc.graph().edges();
	for (std::size_t i = 0; i < edges.size(); ++i)
		if (lc.isRevisit(i))
		{
			r.revisits.emplace_back(edges[i].from, edges[i].to);
			r.measured.push_back(edges[i].z);
		}
		else if (edges[i].kind == pmslam::PoseGraphEdgeKind::Loop)
			r.loopTo.push_back(edges[i].to);
	r.stats = lc.stats();
	return r;
}
// Keyframes of the way back with a keyframe of the way out in reach of a revisit edge: at least
// 10 m of path back (minTravel), within 3 m.
std::size_t inReach(const Drive& r)
{
	std::size_t n = 0;
	for (std::size_t k = r.outward; k < r.path.size(); ++k)
	{
		bool reach = false;
		for (std::size_t j = 0; j < r.outward && !reach; ++j)
		{
			const double path = (35.0 - r.path[j].x) + (35.0 - r.path[k].x);	// driven from j to k, about
			reach = path >= 10.0 && std::hypot(r.path[j].x - r.path[k].x, r.path[j].y - r.path[k].y) <= 3.0;
		}
		n += reach;
	}
	return n;
}
}  // namespace

TEST(RevisitEdges, WayBackLinksToWayOutWhereScansOverlap)
{
	// A 360-degree laser sees on the way back what it saw on the way out.
	const Drive r = drive(corridor(), 0, 2 * M_PI);
	ASSERT_GT(r.outward, 60u);
	const std::size_t eligible = inReach(r);
	std::printf("revisit edges %zu of %zu eligible keyframes (stats %zu, detected loop edges %zu)\n", r.revisits.size(),
				eligible, r.stats.revisits, r.stats.accepted);
	EXPECT_EQ(r.stats.revisits, r.revisits.size());
	// Linked from the first detected loop on (the back-end verified the two visits are aligned), then
	// all the way back.
	ASSERT_FALSE(r.loopTo.empty());
	const std::size_t firstLoop = *std::min_element(r.loopTo.begin(), r.loopTo.end());
	EXPECT_GE(r.revisits.size() + (firstLoop - r.outward) + 2, eligible);
	EXPECT_GE(r.revisits.size(), eligible * 3 / 4);
	for (std::size_t i = 0; i < r.revisits.size(); ++i)
	{
		const auto [from, to] = r.revisits[i];
		EXPECT_GE(to, firstLoop) << "revisit edge " << from << " -> " << to << " before any detected loop";
		EXPECT_LT(from, r.outward) << "revisit edge " << from << " -> " << to << " starts on the way back";
		EXPECT_GE(to, r.outward) << "revisit edge " << from << " -> " << to << " ends on the way out";
		const TPose2D& a = r.path[from];
		const TPose2D& b = r.path[to];
		EXPECT_LE(std::hypot(a.x - b.x, a.y - b.y), 3.0 + 1e-9);
		// The relative pose the front-end had (here: the truth).
		const CPose2D truth = CPose2D(b) - CPose2D(a);
		EXPECT_NEAR(r.measured[i].x, truth.x(), 1e-6);
		EXPECT_NEAR(r.measured[i].y, truth.y(), 1e-6);
		EXPECT_NEAR(std::remainder(r.measured[i].phi - truth.phi(), 2 * M_PI), 0, 1e-6);
	}
}

TEST(RevisitEdges, NoneBehindAWall)
{
	// The way back runs 2.7 m from the way out, in reach of its keyframes, but sees the other face
	// of the dividing wall and another corridor.
	const Drive r = drive(twinCorridors(), 2.7, 2 * M_PI);
	const std::size_t eligible = inReach(r);
	std::printf("behind a wall: %zu revisit edges, %zu keyframes of the way back in reach of the way out\n",
				r.revisits.size(), eligible);
	EXPECT_GT(eligible, 50u);
	EXPECT_EQ(r.revisits.size(), 0u);
}

TEST(RevisitEdges, NoneAfterARelocalisationUntilALoopConfirmsIt)
{
	// A keyframe of the way back, after revisit edges have begun, was placed by a re-localisation
	// search: a hypothesis (it may be a look-alike place) until the back-end's own verified loop
	// detection confirms it with a loop that ends after it.
	// Loops detected every 4 m (8 keyframes), so that there is a stretch between search and confirmation.
	const Drive plain = drive(corridor(), 0, 2 * M_PI, SIZE_MAX, 4.0);
	ASSERT_FALSE(plain.revisits.empty());
	const std::size_t searched = plain.revisits.front().second + 4;
	const Drive r = drive(corridor(), 0, 2 * M_PI, searched, 4.0);
	std::size_t confirmed = SIZE_MAX;
	for (std::size_t to : r.loopTo)
		if (to >= searched) confirmed = std::min(confirmed, to);
	ASSERT_NE(confirmed, SIZE_MAX);
	std::size_t plainBetween = 0, between = 0;
	for (const auto& [from, to] : plain.revisits) plainBetween += to >= searched && to < confirmed;
	for (const auto& [from, to] : r.revisits) between += to >= searched && to < confirmed;
	std::printf("re-localised at keyframe %zu, confirmed by a loop at %zu: revisit edges in between %zu (%zu without the "
				"search); %zu in all (%zu)\n",
				searched, confirmed, between, plainBetween, r.revisits.size(), plain.revisits.size());
	// The test drives the case: without the search, that stretch has revisit edges.
	EXPECT_GT(plainBetween, 0u);
	EXPECT_EQ(between, 0u);
	// Confirmed, the rest of the way back links again.
	EXPECT_GE(r.revisits.size() + plainBetween + 1, plain.revisits.size());
}
