/* pmslam — the loop-closure pose graph and its optimisation (see PoseGraph.h). */
#include <pmslam/graph/PoseGraph.h>
#include <pmslam/io/AtomicFile.h>

#include <ceres/ceres.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace pmslam
{
namespace
{
using mrpt::math::TPose2D;
using Graph = mrpt::graphs::CNetworkOfPoses2DInf;

bool finite(const TPose2D& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.phi); }

std::string idText(PoseGraph::NodeId id) { return std::to_string(id); }

double chi2Of(const PoseGraphEdge& e, const std::map<PoseGraph::NodeId, TPose2D>& nodes)
{
	const TPose2D pred = relativePose(nodes.at(e.from), nodes.at(e.to));
	const double r[3] = {pred.x - e.z.x, pred.y - e.z.y, mrpt::math::wrapToPi(pred.phi - e.z.phi)};
	double chi2 = 0;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j) chi2 += r[i] * e.information(i, j) * r[j];
	return chi2;
}

// Residual of one edge for Ceres: sqrt(information) (x_from^-1 (+) x_to - z), the angle wrapped.
struct EdgeResidual
{
	double z[3];
	Eigen::Matrix3d sqrtInfo;
	template <typename T>
	bool operator()(const T* a, const T* b, T* r) const
	{
		using std::cos;
		using std::sin;
		const T c = cos(a[2]), s = sin(a[2]), dx = b[0] - a[0], dy = b[1] - a[1];
		T e[3] = {c * dx + s * dy - z[0], -s * dx + c * dy - z[1], b[2] - a[2] - z[2]};
		const T twoPi = T(2 * M_PI);
		e[2] = e[2] - twoPi * ceres::floor((e[2] + T(M_PI)) / twoPi);
		for (int i = 0; i < 3; ++i) r[i] = T(sqrtInfo(i, 0)) * e[0] + T(sqrtInfo(i, 1)) * e[1] + T(sqrtInfo(i, 2)) * e[2];
		return true;
	}
};

void checkInformation(const mrpt::math::CMatrixDouble33& I, const std::string& what)
{
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			if (!std::isfinite(I(i, j))) throw std::invalid_argument(what + ": information matrix has a non-finite entry");
			const double tol = 1e-9 * (std::abs(I(i, j)) + std::abs(I(j, i))) + 1e-300;
			if (std::abs(I(i, j) - I(j, i)) > tol)
				throw std::invalid_argument(what + ": information matrix is not symmetric");
		}
	Eigen::LLT<Eigen::Matrix3d> llt(I.asEigen());
	if (llt.info() != Eigen::Success) throw std::invalid_argument(what + ": information matrix is not positive definite");
}
}  // namespace

TPose2D relativePose(const TPose2D& a, const TPose2D& b)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi), dx = b.x - a.x, dy = b.y - a.y;
	return {c * dx + s * dy, -s * dx + c * dy, mrpt::math::wrapToPi(b.phi - a.phi)};
}

void PoseGraph::addNode(NodeId id, const TPose2D& pose)
{
	if (id == mrpt::graphs::INVALID_NODEID)
		throw std::invalid_argument("PoseGraph::addNode: id " + idText(id) + " is reserved");
	if (!finite(pose)) throw std::invalid_argument("PoseGraph::addNode(" + idText(id) + "): non-finite pose");
	if (nodes_.count(id)) throw std::invalid_argument("PoseGraph::addNode: node " + idText(id) + " already exists");
	if (nodes_.empty()) fixed_ = id;
	TPose2D p = pose;
	p.phi = mrpt::math::wrapToPi(p.phi);
	nodes_.emplace(id, p);
}

std::size_t PoseGraph::addEdge(NodeId from, NodeId to, const TPose2D& z, const mrpt::math::CMatrixDouble33& information,
							   PoseGraphEdgeKind kind)
{
	const std::string what = "PoseGraph::addEdge(" + idText(from) + " -> " + idText(to) + ")";
	if (!nodes_.count(from)) throw std::invalid_argument(what + ": unknown node " + idText(from));
	if (!nodes_.count(to)) throw std::invalid_argument(what + ": unknown node " + idText(to));
	if (from == to) throw std::invalid_argument(what + ": an edge needs two different nodes");
	if (!finite(z)) throw std::invalid_argument(what + ": non-finite measurement");
	checkInformation(information, what);
	PoseGraphEdge e;
	e.from = from;
	e.to = to;
	e.z = z;
	e.z.phi = mrpt::math::wrapToPi(z.phi);
	e.information = information;
	e.kind = kind;
	edges_.push_back(e);
	return edges_.size() - 1;
}

