/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * PoseGraph: the loop-closure back-end's pose graph and its optimisation.
 *
 * Nodes are 2D poses (keyframes or submap origins) of the robot base in the map
 * frame: x, y in metres, phi in radians (counter-clockwise, normalised to
 * (-pi, pi]). Edges are relative pose measurements: z is the pose of node `to`
 * expressed in the frame of node `from` (x_to = x_from (+) z, MRPT's convention
 * for CNetworkOfPoses), with a 3x3 information matrix (inverse covariance) in
 * that same frame, ordered (x, y, phi): units 1/m^2, 1/(m rad), 1/rad^2. An edge
 * is either an odometry / scan-match edge between consecutive nodes or a loop
 * edge (a closure found by place recognition, which may be wrong).
 *
 * optimize() runs Ceres' sparse Levenberg-Marquardt (the default, chosen by
 * measurement: see PoseGraphOptions::solver) or MRPT's sparse pose adjustment (SPA:
 * mrpt::graphslam::optimize_graph_spa_levmarq on a CNetworkOfPoses2DInf) with
 * the fixed node held in place (the first node added, unless setFixedNode()).
 * Robustness against false loops: after each optimisation every loop edge's
 * residual e (prediction x_from^-1 (+) x_to minus z, angle wrapped) is tested
 * with chi2 = e' * Information * e against the chi-square quantile for 3 degrees
 * of freedom (default 99 %: 11.345). The worst failing active loop edge is
 * disabled and the graph re-optimised (one edge per round: a false loop drags
 * correct neighbours over the threshold too, and must not take them with it);
 * when no active loop edge fails, a rejected loop edge that now passes is
 * re-admitted (best first, once per call). The rounds stop when nothing changes
 * or after maxRounds. Odometry edges are never rejected. Rejected edges stay in
 * the graph, flagged, and are re-tested by the next optimize().
 *
 * Nodes that no active edge chain connects to the fixed node cannot be placed
 * by the optimiser; they keep their poses and are listed in the statistics.
 *
 * Files: writeGraphFile() writes MRPT's .graph text format with MRPT's own
 * writer (CNetworkOfPoses::writeAsText: VERTEX_SE2 id x y phi, FIX id,
 * EDGE_SE2 from to x y phi I_xx I_xy I_xphi I_yy I_yphi I_phiphi — the g2o
 * layout, which is what MRPT 2.5 writes and reads for EDGE2 too), with 17
 * significant digits so a file read back is exact, atomically (io/AtomicFile).
 * Active edges only; comment lines (which MRPT's reader skips) add what the
 * format cannot hold: "# pmslam LOOP from to" for each loop edge and
 * "# pmslam REJECTED EDGE_SE2 ..." for each rejected one. MRPT's graph-slam
 * program reads the file (graph-slam --2d --levmarq -i FILE -o OUT).
 */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace pmslam
{
enum class PoseGraphEdgeKind
{
	Odometry,  // odometry or scan matching between consecutive nodes: trusted
	Loop	   // loop closure: tested, may be rejected
};

struct PoseGraphEdge
{
	std::uint64_t from = 0, to = 0;
	mrpt::math::TPose2D z;					  // pose of `to` in the frame of `from` (m, rad)
	mrpt::math::CMatrixDouble33 information;  // inverse covariance of z, (x, y, phi)
	PoseGraphEdgeKind kind = PoseGraphEdgeKind::Odometry;
	bool rejected = false;	// a loop edge the last optimize() disabled
};

enum class PoseGraphSolver
{
	Ceres,	// Ceres' sparse Levenberg-Marquardt (SPARSE_NORMAL_CHOLESKY, automatic derivatives): the default
	Mrpt	// MRPT's sparse pose adjustment (optimize_graph_spa_levmarq)
};

struct PoseGraphOptions
{
	/** Ceres: 64 ms on a 5 000-node ring and 0.26 s on 20 000, against MRPT's 0.63 s and 19.9 s, the same
	 * solution (bench/ceres_pose_graph.cpp, bench/bench_pose_graph.cpp). */
	PoseGraphSolver solver = PoseGraphSolver::Ceres;
	std::size_t maxIterations = 100;  // Levenberg-Marquardt iterations per optimisation
	bool rejectOutliers = true;		  // chi-square test of loop edges (see the file comment)
	double chi2Threshold = 11.345;	  // chi-square quantile, 3 dof: 99 % (95 %: 7.815)
	std::size_t maxRounds = 10;		  // optimisations per optimize() call, at most
	bool verbose = false;			  // MRPT's optimiser prints its iterations to stdout
};

struct PoseGraphStats
{
	std::size_t rounds = 0;		 // optimisations run (0: nothing to optimise)
	std::size_t iterations = 0;	 // Levenberg-Marquardt iterations, all rounds together
	double seconds = 0;			 // wall time of optimize()
	double initialChi2 = 0;		 // sum of e' I e over the active edges, before
	double finalChi2 = 0;		 // the same after (rejected edges excluded)
	std::vector<std::size_t> rejectedEdges;		// indices into edges(), rejected after this call
	std::vector<std::uint64_t> unconnectedNodes;  // not linked to the fixed node: left where they were
};

/** The pose of `b` in the frame of `a`: a^-1 (+) b, its heading wrapped to (-pi, pi]. */
mrpt::math::TPose2D relativePose(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b);

class PoseGraph
{
   public:
	using NodeId = std::uint64_t;

	/** Adds a node with its initial pose estimate. The first node added becomes
	 * the fixed node. Throws std::invalid_argument for an id already present,
	 * the reserved id UINT64_MAX or a non-finite pose. */
	void addNode(NodeId id, const mrpt::math::TPose2D& pose);

	/** Adds an edge and returns its index in edges(). Throws
	 * std::invalid_argument for an unknown node, from == to, a non-finite z, or
	 * an information matrix that is not symmetric positive definite. */
	std::size_t addEdge(NodeId from, NodeId to, const mrpt::math::TPose2D& z,
						const mrpt::math::CMatrixDouble33& information,
						PoseGraphEdgeKind kind = PoseGraphEdgeKind::Odometry);

	/** Optimises the node poses (see the file comment). An empty graph, a single
	 * node or a graph without edges is a no-op (rounds == 0). */
	PoseGraphStats optimize(const PoseGraphOptions& options = {});

	bool empty() const { return nodes_.empty(); }
	std::size_t nodeCount() const { return nodes_.size(); }
	std::size_t edgeCount() const { return edges_.size(); }
	bool hasNode(NodeId id) const { return nodes_.count(id) != 0; }

	/** Current (after optimize(): optimised) pose. Throws std::out_of_range. */
	const mrpt::math::TPose2D& pose(NodeId id) const;
	/** Overwrites a node's pose estimate (e.g. a new initial guess). */
	void setPose(NodeId id, const mrpt::math::TPose2D& pose);
	const std::map<NodeId, mrpt::math::TPose2D>& poses() const { return nodes_; }
	const std::vector<PoseGraphEdge>& edges() const { return edges_; }

	/** The node held fixed by optimize(). Throws std::logic_error when empty. */
	NodeId fixedNode() const;
	void setFixedNode(NodeId id);

	/** chi2 = e' I e of edge `index` against the current poses. */
	double edgeChi2(std::size_t index) const;

	/** Writes the graph in MRPT's .graph text format (see the file comment).
	 * Throws std::runtime_error on an I/O failure (the old file is kept). */
	void writeGraphFile(const std::string& path) const;

	/** Reads a .graph file (2D: VERTEX2/VERTEX_SE2, EDGE2/EDGE_SE2, FIX, with
	 * pmslam's comment lines restoring loop kinds and rejected edges). Throws
	 * std::runtime_error naming the file on a missing file or a malformed line. */
	static PoseGraph readGraphFile(const std::string& path);

	void clear();

   private:
	// One optimisation of the nodes in `reached` (the fixed node's component), in place.
	void solveMrpt(const std::map<NodeId, bool>& reached, const PoseGraphOptions& options, PoseGraphStats& stats);
	void solveCeres(const std::map<NodeId, bool>& reached, const PoseGraphOptions& options, PoseGraphStats& stats);
	std::map<NodeId, mrpt::math::TPose2D> nodes_;
	std::vector<PoseGraphEdge> edges_;
	NodeId fixed_ = 0;
};

}  // namespace pmslam
