// PoseGraph: optimisation of a synthetic ring (100 m x 80 m, 200 nodes) closed by loop edges, rejection of false
// loops, the .graph file (round trip, MRPT's reader and MRPT's graph-slam program), and the edge cases.
#include <gtest/gtest.h>
#include <pmslam/graph/PoseGraph.h>

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "RingGraph.h"

namespace fs = std::filesystem;
using namespace pmslam;
using mrpt::math::TPose2D;

namespace
{
class PoseGraphTest : public ::testing::Test
{
   protected:
	void SetUp() override
	{
		const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
		m_dir = fs::temp_directory_path() / ("pmslam_test_pose_graph_" + std::to_string(::getpid()) + "_" + info->name());
		fs::remove_all(m_dir);
		fs::create_directories(m_dir);
	}
	void TearDown() override
	{
		if (!HasFailure()) fs::remove_all(m_dir);
	}
	std::string path(const std::string& name) const { return (m_dir / name).string(); }
	fs::path m_dir;
};

// The ring's closure: the last nodes seen again from the first ones (the robot is back at the start).
void addCorrectLoops(test::Ring& r)
{
	for (std::size_t k = 0; k < 5; ++k) r.addLoop(199 - k, k);	// 199->0, 198->1, ... (1.8 m to 16 m apart)
}

// Look-alike places: consistent-looking loop edges (loop information) 2-5 m off the truth.
std::vector<std::size_t> addFalseLoops(test::Ring& r)
{
	return {r.addLoop(185, 10, {3.0, 0.0, 0.0}), r.addLoop(100, 120, {0.0, 2.5, 0.02}),
			r.addLoop(30, 60, {-4.0, 2.0, 0.0})};
}

TEST_F(PoseGraphTest, RingClosesWithCorrectLoops)
{
	test::Ring r = test::makeRing({});
	addCorrectLoops(r);
	double maxBefore, rmsBefore;
	r.positionError(maxBefore, rmsBefore);
	EXPECT_GT(maxBefore, 10.0);	 // the unoptimised drift: metres

	const PoseGraphStats st = r.graph.optimize();
	double maxAfter, rmsAfter;
	r.positionError(maxAfter, rmsAfter);
	std::printf("drift max %.2f m rms %.2f m -> optimised max %.4f m rms %.4f m; %zu rounds, %zu iterations, %.1f ms, "
				"chi2 %.3g -> %.3g\n",
				maxBefore, rmsBefore, maxAfter, rmsAfter, st.rounds, st.iterations, 1e3 * st.seconds, st.initialChi2,
				st.finalChi2);
	EXPECT_LT(maxAfter, 0.05);
	EXPECT_LT(rmsAfter, 0.03);
	EXPECT_TRUE(st.rejectedEdges.empty());
	EXPECT_TRUE(st.unconnectedNodes.empty());
	EXPECT_GE(st.rounds, 1u);
	EXPECT_GT(st.iterations, 0u);
	EXPECT_LT(st.finalChi2, st.initialChi2);
	// The fixed node has not moved.
	EXPECT_EQ(r.graph.fixedNode(), 0u);
	EXPECT_DOUBLE_EQ(r.graph.pose(0).x, 0.0);
	EXPECT_DOUBLE_EQ(r.graph.pose(0).y, 0.0);
	EXPECT_DOUBLE_EQ(r.graph.pose(0).phi, 0.0);
	// Consistent: the information covers the odometry's error (bias included), chi2 below 1 per edge.
	EXPECT_LT(st.finalChi2, double(r.graph.edgeCount()));
}

TEST_F(PoseGraphTest, FalseLoopsAreRejected)
{
	test::Ring r = test::makeRing({});
	addCorrectLoops(r);
	PoseGraph reference = r.graph;	// the correct loops alone
	const PoseGraphStats refStats = reference.optimize();
	const std::vector<std::size_t> wrong = addFalseLoops(r);

	// Without the test, the false loops wreck the ring.
	{
		PoseGraph g = r.graph;
		PoseGraphOptions o;
		o.rejectOutliers = false;
		std::swap(g, r.graph);
		r.graph.optimize(o);
		double maxError, rmsError;
		r.positionError(maxError, rmsError);
		std::printf("false loops kept: max %.3f m rms %.3f m\n", maxError, rmsError);
		EXPECT_GT(maxError, 0.5);
		std::swap(g, r.graph);
	}

	PoseGraphOptions verbose;
	verbose.verbose = std::getenv("PMSLAM_VERBOSE") != nullptr;
	const PoseGraphStats st = r.graph.optimize(verbose);
	double maxAfter, rmsAfter;
	r.positionError(maxAfter, rmsAfter);
	std::printf("false loops rejected: max %.4f m rms %.4f m; %zu rounds, %zu iterations, %.1f ms\n", maxAfter, rmsAfter,
				st.rounds, st.iterations, 1e3 * st.seconds);
	std::vector<std::size_t> rejected = st.rejectedEdges;
	std::sort(rejected.begin(), rejected.end());
	EXPECT_EQ(rejected, wrong);
	for (std::size_t i : wrong) EXPECT_TRUE(r.graph.edges()[i].rejected);
	for (std::size_t i = 0; i < r.graph.edgeCount(); ++i)
	{
		if (std::find(wrong.begin(), wrong.end(), i) == wrong.end())
		{
			EXPECT_FALSE(r.graph.edges()[i].rejected) << i;
		}
	}
	EXPECT_LT(maxAfter, 0.05);
	EXPECT_LT(rmsAfter, 0.03);
	for (std::size_t i : wrong) EXPECT_GT(r.graph.edgeChi2(i), 11.345);
	// As good as without the false loops: the same solution.
	double maxDiff = 0;
	for (const auto& n : reference.poses())
		maxDiff = std::max(maxDiff, std::hypot(r.graph.pose(n.first).x - n.second.x, r.graph.pose(n.first).y - n.second.y));
	std::printf("chi2 %.6g, without the false loops %.6g; poses differ by %.4f m at most\n", st.finalChi2, refStats.finalChi2, maxDiff);
	// The same minimum (chi2), up to the ring's weakly observed bending (within the odometry's error model).
	EXPECT_NEAR(st.finalChi2, refStats.finalChi2, 0.01 * refStats.finalChi2);
	EXPECT_LT(maxDiff, 0.03);

	// Re-optimising keeps the decision (the rejected edges are re-tested and fail again).
	const PoseGraphStats again = r.graph.optimize();
	rejected = again.rejectedEdges;
	std::sort(rejected.begin(), rejected.end());
	EXPECT_EQ(rejected, wrong);
}

TEST_F(PoseGraphTest, WronglyRejectedEdgeIsReadmitted)
{
	// A correct loop edge flagged rejected (as an earlier optimize() may leave it, and as a file keeps it) passes
	// the test against the graph the other loops close, and is re-admitted.
	test::Ring r = test::makeRing({});
	addCorrectLoops(r);
	const PoseGraph unoptimised = r.graph;
	r.graph.optimize();

	// A file with the last loop edge as a REJECTED comment line (the way pmslam writes rejected edges).
	const std::string file = path("flagged.graph");
	PoseGraph w;
	for (const auto& n : unoptimised.poses()) w.addNode(n.first, n.second);
	const std::size_t last = unoptimised.edgeCount() - 1;
	for (std::size_t i = 0; i < last; ++i)
	{
		const PoseGraphEdge& e = unoptimised.edges()[i];
		w.addEdge(e.from, e.to, e.z, e.information, e.kind);
	}
	w.writeGraphFile(file);
	{
		const PoseGraphEdge& e = unoptimised.edges()[last];
		std::ofstream f(file, std::ios::app);
		f.precision(17);
		f << "# pmslam REJECTED EDGE_SE2 " << e.from << ' ' << e.to << ' ' << e.z.x << ' ' << e.z.y << ' ' << e.z.phi
		  << ' ' << e.information(0, 0) << " 0 0 " << e.information(1, 1) << " 0 " << e.information(2, 2) << '\n';
	}
	PoseGraph back = PoseGraph::readGraphFile(file);
	ASSERT_EQ(back.edgeCount(), unoptimised.edgeCount());
	EXPECT_TRUE(back.edges().back().rejected);
	EXPECT_EQ(back.edges().back().kind, PoseGraphEdgeKind::Loop);
	const PoseGraphStats st = back.optimize();
	EXPECT_TRUE(st.rejectedEdges.empty());
	EXPECT_FALSE(back.edges().back().rejected);
	for (const auto& n : r.graph.poses())
	{
		EXPECT_NEAR(back.pose(n.first).x, n.second.x, 1e-4);
		EXPECT_NEAR(back.pose(n.first).y, n.second.y, 1e-4);
	}
}

void expectSameGraph(const PoseGraph& a, const PoseGraph& b, double tol)
{
	ASSERT_EQ(a.nodeCount(), b.nodeCount());
	ASSERT_EQ(a.edgeCount(), b.edgeCount());
	EXPECT_EQ(a.fixedNode(), b.fixedNode());
	for (const auto& n : a.poses())
	{
		ASSERT_TRUE(b.hasNode(n.first)) << n.first;
		EXPECT_NEAR(b.pose(n.first).x, n.second.x, tol);
		EXPECT_NEAR(b.pose(n.first).y, n.second.y, tol);
		EXPECT_NEAR(b.pose(n.first).phi, n.second.phi, tol);
	}
	// The file orders the edges by (from, to); compare in that order.
	auto sorted = [](const PoseGraph& g) {
		std::vector<PoseGraphEdge> e = g.edges();
		std::stable_sort(e.begin(), e.end(), [](const PoseGraphEdge& x, const PoseGraphEdge& y) {
			return std::make_tuple(x.rejected, x.from, x.to) < std::make_tuple(y.rejected, y.from, y.to);
		});
		return e;
	};
	const auto ea = sorted(a), eb = sorted(b);
	for (std::size_t i = 0; i < ea.size(); ++i)
	{
		EXPECT_EQ(ea[i].from, eb[i].from) << i;
		EXPECT_EQ(ea[i].to, eb[i].to) << i;
		EXPECT_EQ(ea[i].kind, eb[i].kind) << i;
		EXPECT_EQ(ea[i].rejected, eb[i].rejected) << i;
		EXPECT_NEAR(ea[i].z.x, eb[i].z.x, tol) << i;
		EXPECT_NEAR(ea[i].z.y, eb[i].z.y, tol) << i;
		EXPECT_NEAR(ea[i].z.phi, eb[i].z.phi, tol) << i;
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 3; ++c)
				EXPECT_NEAR(ea[i].information(r, c), eb[i].information(r, c), tol * std::abs(ea[i].information(r, c)))
					<< i;
	}
}