const TPose2D& PoseGraph::pose(NodeId id) const
{
	const auto it = nodes_.find(id);
	if (it == nodes_.end()) throw std::out_of_range("PoseGraph::pose: unknown node " + idText(id));
	return it->second;
}

void PoseGraph::setPose(NodeId id, const TPose2D& pose)
{
	const auto it = nodes_.find(id);
	if (it == nodes_.end()) throw std::out_of_range("PoseGraph::setPose: unknown node " + idText(id));
	if (!finite(pose)) throw std::invalid_argument("PoseGraph::setPose(" + idText(id) + "): non-finite pose");
	it->second = pose;
	it->second.phi = mrpt::math::wrapToPi(pose.phi);
}

PoseGraph::NodeId PoseGraph::fixedNode() const
{
	if (nodes_.empty()) throw std::logic_error("PoseGraph::fixedNode: the graph is empty");
	return fixed_;
}

void PoseGraph::setFixedNode(NodeId id)
{
	if (!nodes_.count(id)) throw std::out_of_range("PoseGraph::setFixedNode: unknown node " + idText(id));
	fixed_ = id;
}

double PoseGraph::edgeChi2(std::size_t index) const
{
	if (index >= edges_.size()) throw std::out_of_range("PoseGraph::edgeChi2: no edge " + std::to_string(index));
	return chi2Of(edges_[index], nodes_);
}

void PoseGraph::clear()
{
	nodes_.clear();
	edges_.clear();
	fixed_ = 0;
}

void PoseGraph::solveMrpt(const std::map<NodeId, bool>& reached, const PoseGraphOptions& options, PoseGraphStats& stats)
{
	auto activeChi2 = [&] {
		double sum = 0;
		for (const PoseGraphEdge& e : edges_)
			if (!e.rejected) sum += chi2Of(e, nodes_);
		return sum;
	};
	// MRPT's graph of that component, optimised with the fixed node as root.
	Graph g;
	for (const auto& n : reached) g.nodes[n.first] = mrpt::poses::CPose2D(nodes_.at(n.first));
	g.root = fixed_;
	for (const PoseGraphEdge& e : edges_)
		if (!e.rejected && reached.count(e.from))
			g.insertEdge(e.from, e.to,
						 mrpt::poses::CPosePDFGaussianInf(mrpt::poses::CPose2D(e.z), e.information));
	mrpt::containers::yaml params = mrpt::containers::yaml::Map();
	params["max_iterations"] = static_cast<uint64_t>(options.maxIterations);
	params["verbose"] = options.verbose;
	// Stop when a step moves the solution by less than 1e-9 of its norm (MRPT's default, 1e-6, stops a
	// 100 m ring centimetres short of the minimum: the norm is that of all coordinates together).
	params["e2"] = 1e-9;
	// MRPT 2.5's Levenberg-Marquardt does not recover from a rejected step (the retry with a larger lambda
	// builds its matrix from an emptied Hessian, "non-definite positive", until lambda > 1e9): it stops at
	// the first step that would increase the error. Restarted from where it stopped, it rebuilds the
	// Hessian; restarts end when one no longer lowers the error.
	double previous = std::numeric_limits<double>::infinity();
	for (std::size_t restart = 0; restart < 10 && stats.iterations < options.maxIterations * 10; ++restart)
	{
		mrpt::graphslam::TResultInfoSpaLevMarq info{};
		mrpt::graphslam::optimize_graph_spa_levmarq(g, info, nullptr, params);
		stats.iterations += info.num_iters;
		for (const auto& n : g.nodes)
		{
			const TPose2D p(n.second.x(), n.second.y(), mrpt::math::wrapToPi(n.second.phi()));
			if (finite(p)) nodes_[n.first] = p;
		}
		const double now = activeChi2();
		if (!(now < previous * (1 - 1e-9)) || info.num_iters == 0) break;
		previous = now;
		params["initial_lambda"] = 1e-6;  // a restart is near the minimum: start close to Gauss-Newton
	}
}

