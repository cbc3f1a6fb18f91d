/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * LoopClosure: the back-end. The front-end (PM against the map built so far) cannot undo
 * the drift accumulated around a long loop; this keeps a pose graph of the keyframes (the
 * scans inserted into the map), finds and verifies loops, optimises the graph and rebuilds
 * the map at the corrected poses, so that later scans match a consistent map.
 *
 * - Nodes: every keyframe, with its scan points. Edges between consecutive keyframes: the
 *   front-end's relative pose; information from the match's curvature (the PM Hessian divided
 *   by informationScale, calibrated on the benchmark logs against their relations) plus an
 *   odometry-like floor
 *   (a plain corridor leaves the Hessian singular along it). Across a stretch where tracking
 *   was lost, the edge has only a loose odometry information.
 * - Loop detection, at most every detectEvery metres driven: the candidates are the keyframes
 *   at least minTravel metres of path back whose pose lies within the position uncertainty,
 *   searchRadius + searchRadiusPerMeter x (distance driven since the last closure), up to
 *   maxSearchRadius (and the same for the heading). They come in runs, one per visit of the
 *   place; the nearest keyframe of the two nearest runs is verified: the keyframe's scan is
 *   matched against a local map built from that visit's keyframes within localMapExtent metres of
 *   path of the candidate (or as far as the window reaches), with the wide-basin search over the
 *   whole uncertainty window and the PM refinement from its best peaks. Two visits that explain
 *   the scan at placements further apart than searchRadius are a look-alike: both dropped.
 * - False loops: a verified match must explain the scan (goodness, inlier fraction), be
 *   unambiguous (no distinct pose within ambiguityMargin of its score: a plain or periodic
 *   corridor), put the robot where the local map saw free space and the scan where it saw
 *   something (maxUnexploredFraction: a look-alike fit to part of the map fails this), put
 *   few returns where it saw free space (maxInFreeSpace: a twin corridor's features elsewhere; returns
 *   the keyframes just before saw through, things that moved, not counted: SeenThrough.h), and agree with agreeingMatches - 1 other verified matches (one more per doubling of the window beyond 4 m) of the last
 *   agreeWindow metres (the two loops imply the same relative pose between their keyframes as
 *   the graph does). In the optimisation, loop edges failing a chi-square test are disabled
 *   (PoseGraph: a hard-redescending robust kernel, re-admitted when they fit again).
 * - Revisit edges: the front-end's match of a keyframe against the map is a loop constraint too
 *   where the map holds an earlier visit. Each keyframe gets an edge to the earlier keyframe (at
 *   least minTravel back, within 3 m) that sees revisitMinOverlap of its returns, with the
 *   relative pose the front-end had, once a detected loop of the last agreeWindow metres has
 *   verified that the two visits are aligned and the graph agrees; not from a match that explains
 *   its scan poorly (revisitBelowTypical), nor after lost tracking or a re-localisation until a
 *   detected loop reaching back across the loss confirms the front-end's placement, and only
 *   where the detected loops agree with the front-end. Without them an
 *   optimisation for a loop elsewhere bends the stretch between two visits freely.
 * - After lost tracking, the stretch since is where the front-end put it: the search window
 *   towards what came before keeps growing until a loop across the loss anchors it (a loop of
 *   the stretch onto itself does not), and one of the visits verified is from before the loss.
 * - Optimisation: Ceres' sparse Levenberg-Marquardt (PoseGraph), as soon as a loop is
 *   accepted after a stretch without one, then every optimizeEvery keyframes while loop
 *   edges keep coming; only when a loop edge added since fails the chi-square test against
 *   the current graph (one the front-end has right would only spread matching noise).
 * - The map follows the graph, in part: once a keyframe moved by more than rebuildAbove metres,
 *   those that moved by more than reinsertAbove are re-inserted at their optimised poses. The blocks their scans touch (where they
 *   were and where they go) are rebuilt on the worker from every keyframe that reaches them, in
 *   order; the front-end's map takes those blocks, and its distance layer re-propagates around
 *   the cells that flipped (OccupancyDistanceGridMap::replaceBlocks). The rest of the map, and
 *   of its distance layer, is not touched.
 * - Online: all of that runs on a worker thread, launched at one keyframe and joined at the
 *   next (the front-end keeps matching meanwhile against the map it has). Its result is used
 *   at a fixed point of the scan stream, so a run is repeatable whatever the timing. Within a
 *   job, pieces that do not depend on each other run side by side (the local maps of the two
 *   visits and their matches, the two halves of a map patch): a log replayed faster than real
 *   time has the front-end waiting, and its core idle, while the job runs.
 *
 * Frames: poses of the robot base in the map frame (m, rad); the first node is fixed. The
 * front-end's frame follows the graph: when the newest keyframe is re-inserted, the front-end
 * moves by the rigid correction that puts it where the graph has it.
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/graph/PoseGraph.h>
#include <pmslam/map/BlockMask.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/LikelihoodPyramid.h>
#include <pmslam/match/PerfectMatchMatcher.h>
#include <pmslam/sensor/ScanPoints.h>

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pmslam
{
/** INI section [LoopClosure]; every key is documented in config/default.ini. */
struct LoopClosureOptions : public mrpt::config::CLoadableOptions
{
	bool enabled = true;
	double minTravel = 10.0;  ///< m of path between a keyframe and a loop candidate
	double searchRadius = 1.0;	///< m: position uncertainty right after a closure
	double searchRadiusPerMeter = 0.05;	 ///< its growth per m driven since the last closure
	double maxSearchRadius = 10.0;	///< m
	double searchAngle = 10.0 * M_PI / 180;	 ///< rad, as searchRadius
	double searchAnglePerMeter = 0.5 * M_PI / 180;	///< rad per m
	double maxSearchAngle = 45.0 * M_PI / 180;	///< rad
	double detectEvery = 1.0;  ///< m driven between two detection attempts
	double localMapExtent = 8.0;  ///< m of path on either side of the candidate in its local map
	double minGoodness = 0.75;	///< of the match against the local map (mean PM likelihood)
	double minInlierFraction = 0.6;
	double ambiguityMargin = 0.05;	///< a distinct pose scoring within this of the best: ambiguous
	/** At most this fraction of the scan may land where the local map saw nothing, and the robot
	 * must stand where it saw free space: a revisit sees what the earlier visit saw. */
	double maxUnexploredFraction = 0.3;
	/** At most this fraction of the scan may land where the local map saw free space (more than 0.15 m
	 * from any obstacle): only what moved since, not a look-alike place's features. */
	double maxInFreeSpace = 0.08;
	unsigned agreeingMatches = 2;  ///< verified matches that must agree before a loop is accepted
	double agreeWindow = 20.0;	///< m driven over which those matches are looked for
	double agreeLinear = 0.2;  ///< m: two matches agree when they imply the same relative pose...
	double agreeAngular = 2.0 * M_PI / 180;	 ///< ...within this (rad)
	/** Edge covariance = informationScale x (PM Hessian)^-1. Against the benchmark relations
	 * (bench/calibrate_information.py) the median normalised error says 0.4 (intel), 9.8 (aces), 1.3
	 * (fr079): the Hessian is not optimistic on these logs. 10, the largest, leaves no log's graph
	 * overconfident; a much looser graph (50) lets the chi-square test pass false loops (intel with
	 * 80 % of its scans cluttered: 0.118 m instead of 0.026). */
	double informationScale = 10.0;
	double odometrySigmaLinear = 0.02, odometrySigmaPerMeter = 0.05;  ///< floor of consecutive edges (m, m/m)
	double odometrySigmaAngular = 1.0 * M_PI / 180, odometrySigmaPerRadian = 0.05;	///< (rad, rad/rad)
	unsigned optimizeEvery = 10;  ///< keyframes between optimisations while loop edges keep coming
	/** m: once a keyframe moved more than this (a cell) since it was put into the map, the map
	 * follows the graph: every keyframe that moved more than reinsertAbove is re-inserted. */
	double rebuildAbove = 0.05;
	double reinsertAbove = 0.01;  ///< m
	bool background = true;	 ///< the back-end on a worker thread (false: inline, same results)
	/** A keyframe matched by the front-end gets an edge to the earlier visit's keyframe that sees
	 * this much of its scan (fraction of its returns within a cell of that keyframe's); > 1: none. */
	double revisitMinOverlap = 0.5;
	/** ...and whose match explains its scan within this of the median of the last 64 keyframes' matches
	 * (a front-end off its track explains its scans worse: after the aces robot was carried 3 m its
	 * matches scored 0.74-0.87 for a while; its alignment to an earlier visit is no loop constraint). */
	double revisitBelowTypical = 0.05;
	/** m of path between whole-map searches while the stretch since lost tracking (or a
	 * re-localisation) is not yet anchored by a loop: where that stretch is relative to the map
	 * before it, the drift window does not say (D46). 0: none. */
	double globalSearchEvery = 2.0;

	/** Every INI key of this struct (ConfigKeys.h; LoopClosureKeys.cpp). */
	static const std::vector<config::Key<LoopClosureOptions>>& keys();
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
	void dumpToTextStream(std::ostream& out) const override;
};

struct LoopClosureStats
{
	std::size_t attempts = 0;  ///< keyframes for which loop candidates were verified
	std::size_t verified = 0;  ///< matches that passed the verification
	/** Verified matches dropped because another visit explained the same scan at a place further off
	 * than searchRadius / searchAngle (a look-alike: which one is right, the scan does not say). */
	std::size_t ambiguous = 0;
	std::size_t accepted = 0;  ///< loop edges added to the graph (agreeing matches)
	std::size_t rejected = 0;  ///< loop edges the chi-square test disables at the end
	std::size_t closures = 0;  ///< loops accepted after a stretch without one
	std::size_t revisits = 0;  ///< edges from front-end matches onto an earlier visit's part of the map
	std::size_t revisitsRejected = 0;  ///< of those, disabled by the chi-square test at the end
	std::size_t globalSearches = 0;	 ///< whole-map searches of a keyframe after lost tracking (D46)
	std::size_t globalVerified = 0;	 ///< their places that passed the verification
	double globalSeconds = 0;  ///< worker time in them (the map before the loss and its pyramid included)
	std::size_t optimizations = 0;
	std::size_t mapUpdates = 0;	 ///< times the map followed the graph (keyframes re-inserted)
	std::size_t reinserted = 0;	 ///< keyframes re-inserted, over all map updates
	std::size_t blocksReplaced = 0;	 ///< map blocks (32 x 32 cells) rebuilt, over all map updates
	double optimizeSeconds = 0;	 ///< of which in the optimiser
	double backendSeconds = 0;	///< worker time: detection, optimisation, map patches
	double waitSeconds = 0;	 ///< time the front-end waited for the worker
};

class LoopClosure
{
   public:
	LoopClosure(const LoopClosureOptions& options, const PerfectMatchMatcher::TConfigParams& matcher,
				const OccupancyGridUpdateOptions& grid);
	~LoopClosure();
	LoopClosure(const LoopClosure&) = delete;
	LoopClosure& operator=(const LoopClosure&) = delete;

	/** A scan that is in every map built (initialize()'s prior keyframes), at a fixed pose. */
	void addFixedScan(const mrpt::math::TPose2D& pose, ScanPoints scan);

	/** A keyframe of an earlier session (pm-slam-app --continue). */
	struct PriorKeyframe
	{
		mrpt::math::TPose2D pose;
		double timestamp = 0;
		ScanPoints scan;
	};
	/** An earlier session's keyframes as the first nodes, before any addKeyframe(): their scans in every
	 * map built and their poses free to move, so loops onto them close like any other and the graph
	 * optimises both sessions together. `graph`: that session's pose graph over exactly these
	 * keyframes, whose edges (odometry, loops, revisits) are taken as they are; without one (or one
	 * of another size), each keyframe is tied to the one before by its relative pose as an odometry
	 * edge. The next keyframe, the new session's first, is tied to the nearest of them by its
	 * front-end match (the start was matched on their map), not to the last one. */
	void addPriorKeyframes(std::vector<PriorKeyframe> keyframes, const PoseGraph* graph);
	/** Nodes that addPriorKeyframes() added (the first ones). */
	std::size_t priorCount() const { return m_priorCount; }
	/** After finish(): the graph without the nodes `retired` marks (nodes renumbered in order), for a
	 * session that retires keyframes newer ones cover. Edges between kept nodes stay; two kept nodes that
	 * followed each other across retired ones are tied by their relative pose as an odometry edge, so
	 * the chain stays connected. */
	PoseGraph graphWithout(const std::vector<bool>& retired) const;

	/** What the worker handed over: the map's blocks that changed, as a map with the moved
	 * keyframes at their optimised poses has them (give both to the front-end's map's
	 * replaceBlocks()), and the rigid correction that takes the front-end's frame to it (apply
	 * it to every pose the front-end holds). */
	struct Update
	{
		std::shared_ptr<const OccupancyDistanceGridMap> patch;
		std::shared_ptr<const BlockMask> blocks;
		mrpt::poses::CPose2D correction;
	};
	/** Waits for the worker (if one runs) and takes its result. Call before addKeyframe(). */
	std::optional<Update> sync();

	/** Adds the keyframe just inserted into the front-end's map at `pose` (front-end frame) and
	 * starts the worker on it. `hessian`: the curvature of its match (map frame); `tracked`: it
	 * was matched, and every scan since the previous keyframe was (false: odometry only);
	 * `searched`: a match since the previous keyframe was placed by a re-localisation search. That, or
	 * lost tracking, makes where the front-end put the robot a hypothesis until a detected loop
	 * confirms it: until then its matches make no revisit edges. `goodness`: of its match (mean PM
	 * likelihood; NaN: unknown). `sigma`: the likelihood field's σ for its lidar (D52), with which
	 * it is verified (NaN: the matcher's). */
	void addKeyframe(const mrpt::math::TPose2D& pose, double timestamp, ScanPoints scan, const Eigen::Matrix3d& hessian,
					 bool tracked, bool searched = false, double goodness = std::nan(""), double sigma = std::nan(""));

	/** End of the log: waits, optimises what is pending, and returns the updates to apply in order
	 * (the worker's last, then one that puts every keyframe that moved since it was inserted at its
	 * final pose; none when the map already has them there), so the map written agrees with the
	 * final trajectory. */
	std::vector<Update> finish();

	/** The graph; only while no worker runs (after finish()). */
	const PoseGraph& graph() const { return m_graph; }
	/** Edge `index` of graph() is a revisit edge (a front-end match onto an earlier visit's keyframe),
	 * not a detected loop; only while no worker runs. */
	bool isRevisit(std::size_t index) const { return index < m_isRevisit.size() && m_isRevisit[index]; }
	std::size_t nodeCount() const { return m_nodes.size(); }
	/** Pose of node `id` as of the last result taken (sync(), finish()): safe while the worker runs. */
	mrpt::math::TPose2D nodePose(std::size_t id) const { return m_published.at(id); }
	/** The accepted loop edges as of the last result taken, as the positions of their two nodes
	 * (for display; safe while the worker runs). */
	const std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>>& loopLinks() const { return m_links; }
	/** Counters; complete after finish() (the worker updates them while it runs). */
	const LoopClosureStats& stats() const { return m_stats; }
	/** Heap bytes held: the keyframes' points, the graph, the published poses (not the worker's
	 * transient local maps and map patches). Valid while no worker runs. */
	std::size_t memoryBytes() const;

   private:
	struct Node
	{
		double travel;	// m of path from the first node
		double timestamp;
		std::shared_ptr<const ScanPoints> scan;
		mrpt::math::TPose2D mapPose;  // where its scan is in the current grid (front-end frame)
		float reach;  // m: the farthest cell its insertion touches from the robot's origin
		double sigma = std::nan("");  // m: σ its lidar's scans are matched with (NaN: the matcher's)
	};
	struct Match
	{
		std::size_t from, to;
		mrpt::math::TPose2D z;
		Eigen::Matrix3d information;
		double window = 0;	// m: the search window it was found in
		bool accepted = false;
	};
	struct JobResult
	{
		std::shared_ptr<const OccupancyDistanceGridMap> patch;
		std::shared_ptr<const BlockMask> blocks;
		mrpt::poses::CPose2D correction;
		bool optimized = false;
		double seconds = 0;
	};
	JobResult runJob(std::size_t node, std::optional<Eigen::Matrix3d> frontEndHessian);	 // on the worker
	void linkRevisit(std::size_t node, const Eigen::Matrix3d& hessian);
	void detect(std::size_t node);
	// A whole-map search of the keyframe on the map from before the loss, its places verified (D46).
	void detectGlobal(std::size_t node);
	// The look-alike test, the agreement of recent matches, and the accepted ones into the graph.
	void admit(std::size_t node, std::vector<Match>& verified);
	// What a local map is built from: keyframes (id, and the graph pose it is built at) and the reach of
	// its distance layer. Equal specs give equal maps.
	struct LocalMapSpec
	{
		std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> keyframes;
		double maxDistance = 0;
		bool operator==(const LocalMapSpec& o) const;
	};
	// A keyframe (`node`) to verify against the visit of keyframe `candidate`: the windows and their
	// centre, and the local map of the candidate's neighbourhood (null until built).
	struct Visit
	{
		std::size_t node = 0, candidate = 0;
		mrpt::math::TPose2D centre;
		double linWindow = 0, angWindow = 0;
		LocalMapSpec local;
		std::shared_ptr<const OccupancyDistanceGridMap> map;
	};
	// The keyframe `node`'s visit of `candidate` in the windows around `centre` (default: where the graph
	// has the keyframe), its local map from the cache if there.
	Visit visit(std::size_t node, std::size_t candidate, double linWindow, double angWindow,
				const std::optional<mrpt::math::TPose2D>& centre = std::nullopt);
	// The visits' matches (one each): the local maps not cached built (and cached), then each visit's
	// match against its local map searched and checked. Both steps run their pieces side by side: they
	// only read the keyframes and the graph, which nothing changes during a job.
	std::vector<std::optional<Match>> verifyVisits(std::vector<Visit> visits);
	std::optional<Match> verifyOn(const Visit& v) const;
	std::shared_ptr<const OccupancyDistanceGridMap> buildLocalMap(const LocalMapSpec& spec) const;
	// The keyframe's returns but those the keyframes just before it saw through (things that moved).
	std::vector<mrpt::math::TPoint2Df> returnsThatStayed(std::size_t node) const;
	// The likelihood pyramids (fine, coarse) of the map of every keyframe before the loss, built once
	// per loss.
	const std::pair<LikelihoodPyramid, LikelihoodPyramid>& mapBeforeLoss();
	// The two matches' relative pose between their keyframes against the graph's (identity: they agree;
	// for two matches of one keyframe, how far apart they put it).
	mrpt::math::TPose2D disagreement(const Match& a, const Match& b) const;
	bool agree(const Match& a, const Match& b) const;
	bool optimizeIfDue(bool force);
	// optimizeIfDue(), then the map patched where keyframes moved: into r. False when nothing was optimised.
	bool optimizeAndPatch(bool force, JobResult& r);
	// When a keyframe moved more than `trigger` (m, a heading change counted at a 5 m lever arm)
	// since it was put into the map, the patch that re-inserts those that moved more than `reinsert`.
	void patchMoved(double trigger, double reinsert, JobResult& r);
	Eigen::Matrix3d odometryInformation(const mrpt::math::TPose2D& z, double scale) const;
	std::size_t nearestNode(const mrpt::math::TPose2D& pose) const;	// by position, of the nodes so far
	// m: three sigmas of the odometry edge `z` across lost tracking, its heading at a 5 m lever arm.
	double untrackedDoubt(const mrpt::math::TPose2D& z) const;
	Eigen::Matrix3d toEdgeFrame(const Eigen::Matrix3d& mapFrameInformation, double fromPhi) const;
	std::optional<Update> take(JobResult r);
	void publish();	 // node poses and loop links for the main thread (no worker running)

	LoopClosureOptions m_opts;
	OccupancyGridUpdateOptions m_gridOpts;
	PerfectMatchMatcher m_matcher;
	std::vector<std::pair<mrpt::math::TPose2D, ScanPoints>> m_fixed;
	std::vector<Node> m_nodes;
	std::size_t m_priorCount = 0;  // the first nodes, an earlier session's (addPriorKeyframes)
	PoseGraph m_graph;
	std::vector<Match> m_matches;  // verified, of the last agreeWindow metres (and all accepted ones)
	double m_lastAttempt = -1e18, m_lastClosure = 0;  // travel (m)
	double m_lastAnchor = 0;  // travel at the last closure not within a stretch placed after lost tracking
	std::size_t m_sinceOptimization = 0, m_pendingLoops = 0;
	std::size_t m_checkedEdges = 0;	 // edges before this index were in an optimisation or its check
	bool m_loopOpen = false;  // a loop was accepted and the graph not yet optimised with it
	// First keyframe after tracking was last lost, until a detected loop reaching back across the loss
	// confirms where the front-end put the robot since (SIZE_MAX: confirmed): no revisit edges meanwhile.
	std::size_t m_unconfirmedFrom = SIZE_MAX;
	std::size_t m_lossStart = SIZE_MAX;	 // the first keyframe of that unconfirmed stretch
	// m: how far the stretch may be off what came before it (untrackedDoubt() summed over its untracked
	// edges; infinite after a re-localisation, which may have taken a look-alike anywhere in its window).
	double m_lossDoubt = 0;
	double m_lastGlobal = -1e18;  // travel (m) at the last whole-map search
	std::size_t m_pyramidsBefore = SIZE_MAX;  // m_beforeLoss holds the keyframes [0, this)
	std::unique_ptr<std::pair<LikelihoodPyramid, LikelihoodPyramid>> m_beforeLoss;
	// Local maps verified against lately, newest first (the worker's only): consecutive attempts at one
	// place verify against the same stretch of an earlier visit.
	std::vector<std::pair<LocalMapSpec, std::shared_ptr<const OccupancyDistanceGridMap>>> m_localMaps;
	std::vector<float> m_goodness;	// of the last tracked keyframes' matches (a ring)
	std::size_t m_goodnessNext = 0;
	bool m_handedOver = false;	// sync() just handed a new grid over: the front-end matched the old one
	std::vector<bool> m_isRevisit;	// per edge (as far as revisit edges were added): from linkRevisit
	std::future<JobResult> m_job;
	std::optional<JobResult> m_inlineResult;
	LoopClosureStats m_stats;
	std::vector<mrpt::math::TPose2D> m_published;
	std::vector<std::pair<mrpt::math::TPoint2D, mrpt::math::TPoint2D>> m_links;
};

}  // namespace pmslam