TEST_F(PoseGraphTest, GraphFileRoundTrip)
{
	test::Ring r = test::makeRing({});
	addCorrectLoops(r);
	addFalseLoops(r);
	r.graph.optimize();	 // three rejected edges, kept as comments
	const std::string file = path("ring.graph");
	r.graph.writeGraphFile(file);
	EXPECT_FALSE(fs::exists(file + ".tmp." + std::to_string(::getpid())));

	// pmslam's reader: the same graph, exactly (17 significant digits).
	const PoseGraph back = PoseGraph::readGraphFile(file);
	expectSameGraph(r.graph, back, 1e-12);

	// MRPT's own reader: the vertices, the root and the active edges.
	mrpt::graphs::CNetworkOfPoses2DInf g;
	g.loadFromTextFile(file, false);
	EXPECT_EQ(g.nodes.size(), r.graph.nodeCount());
	EXPECT_EQ(g.edges.size(), r.graph.edgeCount() - 3);
	EXPECT_EQ(g.root, 0u);
	for (const auto& n : g.nodes)
	{
		EXPECT_DOUBLE_EQ(n.second.x(), r.graph.pose(n.first).x);
		EXPECT_DOUBLE_EQ(n.second.y(), r.graph.pose(n.first).y);
	}
	const PoseGraphEdge& e0 = r.graph.edges()[0];
	const auto it = g.edges.find({e0.from, e0.to});
	ASSERT_NE(it, g.edges.end());
	EXPECT_DOUBLE_EQ(it->second.mean.x(), e0.z.x);
	EXPECT_DOUBLE_EQ(it->second.cov_inv(2, 2), e0.information(2, 2));

	// Writing again gives the same bytes.
	back.writeGraphFile(path("again.graph"));
	std::ifstream f1(file), f2(path("again.graph"));
	const std::string s1((std::istreambuf_iterator<char>(f1)), {}), s2((std::istreambuf_iterator<char>(f2)), {});
	EXPECT_EQ(s1, s2);
}