void PoseGraph::solveCeres(const std::map<NodeId, bool>& reached, const PoseGraphOptions& options, PoseGraphStats& stats)
{
	// One parameter block (x, y, phi) per node of the component; the fixed node held constant.
	std::map<NodeId, std::array<double, 3>> x;
	for (const auto& n : reached)
	{
		const TPose2D& p = nodes_.at(n.first);
		x[n.first] = {p.x, p.y, p.phi};
	}
	ceres::Problem problem;
	for (const PoseGraphEdge& e : edges_)
		if (!e.rejected && reached.count(e.from))
		{
			const Eigen::Matrix3d sqrtInfo = Eigen::LLT<Eigen::Matrix3d>(e.information.asEigen()).matrixU();
			problem.AddResidualBlock(
				new ceres::AutoDiffCostFunction<EdgeResidual, 3, 3, 3>(new EdgeResidual{{e.z.x, e.z.y, e.z.phi}, sqrtInfo}),
				nullptr, x[e.from].data(), x[e.to].data());
		}
	problem.SetParameterBlockConstant(x[fixed_].data());
	ceres::Solver::Options o;
	o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
	o.max_num_iterations = static_cast<int>(options.maxIterations);
	o.num_threads = 1;	// repeatable
	o.function_tolerance = 1e-12;
	o.gradient_tolerance = 1e-14;
	o.parameter_tolerance = 1e-12;
	o.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
	o.minimizer_progress_to_stdout = options.verbose;
	ceres::Solver::Summary summary;
	ceres::Solve(o, &problem, &summary);
	stats.iterations += summary.iterations.size();
	for (const auto& [id, v] : x)
	{
		const TPose2D p(v[0], v[1], mrpt::math::wrapToPi(v[2]));
		if (finite(p)) nodes_[id] = p;
	}
}

PoseGraphStats PoseGraph::optimize(const PoseGraphOptions& options)
{
	const auto t0 = std::chrono::steady_clock::now();
	PoseGraphStats stats;
	auto activeChi2 = [&] {
		double sum = 0;
		for (const PoseGraphEdge& e : edges_)
			if (!e.rejected) sum += chi2Of(e, nodes_);
		return sum;
	};
	stats.initialChi2 = activeChi2();
	std::vector<bool> readmitted(edges_.size(), false);

	for (std::size_t round = 0; round < std::max<std::size_t>(options.maxRounds, 1); ++round)
	{
		// The nodes the active edges link to the fixed node (undirected).
		std::map<NodeId, std::vector<NodeId>> adjacent;
		for (const PoseGraphEdge& e : edges_)
			if (!e.rejected)
			{
				adjacent[e.from].push_back(e.to);
				adjacent[e.to].push_back(e.from);
			}
		std::map<NodeId, bool> reached;
		if (!nodes_.empty())
		{
			std::vector<NodeId> stack{fixed_};
			reached[fixed_] = true;
			while (!stack.empty())
			{
				const NodeId n = stack.back();
				stack.pop_back();
				for (NodeId m : adjacent[n])
					if (!reached[m]) reached[m] = true, stack.push_back(m);
			}
		}
		stats.unconnectedNodes.clear();
		for (const auto& n : nodes_)
			if (!reached.count(n.first)) stats.unconnectedNodes.push_back(n.first);
		if (reached.size() < 2) break;	// nothing to optimise

		if (options.solver == PoseGraphSolver::Ceres)
			solveCeres(reached, options, stats);
		else
			solveMrpt(reached, options, stats);
		++stats.rounds;
		if (!options.rejectOutliers) break;

		// Chi-square test of the loop edges against the optimised poses.
		std::size_t worst = edges_.size(), best = edges_.size();
		double worstChi2 = options.chi2Threshold, bestChi2 = options.chi2Threshold;
		for (std::size_t i = 0; i < edges_.size(); ++i)
		{
			const PoseGraphEdge& e = edges_[i];
			if (e.kind != PoseGraphEdgeKind::Loop) continue;
			const double c = chi2Of(e, nodes_);
			if (!e.rejected && c > worstChi2) worstChi2 = c, worst = i;
			if (e.rejected && !readmitted[i] && c <= bestChi2) bestChi2 = c, best = i;
		}
		if (worst < edges_.size()) edges_[worst].rejected = true;
		else if (best < edges_.size()) edges_[best].rejected = false, readmitted[best] = true;
		else break;
	}
	for (std::size_t i = 0; i < edges_.size(); ++i)
		if (edges_[i].rejected) stats.rejectedEdges.push_back(i);
	stats.finalChi2 = activeChi2();
	stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return stats;
}

