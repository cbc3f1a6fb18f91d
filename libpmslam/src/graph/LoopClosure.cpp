/* pmslam — the loop-closure back-end (see LoopClosure.h). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/graph/KeyframeProbe.h>
#include <pmslam/graph/LoopClosure.h>
#include <malloc.h>
#include <pmslam/match/BranchAndBoundSearch.h>
#include <pmslam/match/CorrelativeSearch.h>
#include <pmslam/sensor/SeenThrough.h>
#include <pmslam/util/Concurrently.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <unordered_set>

namespace pmslam
{
namespace
{
using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;

TPose2D compose(const TPose2D& a, const TPose2D& b) { return (CPose2D(a) + CPose2D(b)).asTPose(); }
double distance(const TPose2D& a, const TPose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }
// The distance of a and b if it is at most r (the box test first: this runs over every keyframe, at every one).
std::optional<double> distanceWithin(const TPose2D& a, const TPose2D& b, double r)
{
	if (std::abs(a.x - b.x) > r || std::abs(a.y - b.y) > r) return std::nullopt;
	const double d = distance(a, b);
	return d <= r ? std::optional<double>(d) : std::nullopt;
}
bool within(const TPose2D& d, double linear, double angular) { return std::hypot(d.x, d.y) <= linear && std::abs(d.phi) <= angular; }

mrpt::math::CMatrixDouble33 toMrpt(const Eigen::Matrix3d& m)
{
	mrpt::math::CMatrixDouble33 r;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j) r(i, j) = 0.5 * (m(i, j) + m(j, i));
	return r;
}

// m: a search window up to which agreeingMatches verified matches, and 4 refined peaks, are enough.
constexpr double kWideWindow = 4.0;

// Local maps for verification (D50): built over whole chunks of kLocalMapChunk metres of path and with a
// distance layer whose reach is rounded up to kReachStep metres, so that attempts a metre or two apart share one;
// the last kCachedLocalMaps (two visits are verified per attempt) are kept.
constexpr double kLocalMapChunk = 4.0, kReachStep = 0.25;
constexpr std::size_t kCachedLocalMaps = 4;
// The keyframes that say which returns of a keyframe moved (returnsThatStayed): the last few before
// it, taken within seconds and metres of it, where their relative poses are the front-end's own.
constexpr std::size_t kSeenThroughKeyframes = 3;
constexpr double kSeenThroughSeconds = 10.0, kSeenThroughDistance = 3.0;

// The blocks of `all` (frozen) west of the middle one's column, and the others (both frozen).
std::array<BlockMask, 2> splitWestEast(const BlockMask& all)
{
	std::vector<int> columns;
	all.forEach([&](int bx, int) { columns.push_back(bx); });
	std::array<BlockMask, 2> halves;
	if (!columns.empty())
	{
		std::nth_element(columns.begin(), columns.begin() + columns.size() / 2, columns.end());
		const int middle = columns[columns.size() / 2];
		all.forEach([&](int bx, int by) { halves[bx < middle ? 0 : 1].add(bx, by); });
	}
	for (auto& h : halves) h.freeze();
	return halves;
}

// A whole-map search (D46): the distinct places taken (within 0.8 of the best's score), the window each is
// verified in (the coarse-to-fine search's places are exact on its lattice; PM refines within a cell or two),
// and how near a keyframe from before the loss must be to a place for its visit's local map to hold it.
constexpr std::size_t kGlobalPlaces = 3;
constexpr double kGlobalWindow = 1.0, kGlobalAngle = 10.0 * M_PI / 180, kGlobalVisitRadius = 5.0;

// The whole map asked for a keyframe's places after lost tracking (D46): the few within 0.8 of the best.
BranchAndBoundSearch::Options globalSearchOptions() { return BranchAndBoundSearch::Options::wholeMap(kGlobalPlaces, 0.8); }

// m: the lever arm at which a heading error counts as a displacement (what a turn moves at 5 m from the robot).
constexpr double kDoubtLever = 5.0;

// A loose information for a loop edge along directions the scan does not fix (a corridor):
// 1 m and 30 degrees, enough to keep the matrix positive definite without pulling.
const Eigen::Matrix3d kLoopFloor = Eigen::Vector3d(1.0, 1.0, 1.0 / std::pow(30.0 * M_PI / 180, 2)).asDiagonal();
}  // namespace

LoopClosure::LoopClosure(const LoopClosureOptions& options, const PerfectMatchMatcher::TConfigParams& matcher,
						 const OccupancyGridUpdateOptions& grid)
	: m_opts(options), m_gridOpts(grid), m_matcher(matcher)
{
}

LoopClosure::~LoopClosure()
{
	if (m_job.valid()) m_job.wait();
}

void LoopClosure::addFixedScan(const TPose2D& pose, ScanPoints scan) { m_fixed.emplace_back(pose, std::move(scan)); }

namespace
{
float reachOf(const ScanPoints& scan)
{
	float reach = 0;
	for (const auto* pts : {&scan.hits, &scan.freeEnds})
		for (const auto& p : *pts) reach = std::max(reach, std::hypot(p.x, p.y));
	return reach + static_cast<float>(std::hypot(scan.sensorOrigin.x, scan.sensorOrigin.y));
}

bool coversExactly(const PoseGraph* graph, std::size_t n)
{
	if (!graph || graph->nodeCount() != n) return false;
	for (std::size_t i = 0; i < n; ++i)
		if (!graph->hasNode(i)) return false;
	return true;
}
}  // namespace

void LoopClosure::addPriorKeyframes(std::vector<PriorKeyframe> keyframes, const PoseGraph* graph)
{
	if (!m_nodes.empty()) throw std::logic_error("LoopClosure::addPriorKeyframes: after addKeyframe()");
	const bool withEdges = coversExactly(graph, keyframes.size());
	for (std::size_t id = 0; id < keyframes.size(); ++id)
	{
		auto& k = keyframes[id];
		double travel = 0;
		m_graph.addNode(id, k.pose);
		if (id > 0)
		{
			const TPose2D z = relativePose(m_nodes.back().mapPose, k.pose);
			travel = m_nodes.back().travel + std::hypot(z.x, z.y);
			if (!withEdges) m_graph.addEdge(id - 1, id, z, toMrpt(odometryInformation(z, 1.0)));
		}
		k.scan.hits.shrink_to_fit();
		k.scan.freeEnds.shrink_to_fit();
		const float reach = reachOf(k.scan);
		m_nodes.push_back({travel, k.timestamp, std::make_shared<const ScanPoints>(std::move(k.scan)), k.pose, reach});
		m_published.push_back(k.pose);
	}
	if (withEdges)
		for (const auto& e : graph->edges())
			if (!e.rejected) m_graph.addEdge(e.from, e.to, e.z, e.information, e.kind);
	m_isRevisit.assign(m_graph.edgeCount(), false);
	m_checkedEdges = m_graph.edgeCount();  // optimised already, in their own session
	m_priorCount = m_nodes.size();
	// The new session starts anchored: its start was found on these keyframes' map.
	if (!m_nodes.empty()) m_lastAnchor = m_lastClosure = m_nodes.back().travel;
}

PoseGraph LoopClosure::graphWithout(const std::vector<bool>& retired) const
{
	const auto gone = [&](std::size_t i) { return i < retired.size() && retired[i]; };
	std::vector<std::size_t> newId(m_nodes.size(), SIZE_MAX);
	PoseGraph out;
	std::size_t next = 0;
	for (std::size_t i = 0; i < m_nodes.size(); ++i)
		if (!gone(i)) out.addNode(newId[i] = next++, m_graph.pose(i));
	for (const auto& e : m_graph.edges())
		if (!e.rejected && !gone(e.from) && !gone(e.to)) out.addEdge(newId[e.from], newId[e.to], e.z, e.information, e.kind);
	// The chain across retired nodes: the kept one before them to the kept one after, as the graph has them.
	std::size_t last = SIZE_MAX;
	for (std::size_t i = 0; i < m_nodes.size(); ++i)
	{
		if (gone(i)) continue;
		if (last != SIZE_MAX && i > last + 1)
		{
			const TPose2D z = relativePose(m_graph.pose(last), m_graph.pose(i));
			out.addEdge(newId[last], newId[i], z, toMrpt(odometryInformation(z, 1.0)));
		}
		last = i;
	}
	return out;
}

std::size_t LoopClosure::nearestNode(const TPose2D& pose) const
{
	std::size_t best = 0;
	double bestD = std::numeric_limits<double>::infinity();
	for (std::size_t i = 0; i < m_nodes.size(); ++i)
	{
		const double d = std::hypot(m_nodes[i].mapPose.x - pose.x, m_nodes[i].mapPose.y - pose.y);
		if (d < bestD) best = i, bestD = d;
	}
	return best;
}

Eigen::Matrix3d LoopClosure::odometryInformation(const TPose2D& z, double scale) const
{
	const double sl = scale * (m_opts.odometrySigmaLinear + m_opts.odometrySigmaPerMeter * std::hypot(z.x, z.y));
	const double sa = scale * (m_opts.odometrySigmaAngular + m_opts.odometrySigmaPerRadian * std::abs(z.phi));
	return Eigen::Vector3d(1 / (sl * sl), 1 / (sl * sl), 1 / (sa * sa)).asDiagonal();
}

double LoopClosure::untrackedDoubt(const TPose2D& z) const
{
	// Three sigmas of the loose odometry edge across lost tracking (addKeyframe), its heading at the
	// 5 m lever arm with which a turn moves what the robot sees.
	constexpr double kScale = 5.0, kLever = kDoubtLever;
	const double sl = kScale * (m_opts.odometrySigmaLinear + m_opts.odometrySigmaPerMeter * std::hypot(z.x, z.y));
	const double sa = kScale * (m_opts.odometrySigmaAngular + m_opts.odometrySigmaPerRadian * std::abs(z.phi));
	return 3 * (sl + kLever * sa);
}

Eigen::Matrix3d LoopClosure::toEdgeFrame(const Eigen::Matrix3d& I, double fromPhi) const
{
	// A change dz of the edge (in the frame of its first node) moves the second node by R dz in
	// the map frame, where the matcher's curvature lives.
	Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
	R(0, 0) = std::cos(fromPhi), R(0, 1) = -std::sin(fromPhi);
	R(1, 0) = std::sin(fromPhi), R(1, 1) = std::cos(fromPhi);
	Eigen::Matrix3d out = R.transpose() * I * R;
	return out.allFinite() ? out : Eigen::Matrix3d::Zero();
}

void LoopClosure::addKeyframe(const TPose2D& pose, double timestamp, ScanPoints scan, const Eigen::Matrix3d& hessian,
							  bool tracked, bool searched, double goodness, double sigma)
{
	const std::size_t id = m_nodes.size();
	double travel = 0;
	if (id == 0)
		m_graph.addNode(id, pose);
	else
	{
		// The previous keyframe, or for a new session's first the nearest of the earlier session's.
		const std::size_t from = id == m_priorCount ? nearestNode(pose) : id - 1;
		const Node& prev = m_nodes[from];
		const TPose2D z = relativePose(prev.mapPose, pose);
		travel = m_nodes.back().travel + (id == m_priorCount ? 0.0 : std::hypot(z.x, z.y));
		// Across lost tracking the front-end's relative pose is odometry alone: loose. So is the tie of a
		// new session to the earlier one, which only its match says.
		Eigen::Matrix3d info = odometryInformation(z, tracked && id != m_priorCount ? 1.0 : 5.0);
		if (tracked)
		{
			const Eigen::Matrix3d H = hessian.allFinite() ? hessian : Eigen::Matrix3d::Zero();
			info += toEdgeFrame(H / m_opts.informationScale, prev.mapPose.phi);
		}
		// The initial guess follows the previous node where the graph has it.
		m_graph.addNode(id, compose(m_graph.pose(from), z));
		m_graph.addEdge(from, id, z, toMrpt(info));
	}
	// For bench/calibrate_information.py (through pm-slam-app-instrumented): each keyframe's time, pose
	// and match curvature.
	if (const auto& probe = keyframeProbe()) probe({timestamp, pose, hessian});
	// Kept for the rest of the run: without the slack of the vectors they were built in.
	scan.hits.shrink_to_fit();
	scan.freeEnds.shrink_to_fit();
	const float reach = reachOf(scan);
	m_nodes.push_back({travel, timestamp, std::make_shared<const ScanPoints>(std::move(scan)), pose, reach, sigma});
	m_published.push_back(m_graph.pose(id));
	// Whether this keyframe's match may make a revisit edge (linkRevisit). After lost tracking or a
	// re-localisation the front-end's placement is a hypothesis (a look-alike room, a stretch of
	// corridor further on): its matches become loop constraints only once a detected loop confirms
	// it, or they would outvote the detected loops that could undo a wrong one.
	if (id > 0 && (!tracked || searched))
	{
		if (m_unconfirmedFrom == SIZE_MAX) m_lossStart = id, m_lossDoubt = 0;
		m_unconfirmedFrom = id;
		m_lossDoubt += searched ? std::numeric_limits<double>::infinity() : untrackedDoubt(relativePose(m_nodes[id - 1].mapPose, pose));
	}
	// A match that explains its scan less well than this log's keyframes usually are explained is no
	// loop constraint either (a front-end off its track: after the aces robot was carried 3 m its
	// matches scored 0.74-0.87 for a while).
	bool wellExplained = true;
	if (std::isfinite(goodness) && tracked)
	{
		constexpr std::size_t kRecent = 64;
		if (m_goodness.size() >= 16)
		{
			std::vector<float> g = m_goodness;
			std::nth_element(g.begin(), g.begin() + g.size() / 2, g.end());
			wellExplained = goodness >= g[g.size() / 2] - m_opts.revisitBelowTypical;
		}
		if (m_goodness.size() < kRecent)
			m_goodness.push_back(static_cast<float>(goodness));
		else
			m_goodness[m_goodnessNext] = static_cast<float>(goodness);
		m_goodnessNext = (m_goodnessNext + 1) % kRecent;
	}
	// The front-end matched this scan against the grid whose keyframes sit at their mapPose, unless
	// a new grid was handed over in between (then the match was against the old one).
	std::optional<Eigen::Matrix3d> frontEnd;
	if (id > 0 && tracked && !searched && wellExplained && !m_handedOver && m_opts.revisitMinOverlap <= 1 &&
		hessian.allFinite())
		frontEnd = hessian;
	m_handedOver = false;
	if (m_opts.background)
		m_job = std::async(std::launch::async, [this, id, frontEnd] { return runJob(id, frontEnd); });
	else
		m_inlineResult = runJob(id, frontEnd);
}

void LoopClosure::linkRevisit(std::size_t node, const Eigen::Matrix3d& hessian)
{
	// The front-end matched this keyframe against the whole map, earlier visits of the place
	// included: that match is a loop constraint too. Unless the graph has it, an optimisation (for
	// a loop elsewhere) bends the stretch between the visits freely and tears apart two visits the
	// front-end had aligned (intel: 15 cm between passes of one corridor 25 min apart). The edge
	// goes to the earlier keyframe that sees most of what this one sees.
	if (m_unconfirmedFrom != SIZE_MAX) return;
	const Node& n = m_nodes[node];
	// Only where the back-end itself verified that this stretch and that visit are aligned: a
	// detected loop of the last agreeWindow metres between them (a front-end back at a place after
	// a loop's drift matches its own recent scans, and along a corridor still overlaps the earlier
	// visit's walls). Where the earlier ends of those loops are (m of path); none: nothing to link.
	// A loop vouches for the front-end's alignment only where it agrees with it: the relative pose
	// of its two keyframes where their scans are in the map (a front-end that snapped onto the
	// earlier visit a metre along a corridor, after a drop-out, is outvoted by the loops otherwise).
	std::vector<double> verifiedAt;
	for (auto m = m_matches.rbegin(); m != m_matches.rend(); ++m)	// newest first
	{
		if (n.travel - m_nodes[m->to].travel > m_opts.agreeWindow) break;
		const TPose2D inMap = relativePose(m_nodes[m->from].mapPose, m_nodes[m->to].mapPose);
		if (m->accepted && within(relativePose(inMap, m->z), m_opts.agreeLinear, m_opts.agreeAngular))
			verifiedAt.push_back(m_nodes[m->from].travel);
	}
	if (verifiedAt.empty()) return;
	constexpr double kCell = 0.1, kRadius = 3.0;
	// The graph and the map the front-end matched agree to a cell once the rebuilt map is handed over.
	constexpr double kAgreeLinear = 0.05, kAgreeAngular = 1.0 * M_PI / 180;
	constexpr std::size_t kCandidates = 4;
	std::vector<std::pair<double, std::size_t>> near;
	for (std::size_t i = 0; i < node && n.travel - m_nodes[i].travel >= m_opts.minTravel; ++i)
	{
		if (const auto d = distanceWithin(m_nodes[i].mapPose, n.mapPose, kRadius)) near.emplace_back(*d, i);
	}
	if (near.empty()) return;
	std::sort(near.begin(), near.end());
	if (near.size() > kCandidates) near.resize(kCandidates);
	const auto key = [](double x, double y) {	// the two cell indices, 32 bits each (unsigned: no UB)
		const auto ix = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::floor(x / kCell)));
		const auto iy = static_cast<std::uint32_t>(static_cast<std::int32_t>(std::floor(y / kCell)));
		return (static_cast<std::uint64_t>(ix) << 32) | iy;
	};
	std::vector<std::pair<double, double>> mine;
	const CPose2D pn(n.mapPose);
	for (const auto& h : n.scan->hits)
	{
		double gx, gy;
		pn.composePoint(h.x, h.y, gx, gy);
		mine.emplace_back(gx, gy);
	}
	if (mine.empty()) return;
	double bestOverlap = 0;
	std::size_t best = SIZE_MAX;
	std::unordered_set<std::uint64_t> cells;
	for (const auto& [d, c] : near)
	{
		cells.clear();
		const CPose2D pc(m_nodes[c].mapPose);
		for (const auto& h : m_nodes[c].scan->hits)
		{
			double gx, gy;
			pc.composePoint(h.x, h.y, gx, gy);
			cells.insert(key(gx, gy));
		}
		std::size_t seen = 0;
		for (const auto& [gx, gy] : mine)
		{
			bool hit = false;
			for (int dx = -1; dx <= 1 && !hit; ++dx)
				for (int dy = -1; dy <= 1 && !hit; ++dy) hit = cells.count(key(gx + dx * kCell, gy + dy * kCell)) > 0;
			seen += hit;
		}
		const double overlap = static_cast<double>(seen) / static_cast<double>(mine.size());
		if (overlap > bestOverlap) bestOverlap = overlap, best = c;
	}
	if (best == SIZE_MAX || bestOverlap < m_opts.revisitMinOverlap) return;
	const TPose2D& xc = m_nodes[best].mapPose;
	const TPose2D z = relativePose(xc, n.mapPose);
	// The visit linked is one a recent detected loop verified, and the graph, optimised with it,
	// agrees with the front-end's relative pose (not yet, until the map rebuilt at the corrected
	// poses is handed over).
	if (std::none_of(verifiedAt.begin(), verifiedAt.end(),
					 [&](double t) { return std::abs(t - m_nodes[best].travel) <= m_opts.localMapExtent; }))
		return;
	const TPose2D viaGraph = relativePose(m_graph.pose(best), m_graph.pose(node));
	const TPose2D d = relativePose(viaGraph, z);
	if (!within(d, kAgreeLinear, kAgreeAngular)) return;
	// One match supports two edges (to the previous keyframe and to the earlier visit): half each.
	const Eigen::Matrix3d info = toEdgeFrame(hessian / (2 * m_opts.informationScale), xc.phi) + kLoopFloor;
	m_graph.addEdge(best, node, z, toMrpt(info), PoseGraphEdgeKind::Loop);
	m_isRevisit.resize(m_graph.edges().size(), false);
	m_isRevisit.back() = true;
	++m_stats.revisits;
}

std::optional<LoopClosure::Update> LoopClosure::sync()
{
	if (m_job.valid())
	{
		const auto t0 = std::chrono::steady_clock::now();
		JobResult r = m_job.get();
		m_stats.waitSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		return take(std::move(r));
	}
	if (m_inlineResult)
	{
		JobResult r = std::move(*m_inlineResult);
		m_inlineResult.reset();
		return take(std::move(r));
	}
	return std::nullopt;
}

void LoopClosure::publish()
{
	for (std::size_t i = 0; i < m_nodes.size(); ++i) m_published[i] = m_graph.pose(i);
	m_links.clear();
	for (const auto& e : m_graph.edges())
		if (e.kind == PoseGraphEdgeKind::Loop && !e.rejected && !isRevisit(&e - m_graph.edges().data()))
		{
			const TPose2D& a = m_published[e.from];
			const TPose2D& b = m_published[e.to];
			m_links.emplace_back(mrpt::math::TPoint2D(a.x, a.y), mrpt::math::TPoint2D(b.x, b.y));
		}
}

std::optional<LoopClosure::Update> LoopClosure::take(JobResult r)
{
	m_stats.backendSeconds += r.seconds;
	if (r.optimized) publish();
	if (!r.patch) return std::nullopt;
	m_handedOver = true;
	return Update{std::move(r.patch), std::move(r.blocks), r.correction};
}

std::vector<LoopClosure::Update> LoopClosure::finish()
{
	std::vector<Update> out;
	if (auto u = sync()) out.push_back(std::move(*u));
	const auto t0 = std::chrono::steady_clock::now();
	JobResult r;
	r.optimized = optimizeIfDue(true);
	// Every keyframe at its final pose, however little it moved (a micrometre: not the rounding of
	// the graph's chained initial guesses): the map written is the trajectory's.
	patchMoved(0.0, 1e-6, r);
	if (auto u = take(std::move(r))) out.push_back(std::move(*u));
	m_stats.backendSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	m_localMaps.clear();  // no verification after the end
	m_stats.rejected = m_stats.revisitsRejected = 0;
	const auto& edges = m_graph.edges();
	for (std::size_t i = 0; i < edges.size(); ++i)
		if (edges[i].kind == PoseGraphEdgeKind::Loop && edges[i].rejected)
			++(isRevisit(i) ? m_stats.revisitsRejected : m_stats.rejected);
	return out;
}

std::size_t LoopClosure::memoryBytes() const
{
	std::size_t b = m_nodes.capacity() * sizeof(Node) + m_published.capacity() * sizeof(TPose2D) +
					m_links.capacity() * sizeof(m_links[0]) + m_matches.capacity() * sizeof(Match) +
					m_isRevisit.capacity() / 8 + m_goodness.capacity() * sizeof(float);
	for (const auto& n : m_nodes)
		b += sizeof(ScanPoints) + (n.scan->hits.capacity() + n.scan->freeEnds.capacity()) * sizeof(mrpt::math::TPoint2Df);
	for (const auto& [pose, scan] : m_fixed)
		b += (scan.hits.capacity() + scan.freeEnds.capacity()) * sizeof(mrpt::math::TPoint2Df);
	for (const auto& [spec, map] : m_localMaps) b += map->memoryBytes() + spec.keyframes.capacity() * sizeof(spec.keyframes[0]);
	// The graph: a map node and an edge record each (std::map nodes hold ~4 pointers of overhead).
	b += m_graph.nodeCount() * (sizeof(TPose2D) + sizeof(PoseGraph::NodeId) + 4 * sizeof(void*)) +
		 m_graph.edgeCount() * sizeof(PoseGraphEdge);
	return b;
}

LoopClosure::JobResult LoopClosure::runJob(std::size_t node, std::optional<Eigen::Matrix3d> frontEndHessian)
{
	const auto t0 = std::chrono::steady_clock::now();
	JobResult r;
	const std::size_t attempts = m_stats.attempts;
	if (frontEndHessian) linkRevisit(node, *frontEndHessian);
	detect(node);
	detectGlobal(node);
	++m_sinceOptimization;
	optimizeAndPatch(m_loopOpen, r);
	// The local maps just verified against were thousands of small distance blocks: hand the freed
	// pages back, or they stay resident in this thread's heap (glibc keeps them for reuse).
	if (m_stats.attempts != attempts) malloc_trim(0);
	r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	return r;
}

void LoopClosure::detect(std::size_t node)
{
	const Node& n = m_nodes[node];
	if (n.travel - m_lastAttempt < m_opts.detectEvery) return;
	const TPose2D x = m_graph.pose(node);
	const double since = n.travel - m_lastAnchor;
	// The position uncertainty relative to a node grows with the path driven since then, and
	// since the last closure that anchored the graph (not one within a stretch placed after lost
	// tracking: that tells nothing of where the stretch is relative to the rest).
	const auto radius = [&](double back) {
		return std::min(m_opts.maxSearchRadius, m_opts.searchRadius + m_opts.searchRadiusPerMeter * std::min(since, back));
	};
	const auto angle = [&](double back) {
		return std::min(m_opts.maxSearchAngle, m_opts.searchAngle + m_opts.searchAnglePerMeter * std::min(since, back));
	};
	// The keyframes within the uncertainty come in runs, one per visit of the place (a run ends
	// where the path leaves the window for more than localMapExtent metres): the nearest keyframe
	// of each run is a candidate, the nearest runs first.
	struct Candidate
	{
		std::size_t id;
		double d;
	};
	std::vector<Candidate> runs;
	double lastIn = -1e18;
	auto graphPose = m_graph.poses().begin();  // node i's (the ids are 0, 1, …): no lookup per node
	for (std::size_t i = 0; i < node; ++i, ++graphPose)
	{
		const double back = n.travel - m_nodes[i].travel;
		if (back < m_opts.minTravel) break;	 // travel grows with the id
		const auto inWindow = distanceWithin(graphPose->second, x, radius(back));
		if (!inWindow) continue;
		const double d = *inWindow;
		if (runs.empty() || m_nodes[i].travel - lastIn > m_opts.localMapExtent)
			runs.push_back({i, d});
		else if (d < runs.back().d)
			runs.back() = {i, d};
		lastIn = m_nodes[i].travel;
	}
	std::sort(runs.begin(), runs.end(), [](const Candidate& a, const Candidate& b) { return a.d < b.d; });
	constexpr std::size_t kVisits = 2;	// visits verified per attempt
	std::size_t best[kVisits];
	for (std::size_t k = 0; k < kVisits; ++k) best[k] = k < runs.size() ? runs[k].id : SIZE_MAX;
	// Since tracking was lost the graph holds the stretch since where the front-end put it: its own
	// recent visits are the nearest, and a visit from before the loss, where the stretch may be far
	// off, would never be tried. One of the visits verified is the nearest from before the loss.
	const auto beforeLoss = [&](std::size_t id) { return id < m_unconfirmedFrom; };
	if (m_unconfirmedFrom != SIZE_MAX && std::none_of(best, best + kVisits, [&](std::size_t id) { return id != SIZE_MAX && beforeLoss(id); }))
		for (const Candidate& c : runs)
			if (beforeLoss(c.id))
			{
				best[kVisits - 1] = c.id;
				break;
			}
	if (best[0] == SIZE_MAX) return;
	m_lastAttempt = n.travel;
	++m_stats.attempts;
	// Matches of the last agreeWindow metres that were not accepted age out.
	m_matches.erase(std::remove_if(m_matches.begin(), m_matches.end(),
								   [&](const Match& m) {
									   return !m.accepted && n.travel - m_nodes[m.to].travel > m_opts.agreeWindow;
								   }),
					m_matches.end());
	std::vector<Visit> visits;
	for (std::size_t c : best)
	{
		if (c == SIZE_MAX) continue;
		const double back = n.travel - m_nodes[c].travel;
		visits.push_back(visit(node, c, radius(back), angle(back)));
	}
	std::vector<Match> verified;
	for (const auto& m : verifyVisits(visits))
		if (m) verified.push_back(*m);
	admit(node, verified);
}

void LoopClosure::admit(std::size_t node, std::vector<Match>& verified)
{
	const Node& n = m_nodes[node];
	const auto beforeLoss = [&](std::size_t id) { return id < m_unconfirmedFrom; };
	// Two visits that each explain the scan, at places further apart than the graph can be off right
	// after a closure: a look-alike place (a corridor's pilasters a period on), whichever is right.
	// (Not a visit from before lost tracking against one since: there the graph may be off by any amount.)
	bool lookAlike = false;
	for (std::size_t i = 0; i < verified.size(); ++i)
		for (std::size_t j = i + 1; j < verified.size(); ++j)
			lookAlike = lookAlike || (beforeLoss(verified[i].from) == beforeLoss(verified[j].from) &&
									  !within(disagreement(verified[i], verified[j]), m_opts.searchRadius, m_opts.searchAngle));
	if (lookAlike)
	{
		m_stats.ambiguous += verified.size();
		verified.clear();
	}
	bool confirmed = false;
	for (const Match& m : verified)
	{
		++m_stats.verified;
		// Accepted when enough recent matches agree with it (and then they are accepted too).
		std::vector<std::size_t> agreeing;
		for (std::size_t i = 0; i < m_matches.size(); ++i)
			if (n.travel - m_nodes[m_matches[i].to].travel <= m_opts.agreeWindow && agree(m_matches[i], m))
				agreeing.push_back(i);
		m_matches.push_back(m);
		// A wider window holds more poses a look-alike can fit: one more agreeing match per doubling
		// of the window beyond 4 m (up to where two were enough on every log and fault measured;
		// intel with 80 % of its scans cluttered let a poor loop through in a 10 m window).
		const unsigned extra = m.window > kWideWindow ? unsigned(std::ceil(std::log2(m.window / kWideWindow))) : 0;
		if (agreeing.size() + 1 < m_opts.agreeingMatches + extra) continue;
		agreeing.push_back(m_matches.size() - 1);
		// A loop confirms where the front-end put the robot after lost tracking only if it reaches
		// back across the loss; one within the stretch since (the robot back on its own recent
		// path) does not.
		const bool internal = !beforeLoss(m.from);
		for (std::size_t i : agreeing)
		{
			Match& a = m_matches[i];
			if (a.accepted) continue;
			a.accepted = true;
			m_graph.addEdge(a.from, a.to, a.z, toMrpt(a.information), PoseGraphEdgeKind::Loop);
			if (beforeLoss(a.from) && !beforeLoss(a.to)) m_unconfirmedFrom = SIZE_MAX, confirmed = true;
			++m_stats.accepted;
			++m_pendingLoops;
		}
		if (n.travel - m_lastClosure > m_opts.minTravel)
		{
			++m_stats.closures;
			m_loopOpen = true;	// a new loop: optimise now
		}
		m_lastClosure = n.travel;
		if (!internal) m_lastAnchor = n.travel;
	}
	if (confirmed)
	{
		m_lossStart = SIZE_MAX;
		m_beforeLoss.reset();
	}
}

const std::pair<LikelihoodPyramid, LikelihoodPyramid>& LoopClosure::mapBeforeLoss()
{
	if (!m_beforeLoss || m_pyramidsBefore != m_lossStart)
	{
		OccupancyDistanceGridMap map(m_gridOpts);
		std::vector<std::pair<TPose2D, const ScanPoints*>> scans;
		for (const auto& [pose, scan] : m_fixed) scans.emplace_back(pose, &scan);
		for (std::size_t i = 0; i < m_lossStart; ++i) scans.emplace_back(m_graph.pose(i), m_nodes[i].scan.get());
		map.insertScans(scans);
		LikelihoodPyramid fine(map.distanceMap());
		LikelihoodPyramid coarse = BranchAndBoundSearch(fine, globalSearchOptions()).coarsePyramid();
		m_beforeLoss = std::make_unique<std::pair<LikelihoodPyramid, LikelihoodPyramid>>(std::move(fine), std::move(coarse));
		m_pyramidsBefore = m_lossStart;
	}
	return *m_beforeLoss;
}

void LoopClosure::detectGlobal(std::size_t node)
{
	// After lost tracking (or a re-localisation) the stretch since is where the front-end put it, and
	// that may be anywhere: a robot set down on new ground after a long gap, whose odometry across the
	// gap was off, comes back to old ground metres or tens of metres from where the graph expects it,
	// beyond any drift window. Where the loss made the stretch's placement more doubtful than the drift
	// window towards what came before reaches (a re-localisation, or odometry alone across a gap), its keyframes are searched on the whole map from before the loss; the
	// places found are verified like any loop, and accepted as any loop is: when agreeing matches
	// follow (one more per doubling of the correction beyond 4 m, as for a wide window).
	const Node& n = m_nodes[node];
	if (m_opts.globalSearchEvery <= 0 || m_unconfirmedFrom == SIZE_MAX || m_lossStart == SIZE_MAX ||
		m_lossDoubt <= std::min(m_opts.maxSearchRadius, m_opts.searchRadius + m_opts.searchRadiusPerMeter * (n.travel - m_lastAnchor)) ||
		n.travel - m_lastGlobal < m_opts.globalSearchEvery || n.scan->hits.size() < 10)
		return;
	m_lastGlobal = n.travel;
	const auto t0 = std::chrono::steady_clock::now();
	const auto& [fine, coarse] = mapBeforeLoss();
	const auto found = BranchAndBoundSearch(fine, globalSearchOptions()).searchGlobalCoarseToFine(n.scan->hits, coarse);
	++m_stats.globalSearches;
	const TPose2D x = m_graph.pose(node);
	std::vector<Match> verified;
	for (const auto& c : found.candidates)
	{
		// The visit verified is the keyframe from before the loss nearest to the place found.
		std::size_t nearest = SIZE_MAX;
		double nearestD = kGlobalVisitRadius;
		for (std::size_t i = 0; i < m_lossStart && n.travel - m_nodes[i].travel >= m_opts.minTravel; ++i)
		{
			const double d = distance(m_graph.pose(i), c.pose);
			if (d < nearestD) nearestD = d, nearest = i;
		}
		if (nearest == SIZE_MAX) continue;
		// The correction the place implies, its turn at the lever arm of untrackedDoubt(): it counts
		// as the search window does for the matches that must agree (a place turned half round, in a
		// room or corridor that looks alike both ways, needs as many as one 20 m off). Not bounded by
		// the doubt: that follows the net odometry across the loss, not the path driven meanwhile.
		const double correction = distance(c.pose, x) + kDoubtLever * std::abs(mrpt::math::wrapToPi(c.pose.phi - x.phi));
		std::optional<Match> m = verifyVisits({visit(node, nearest, kGlobalWindow, kGlobalAngle, c.pose)}).front();
		if (!m) continue;
		m->window = std::max(m->window, correction);
		verified.push_back(*m);
		++m_stats.globalVerified;
	}
	admit(node, verified);
	m_stats.globalSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

LoopClosure::Visit LoopClosure::visit(std::size_t node, std::size_t candidate, double linWindow, double angWindow,
									  const std::optional<TPose2D>& centre)
{
	const Node& n = m_nodes[node];
	Visit v;
	v.node = node;
	v.candidate = candidate;
	v.centre = centre ? *centre : m_graph.pose(node);
	v.linWindow = linWindow;
	v.angWindow = angWindow;
	// The candidate's neighbourhood, none of it recent: localMapExtent metres of path on either side,
	// or as far as the window reaches (in a wide window the right place may be that far along the
	// visit, and with it in the map a look-alike part of the visit cannot win unseen). Its distance
	// layer reaches as far as the coarse lattice steps (coarseToFine), so that a coarse pose next to
	// the right one still scores.
	//
	// The stretch is widened to whole chunks of kLocalMapChunk metres of path, and the distance layer's
	// reach rounded up to kReachStep, so that the attempts of the next metres, whose candidates lie a
	// little further along the same visit, find that local map built already (m_localMaps).
	const double middle = m_nodes[candidate].travel;
	const double extent = std::max(m_opts.localMapExtent, linWindow);
	const double from = std::floor((middle - extent) / kLocalMapChunk) * kLocalMapChunk;
	const double to = std::ceil((middle + extent) / kLocalMapChunk) * kLocalMapChunk;
	const double reach = std::min(2.0, 1.5 * linWindow / 8);
	v.local.maxDistance =
		reach <= m_gridOpts.maxDistance ? m_gridOpts.maxDistance : std::ceil(reach / kReachStep) * kReachStep;
	std::size_t first = candidate;
	while (first > 0 && m_nodes[first - 1].travel >= from) --first;
	for (std::size_t i = first; i < node; ++i)
	{
		if (m_nodes[i].travel > to || n.travel - m_nodes[i].travel < m_opts.minTravel) break;
		v.local.keyframes.emplace_back(i, m_graph.pose(i));
	}
	const auto hit = std::find_if(m_localMaps.begin(), m_localMaps.end(),
								  [&](const auto& c) { return c.first == v.local; });
	if (hit != m_localMaps.end())
	{
		v.map = hit->second;
		std::rotate(m_localMaps.begin(), hit, hit + 1);	 // most recently used first
	}
	return v;
}

std::vector<std::optional<LoopClosure::Match>> LoopClosure::verifyVisits(std::vector<Visit> visits)
{
	// The local maps not cached, then every visit's match, each piece side by side with the others. A
	// map is the same whichever thread builds it, and a match the same whenever it runs: the results
	// do not depend on the threads.
	std::vector<Visit*> toBuild;
	for (Visit& v : visits)
		if (!v.map) toBuild.push_back(&v);
	concurrently(toBuild.size(), [&](std::size_t b) { toBuild[b]->map = buildLocalMap(toBuild[b]->local); });
	for (const Visit* v : toBuild)
	{
		m_localMaps.insert(m_localMaps.begin(), {v->local, v->map});
		if (m_localMaps.size() > kCachedLocalMaps) m_localMaps.pop_back();
	}
	std::vector<std::optional<Match>> matches(visits.size());
	concurrently(visits.size(), [&](std::size_t k) { matches[k] = verifyOn(visits[k]); });
	return matches;
}

std::optional<LoopClosure::Match> LoopClosure::verifyOn(const Visit& v) const
{
	const Node& n = m_nodes[v.node];
	const OccupancyDistanceGridMap& local = *v.map;
	const double linWindow = v.linWindow, angWindow = v.angWindow;
	const DynamicDistanceMap& dm = local.distanceMap();
	const std::vector<mrpt::math::TPoint2Df>& hits = n.scan->hits;
	const TPose2D& x = v.centre;
	struct Refined
	{
		TPose2D pose;
		PerfectMatchMatcher::MatchInfo info;
	};
	std::vector<Refined> refined;
	// A wide window holds more look-alike peaks: more of them refined, for the ambiguity test below.
	const std::size_t peaks = linWindow > kWideWindow ? 8 : 4;
	PerfectMatchMatcher matcher = m_matcher;
	if (std::isfinite(n.sigma)) matcher.options.sigma = n.sigma;  // D52: a noisier lidar's own σ
	for (const auto& s : CorrelativeSearch::coarseToFine(dm, hits, x, linWindow, angWindow, peaks))
	{
		Refined r;
		r.pose = matcher.alignPoints(dm, hits, s.pose, &r.info);
		refined.push_back(r);
	}
	if (refined.empty()) return std::nullopt;
	std::sort(refined.begin(), refined.end(),
			  [](const Refined& a, const Refined& b) { return a.info.goodness > b.info.goodness; });
	const Refined& best = refined.front();
	if (best.info.goodness < m_opts.minGoodness || best.info.inlierFraction < m_opts.minInlierFraction)
		return std::nullopt;
	// A revisit stands where the earlier visit saw free space, and sees what it saw. A pose in a
	// place the local map never observed (inside a block, beyond its walls) is a look-alike fit to
	// the part of the map there is, whatever its score.
	if (local.isUnexplored(best.pose.x, best.pose.y) ||
		local.isOccupied(best.pose.x, best.pose.y) ||
		local.unexploredFraction(hits, best.pose) > m_opts.maxUnexploredFraction)
		return std::nullopt;
	// Where the earlier visit saw free space, a revisit's returns are only things that moved since
	// (a person: intel's worst true loop has 18 % of them there, most under 2 %). A look-alike place
	// with its features elsewhere (a twin corridor, pilasters a metre off) puts 9-17 % of the scan there.
	// Returns the keyframes just before saw through moved between their scans (a passer-by, clutter):
	// they say nothing about the place, and are not counted (D27).
	const std::vector<mrpt::math::TPoint2Df> stayed = returnsThatStayed(v.node);
	if (local.inFreeSpaceFraction(stayed, best.pose, 0.15) * double(stayed.size()) >
		m_opts.maxInFreeSpace * double(hits.size()))
		return std::nullopt;
	// Another pose, clearly distinct, that explains the scan nearly as well: a corridor or a
	// repetitive place, where the best score does not say which pose is right.
	for (std::size_t i = 1; i < refined.size(); ++i)
	{
		const Refined& o = refined[i];
		const bool distinct = distance(o.pose, best.pose) > 0.3 ||
							  std::abs(mrpt::math::wrapToPi(o.pose.phi - best.pose.phi)) > 3.0 * M_PI / 180;
		if (distinct && o.info.goodness > best.info.goodness - m_opts.ambiguityMargin) return std::nullopt;
	}
	Match m;
	m.from = v.candidate;
	m.to = v.node;
	const TPose2D xc = m_graph.pose(v.candidate);
	m.z = relativePose(xc, best.pose);
	m.information = toEdgeFrame(best.info.hessian / m_opts.informationScale, xc.phi) + kLoopFloor;
	m.window = linWindow;
	return m;
}

std::vector<mrpt::math::TPoint2Df> LoopClosure::returnsThatStayed(std::size_t node) const
{
	// The keyframes of the last moments before this one, close by: what they saw through in this
	// scan was not there when they looked.
	const Node& n = m_nodes[node];
	const TPose2D x = m_graph.pose(node);
	std::vector<std::pair<TPose2D, const ScanPoints*>> before;
	for (std::size_t m = node; m-- > 0 && before.size() < kSeenThroughKeyframes;)
	{
		const TPose2D z = relativePose(x, m_graph.pose(m));
		if (std::abs(n.timestamp - m_nodes[m].timestamp) > kSeenThroughSeconds || std::hypot(z.x, z.y) > kSeenThroughDistance)
			break;
		before.emplace_back(z, m_nodes[m].scan.get());
	}
	const std::vector<bool> moved = seenThrough(*n.scan, before);
	std::vector<mrpt::math::TPoint2Df> stayed;
	for (std::size_t k = 0; k < moved.size(); ++k)
		if (!moved[k]) stayed.push_back(n.scan->hits[k]);
	return stayed;
}

bool LoopClosure::LocalMapSpec::operator==(const LocalMapSpec& o) const
{
	return maxDistance == o.maxDistance && keyframes.size() == o.keyframes.size() &&
		   std::equal(keyframes.begin(), keyframes.end(), o.keyframes.begin(), [](const auto& p, const auto& q) {
			   return p.first == q.first && p.second.x == q.second.x && p.second.y == q.second.y && p.second.phi == q.second.phi;
		   });
}

std::shared_ptr<const OccupancyDistanceGridMap> LoopClosure::buildLocalMap(const LocalMapSpec& spec) const
{
	OccupancyGridUpdateOptions opts = m_gridOpts;
	opts.maxDistance = spec.maxDistance;
	auto map = std::make_shared<OccupancyDistanceGridMap>(opts);
	std::vector<std::pair<TPose2D, const ScanPoints*>> scans;
	for (const auto& [i, pose] : spec.keyframes) scans.emplace_back(pose, m_nodes[i].scan.get());
	map->insertScans(scans);
	return map;
}

TPose2D LoopClosure::disagreement(const Match& a, const Match& b) const
{
	// The relative pose between the two matched keyframes, as the graph has it and as the two
	// loops put them: a wrong loop disagrees with a right one (and with another wrong one).
	const TPose2D viaGraph = relativePose(m_graph.pose(a.to), m_graph.pose(b.to));
	const TPose2D viaLoops = relativePose(compose(m_graph.pose(a.from), a.z), compose(m_graph.pose(b.from), b.z));
	return relativePose(viaGraph, viaLoops);
}

bool LoopClosure::agree(const Match& a, const Match& b) const
{
	return within(disagreement(a, b), m_opts.agreeLinear, m_opts.agreeAngular);
}

bool LoopClosure::optimizeAndPatch(bool force, JobResult& r)
{
	if (!optimizeIfDue(force)) return false;
	r.optimized = true;
	patchMoved(m_opts.rebuildAbove, m_opts.reinsertAbove, r);
	return true;
}

bool LoopClosure::optimizeIfDue(bool force)
{
	if (m_pendingLoops == 0 || (!force && m_sinceOptimization < m_opts.optimizeEvery)) return false;
	// Loop edges the graph already satisfies (chi-square within the test's quantile: a revisit of a
	// place the graph has right, a new loop the front-end closed itself) would change nothing: they
	// wait for the next optimisation that is needed anyway.
	double worst = 0;
	const auto& edges = m_graph.edges();
	for (std::size_t i = m_checkedEdges; i < edges.size(); ++i)
		if (edges[i].kind == PoseGraphEdgeKind::Loop) worst = std::max(worst, m_graph.edgeChi2(i));
	// Checked now, optimised or not (the optimisation adds no edge).
	m_sinceOptimization = 0;
	m_checkedEdges = edges.size();
	m_pendingLoops = 0;
	m_loopOpen = false;
	if (worst <= PoseGraphOptions().chi2Threshold) return false;
	const PoseGraphStats st = m_graph.optimize();
	m_stats.optimizeSeconds += st.seconds;
	++m_stats.optimizations;
	return true;
}

void LoopClosure::patchMoved(double trigger, double reinsert, JobResult& r)
{
	// How far each keyframe moved: its scan's origin, plus its heading change at a 5 m lever arm.
	std::vector<bool> moved(m_nodes.size(), false);
	std::size_t count = 0;
	double most = 0;
	for (std::size_t i = 0; i < m_nodes.size(); ++i)
	{
		const TPose2D& p = m_graph.pose(i);
		const TPose2D& q = m_nodes[i].mapPose;
		const double d = distance(p, q) + 5.0 * std::abs(mrpt::math::wrapToPi(p.phi - q.phi));
		most = std::max(most, d);
		moved[i] = d > reinsert;
		count += moved[i];
	}
	if (most <= trigger || count == 0) return;
	// The blocks whose cells change: those the moved scans touch where they are in the map and
	// where they go.
	auto patch = std::make_shared<OccupancyDistanceGridMap>(m_gridOpts);
	auto blocks = std::make_shared<BlockMask>();
	for (std::size_t i = 0; i < m_nodes.size(); ++i)
		if (moved[i])
		{
			patch->addBlocksTouched(*m_nodes[i].scan, m_nodes[i].mapPose, *blocks);
			patch->addBlocksTouched(*m_nodes[i].scan, m_graph.pose(i), *blocks);
		}
	blocks->freeze();
	// Rebuilt from every scan that reaches them, in the order the map got them, each at the pose
	// it will have in the map: those cells then hold what a map rebuilt from all keyframes would.
	const double res = m_gridOpts.resolution;
	const auto reaches = [&](const BlockMask& only, const TPose2D& p, double reach) {
		using Blocks = SparseOccupancyGrid::Blocks;
		const auto block = [&](double v) { return Blocks::blockOf(static_cast<int>(std::floor(v / res))); };
		reach += 2 * res;  // the cell of a point on the box's edge
		return only.meets(block(p.x - reach), block(p.y - reach), block(p.x + reach), block(p.y + reach));
	};
	// A cell's value depends only on the scans that reach it, in order: the blocks west and east of
	// the middle one are rebuilt side by side, each half by every scan that reaches it.
	const auto halves = splitWestEast(*blocks);
	std::vector<std::shared_ptr<OccupancyDistanceGridMap>> parts{patch, std::make_shared<OccupancyDistanceGridMap>(m_gridOpts)};
	concurrently(2, [&](std::size_t h) {
		const BlockMask& only = halves[h];
		for (const auto& [pose, scan] : m_fixed) parts[h]->insertScanWithin(scan, pose, only);
		for (std::size_t i = 0; i < m_nodes.size(); ++i)
		{
			const TPose2D& p = moved[i] ? m_graph.pose(i) : m_nodes[i].mapPose;
			if (reaches(only, p, m_nodes[i].reach)) parts[h]->insertScanWithin(*m_nodes[i].scan, p, only);
		}
	});
	patch->copyBlocks(*parts[1], halves[1]);
	// The front-end moves with the newest keyframe, if that moved.
	const Node& last = m_nodes.back();
	r.correction = moved.back() ? CPose2D(m_graph.pose(m_nodes.size() - 1)) + (-CPose2D(last.mapPose)) : CPose2D();
	for (std::size_t i = 0; i < m_nodes.size(); ++i)
		if (moved[i]) m_nodes[i].mapPose = m_graph.pose(i);
	++m_stats.mapUpdates;
	m_stats.reinserted += count;
	m_stats.blocksReplaced += blocks->count();
	r.patch = std::move(patch);
	r.blocks = std::move(blocks);
}

}  // namespace pmslam