TEST_F(PoseGraphTest, MrptGraphSlamProgramReadsTheFile)
{
	const char* program = "/usr/bin/graph-slam";
	if (!fs::exists(program)) GTEST_SKIP() << program << " not installed (package mrpt-apps)";
	test::Ring r = test::makeRing({});
	addCorrectLoops(r);
	const std::string in = path("in.graph"), out = path("out.graph");
	r.graph.writeGraphFile(in);
	const std::string cmd = "env -u DISPLAY timeout 60 " + std::string(program) + " --2d --levmarq -q -i '" + in +
							"' -o '" + out + "' > '" + path("log.txt") + "' 2>&1";
	ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
	ASSERT_TRUE(fs::exists(out));
	const PoseGraph result = PoseGraph::readGraphFile(out);
	EXPECT_EQ(result.nodeCount(), r.graph.nodeCount());
	EXPECT_EQ(result.edgeCount(), r.graph.edgeCount());
	EXPECT_EQ(result.fixedNode(), 0u);
	// graph-slam optimised the graph it read: the ring is closed (it weighs every edge alike, ignoring the
	// information matrices, so its solution is not pmslam's: only the gross drift is checked).
	double maxBefore, rms;
	r.positionError(maxBefore, rms);
	test::Ring closed = r;
	closed.graph = result;
	double maxAfter;
	closed.positionError(maxAfter, rms);
	std::printf("graph-slam --levmarq: max error %.2f m -> %.2f m\n", maxBefore, maxAfter);
	EXPECT_LT(maxAfter, maxBefore / 3);
}