void PoseGraph::writeGraphFile(const std::string& path) const
{
	Graph g;
	for (const auto& n : nodes_) g.nodes[n.first] = mrpt::poses::CPose2D(n.second);
	if (!nodes_.empty()) g.root = fixed_;
	std::size_t loops = 0, rejected = 0;
	for (const PoseGraphEdge& e : edges_)
	{
		if (e.rejected) ++rejected;
		else g.insertEdge(e.from, e.to, mrpt::poses::CPosePDFGaussianInf(mrpt::poses::CPose2D(e.z), e.information));
		if (e.kind == PoseGraphEdgeKind::Loop && !e.rejected) ++loops;
	}
	writeFileAtomically(path, [&](std::ostream& os) {
		os.precision(std::numeric_limits<double>::max_digits10);
		os << "# pmslam pose graph: " << nodes_.size() << " nodes, " << edges_.size() - rejected << " edges ("
		   << loops << " loop), " << rejected << " rejected loop edges\n";
		g.writeAsText(os);
		// In (from, to) order, as MRPT writes the edges: a graph read back writes the same bytes.
		std::vector<const PoseGraphEdge*> loopEdges;
		for (const PoseGraphEdge& e : edges_)
			if (e.kind == PoseGraphEdgeKind::Loop) loopEdges.push_back(&e);
		std::stable_sort(loopEdges.begin(), loopEdges.end(), [](const PoseGraphEdge* a, const PoseGraphEdge* b) {
			return std::make_pair(a->from, a->to) < std::make_pair(b->from, b->to);
		});
		for (const PoseGraphEdge* ep : loopEdges)
		{
			const PoseGraphEdge& e = *ep;
			if (!e.rejected)
			{
				os << "# pmslam LOOP " << e.from << ' ' << e.to << '\n';
				continue;
			}
			const auto& I = e.information;
			os << "# pmslam REJECTED EDGE_SE2 " << e.from << ' ' << e.to << ' ' << e.z.x << ' ' << e.z.y << ' '
			   << e.z.phi << ' ' << I(0, 0) << ' ' << I(0, 1) << ' ' << I(0, 2) << ' ' << I(1, 1) << ' ' << I(1, 2)
			   << ' ' << I(2, 2) << '\n';
		}
	});
}

PoseGraph PoseGraph::readGraphFile(const std::string& path)
{
	std::ifstream in(path);
	if (!in) throw std::runtime_error(path + ": cannot open");
	Graph g;
	try
	{
		g.readAsText(in);  // keeps duplicated edges (loadFromTextFile would merge them)
	}
	catch (const std::exception& ex)
	{
		throw std::runtime_error(path + ": " + ex.what());
	}
	if (g.nodes.empty() && !g.edges.empty()) throw std::runtime_error(path + ": edges but no vertices");

	PoseGraph out;
	for (const auto& n : g.nodes)
	{
		const TPose2D p(n.second.x(), n.second.y(), n.second.phi());
		out.addNode(n.first, p);
	}
	if (!g.nodes.empty() && g.nodes.count(g.root)) out.fixed_ = g.root;

	// pmslam's comment lines: which edges are loops, and the rejected ones.
	std::map<std::pair<NodeId, NodeId>, std::size_t> loopCount;
	std::vector<PoseGraphEdge> rejectedEdges;
	in.clear();
	in.seekg(0);
	std::string line;
	std::size_t lineNo = 0;
	while (std::getline(in, line))
	{
		++lineNo;
		std::istringstream s(line);
		std::string hash, tag, kind;
		if (!(s >> hash >> tag >> kind) || hash != "#" || tag != "pmslam") continue;
		NodeId from = 0, to = 0;
		if (kind == "LOOP")
		{
			if (!(s >> from >> to)) throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": bad LOOP line");
			++loopCount[{from, to}];
		}
		else if (kind == "REJECTED")
		{
			std::string key;
			PoseGraphEdge e;
			auto& I = e.information;
			if (!(s >> key >> e.from >> e.to >> e.z.x >> e.z.y >> e.z.phi >> I(0, 0) >> I(0, 1) >> I(0, 2) >> I(1, 1) >>
				  I(1, 2) >> I(2, 2)) ||
				key != "EDGE_SE2")
				throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": bad REJECTED line");
			I(1, 0) = I(0, 1), I(2, 0) = I(0, 2), I(2, 1) = I(1, 2);
			rejectedEdges.push_back(e);
		}
	}
	try
	{
		for (const auto& e : g.edges)
		{
			auto it = loopCount.find(e.first);
			const bool loop = it != loopCount.end() && it->second > 0;
			if (loop) --it->second;
			const auto& pdf = e.second;
			out.addEdge(e.first.first, e.first.second, TPose2D(pdf.mean.x(), pdf.mean.y(), pdf.mean.phi()), pdf.cov_inv,
						loop ? PoseGraphEdgeKind::Loop : PoseGraphEdgeKind::Odometry);
		}
		for (const PoseGraphEdge& e : rejectedEdges)
			out.edges_[out.addEdge(e.from, e.to, e.z, e.information, PoseGraphEdgeKind::Loop)].rejected = true;
	}
	catch (const std::invalid_argument& ex)
	{
		throw std::runtime_error(path + ": " + ex.what());
	}
	return out;
}

}  // namespace pmslam