TEST_F(PoseGraphTest, EmptyGraph)
{
	PoseGraph g;
	EXPECT_TRUE(g.empty());
	const PoseGraphStats st = g.optimize();
	EXPECT_EQ(st.rounds, 0u);
	EXPECT_EQ(st.iterations, 0u);
	EXPECT_TRUE(st.rejectedEdges.empty());
	EXPECT_THROW(g.fixedNode(), std::logic_error);
	EXPECT_THROW(g.pose(0), std::out_of_range);
	EXPECT_THROW(g.edgeChi2(0), std::out_of_range);
	EXPECT_THROW(g.setFixedNode(0), std::out_of_range);
	g.writeGraphFile(path("empty.graph"));
	const PoseGraph back = PoseGraph::readGraphFile(path("empty.graph"));
	EXPECT_TRUE(back.empty());
	EXPECT_EQ(back.edgeCount(), 0u);
}

TEST_F(PoseGraphTest, SingleNode)
{
	PoseGraph g;
	g.addNode(7, {1.5, -2.0, 0.3});
	EXPECT_EQ(g.fixedNode(), 7u);
	const PoseGraphStats st = g.optimize();
	EXPECT_EQ(st.rounds, 0u);
	EXPECT_TRUE(st.unconnectedNodes.empty());
	EXPECT_DOUBLE_EQ(g.pose(7).x, 1.5);
	EXPECT_DOUBLE_EQ(g.pose(7).phi, 0.3);
	g.writeGraphFile(path("one.graph"));
	const PoseGraph back = PoseGraph::readGraphFile(path("one.graph"));
	expectSameGraph(g, back, 0);
}

TEST_F(PoseGraphTest, DisconnectedNodeIsLeftAlone)
{
	// Three nodes in a chain with a closing loop, and node 9 that no edge reaches; a second island 20-21.
	PoseGraph g;
	const auto info = test::diagonalInformation(0.01, 0.001);
	g.addNode(0, {0, 0, 0});
	g.addNode(1, {1.2, 0.1, 0});
	g.addNode(2, {2.1, -0.1, 0});
	g.addNode(9, {50, 50, 1});
	g.addNode(20, {-5, 0, 0});
	g.addNode(21, {-3, 0, 0});
	g.addEdge(0, 1, {1, 0, 0}, info);
	g.addEdge(1, 2, {1, 0, 0}, info);
	g.addEdge(0, 2, {2, 0, 0}, info, PoseGraphEdgeKind::Loop);
	g.addEdge(20, 21, {1, 0, 0}, info);
	const PoseGraphStats st = g.optimize();
	EXPECT_EQ(st.rounds, 1u);
	EXPECT_EQ(st.unconnectedNodes, (std::vector<std::uint64_t>{9, 20, 21}));
	EXPECT_NEAR(g.pose(1).x, 1.0, 1e-6);
	EXPECT_NEAR(g.pose(2).x, 2.0, 1e-6);
	EXPECT_NEAR(g.pose(2).y, 0.0, 1e-6);
	EXPECT_DOUBLE_EQ(g.pose(9).x, 50.0);
	EXPECT_DOUBLE_EQ(g.pose(9).phi, 1.0);
	EXPECT_DOUBLE_EQ(g.pose(20).x, -5.0);
	EXPECT_DOUBLE_EQ(g.pose(21).x, -3.0);

	// Only nodes without edges: nothing to optimise.
	PoseGraph lone;
	lone.addNode(0, {0, 0, 0});
	lone.addNode(1, {1, 0, 0});
	const PoseGraphStats st2 = lone.optimize();
	EXPECT_EQ(st2.rounds, 0u);
	EXPECT_EQ(st2.unconnectedNodes, (std::vector<std::uint64_t>{1}));
}

TEST_F(PoseGraphTest, InvalidInputIsRefused)
{
	PoseGraph g;
	const auto info = test::diagonalInformation(0.01, 0.001);
	const double nan = std::numeric_limits<double>::quiet_NaN();
	g.addNode(0, {0, 0, 0});
	g.addNode(1, {1, 0, 0});
	EXPECT_THROW(g.addNode(1, {0, 0, 0}), std::invalid_argument);
	EXPECT_THROW(g.addNode(2, {nan, 0, 0}), std::invalid_argument);
	EXPECT_THROW(g.addNode(std::numeric_limits<std::uint64_t>::max(), {0, 0, 0}), std::invalid_argument);
	EXPECT_THROW(g.addEdge(0, 5, {1, 0, 0}, info), std::invalid_argument);
	EXPECT_THROW(g.addEdge(1, 1, {0, 0, 0}, info), std::invalid_argument);
	EXPECT_THROW(g.addEdge(0, 1, {1, nan, 0}, info), std::invalid_argument);
	mrpt::math::CMatrixDouble33 bad = info;
	bad(2, 2) = 0;	// singular
	EXPECT_THROW(g.addEdge(0, 1, {1, 0, 0}, bad), std::invalid_argument);
	bad = info;
	bad(0, 1) = 5;	// not symmetric
	EXPECT_THROW(g.addEdge(0, 1, {1, 0, 0}, bad), std::invalid_argument);
	bad = info;
	bad(0, 0) = -1;	 // not positive
	EXPECT_THROW(g.addEdge(0, 1, {1, 0, 0}, bad), std::invalid_argument);
	EXPECT_EQ(g.edgeCount(), 0u);
	EXPECT_THROW(g.setPose(3, {0, 0, 0}), std::out_of_range);
	EXPECT_THROW(g.setPose(1, {0, nan, 0}), std::invalid_argument);

	EXPECT_THROW(PoseGraph::readGraphFile(path("missing.graph")), std::runtime_error);
	std::ofstream(path("bad.graph")) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0\n";
	EXPECT_THROW(PoseGraph::readGraphFile(path("bad.graph")), std::runtime_error);
	std::ofstream(path("dangling.graph")) << "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 4 1 0 0 1 0 0 1 0 1\n";
	EXPECT_THROW(PoseGraph::readGraphFile(path("dangling.graph")), std::runtime_error);
}

}  // namespace
