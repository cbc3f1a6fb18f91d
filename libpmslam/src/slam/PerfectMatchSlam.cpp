/* pmslam — online Perfect Match SLAM (see PerfectMatchSlam.h). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <pmslam/slam/PerfectMatchSlam.h>
#include <malloc.h>

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace pmslam
{
namespace
{
// Views after which look-alike rivals still undecided are let go, and the scans searched anew.
constexpr std::size_t kMaxRivalViews = 20;
// D47: a match on a fixed map is rejected when more than this share of its beams, each cut this
// much short of its end, crosses the map's walls.
constexpr double kMaxWallCrossing = 0.5;
constexpr double kWallCrossingMargin = 0.35;  // m

// Each part of the front-end gets its own options, taken from MapBuilderOptions.
MotionModelOptions motionOptions(const MapBuilderOptions& o)
{
	MotionModelOptions m;
	m.odometryToScanTime = o.odometryToScanTime;
	m.scanLatency = o.scanLatency;
	m.relocalizeAfterGap = o.relocalizeAfterGap;
	m.relocalizeAfterJump = o.relocalizeAfterJump;
	return m;
}

KeyframeGateOptions gateOptions(const MapBuilderOptions& o)
{
	KeyframeGateOptions g;
	g.matchLinDistance = o.matchLinDistance;
	g.matchAngDistance = o.matchAngDistance;
	g.mapInsertLinDistance = o.mapInsertLinDistance;
	g.mapInsertAngDistance = o.mapInsertAngDistance;
	g.mapInsertBelowInliers = o.mapInsertBelowInliers;
	return g;
}

HypothesisSearchOptions searchOptions(const MapBuilderOptions& o)
{
	HypothesisSearchOptions h;
	h.wideSearchBelowGoodness = o.wideSearchBelowGoodness;
	h.minGoodness = o.minGoodness;
	h.wideSearchLinear = o.wideSearchLinear;
	h.wideSearchAngular = o.wideSearchAngular;
	h.relocalizeSpeed = o.relocalizeSpeed;
	h.relocalizeTurnRate = o.relocalizeTurnRate;
	h.relocalizeOdometryError = o.relocalizeOdometryError;
	h.relocalizeMaxLinear = o.relocalizeMaxLinear;
	h.relocalizeAmbiguity = o.relocalizeAmbiguity;
	return h;
}

TrackerOptions trackerOptions(const MapBuilderOptions& o)
{
	TrackerOptions t;
	t.minGoodness = o.minGoodness;
	t.minOverlapGoodness = o.minOverlapGoodness;
	t.minPoints = o.minPoints;
	t.newGroundUnexplored = o.newGroundUnexplored;
	t.newGroundAfter = o.newGroundAfter;
	return t;
}

double millisecondsSince(std::chrono::steady_clock::time_point t0)
{
	return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}

PerfectMatchSlam::PerfectMatchSlam() { initialize(); }

PerfectMatchSlam::~PerfectMatchSlam() = default;

void PerfectMatchSlam::warn(const std::string& message) const { std::cerr << "pmslam: warning: " << message << "\n"; }

void PerfectMatchSlam::initialize(const mrpt::maps::CSimpleMap& initialMap, const mrpt::poses::CPosePDF* x0)
{
	std::lock_guard<std::mutex> lock(mapMutex());
	m_grid = std::make_shared<OccupancyDistanceGridMap>(PM_options.grid);
	m_metricMap.maps.clear();
	m_metricMap.maps.push_back(m_grid);
	m_initialKeyframes.clear();
	m_keyframes.clear();
	m_matcher.options = PM_params;
	m_pose = x0 ? x0->getMeanVal().asTPose() : mrpt::math::TPose2D(0, 0, 0);
	m_motion.emplace(motionOptions(PM_options));
	m_gate.emplace(gateOptions(PM_options), m_pose);
	m_standstill.emplace(StandstillCheckOptions{PM_options.matchWhenScanChanged});
	m_hypotheses.emplace(searchOptions(PM_options));
	m_degenerate.emplace(DegenerateDirectionsOptions{PM_options.degenerateBelow});
	m_tracker.emplace(trackerOptions(PM_options));
	RivalsOptions rivals;
	// A true match scores 0.8-0.98; a lidar alone may be re-localised only where the scans fit that well.
	rivals.minLeaderGoodness = 0.75;
	// Decided only once the robot has moved: a view from a new place, and its motion, must agree.
	rivals.minViews = 2;
	m_rivals.emplace(rivals);
	m_scanMotion.emplace(PM_options.grid.resolution, PM_options.grid.maxDistance);
	m_noise.emplace(PM_params.sigma);
	m_revised.clear();
	m_revisedLater.clear();
	m_lostPoses.clear();
	m_smoother.reset();
	if (PM_options.odometrySmoothing)
	{
		OdometrySmootherOptions so;
		so.lag = PM_options.odometrySmoothingLag;
		m_smoother.emplace(so);
	}
	m_mapEmpty = true;
	m_scans = m_matched = m_inserted = m_rejected = m_ambiguous = 0;
	m_wideSearches = m_relocalizations = m_reanchored = m_crossedWalls = 0;
	m_last = ScanResult();
	m_lastHits.clear();
	m_last.pose = m_last.predicted = m_pose;
	m_loops.reset();
	if (LC_options.enabled) m_loops = std::make_unique<LoopClosure>(LC_options, PM_params, PM_options.grid);
	m_frames = FrameHistory();
	m_priorPoses.clear();
	m_retired.clear();
	m_priorTimes.clear();
	// Re-insert a given map's keyframes at their stored poses.
	forEachKeyframeScan(initialMap, *m_grid, [&](const mrpt::math::TPose2D& p, double, ScanPoints pts) {
		m_mapEmpty = false;
		if (m_loops) m_loops->addFixedScan(p, std::move(pts));
	});
	keepInitialKeyframes(initialMap);
}

template <class F>
void PerfectMatchSlam::forEachKeyframeScan(const mrpt::maps::CSimpleMap& keyframes, OccupancyDistanceGridMap& grid,
										   F&& f) const
{
	// Each keyframe's scans into `grid` at the keyframe's pose, and to `f`.
	for (const auto& [posePDF, sf] : keyframes)
	{
		if (!posePDF || !sf) continue;
		const mrpt::math::TPose2D p = mrpt::poses::CPose2D(posePDF->getMeanVal()).asTPose();
		for (const auto& obs : *sf)
			if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(obs.get()))
			{
				ScanPoints pts = scanToPoints(*scan, PM_options.grid.scan);
				grid.insertScan(pts, p);
				f(p, mrpt::Clock::toDouble(scan->timestamp), std::move(pts));
			}
	}
}

void PerfectMatchSlam::keepInitialKeyframes(const mrpt::maps::CSimpleMap& keyframes)
{
	// Written back out as given (saveSimpleMap), ahead of this run's keyframes.
	if (!PM_options.keepSimpleMap) return;
	for (const auto& [posePDF, sf] : keyframes)
		if (posePDF && sf) m_initialKeyframes.insert(posePDF, sf);
}

void PerfectMatchSlam::continueSession(const mrpt::maps::CSimpleMap& keyframes, const PoseGraph* graph,
									   const mrpt::math::TPose2D& start)
{
	const mrpt::poses::CPosePDFGaussian x0{mrpt::poses::CPose2D(start)};
	initialize(mrpt::maps::CSimpleMap(), &x0);
	std::lock_guard<std::mutex> lock(mapMutex());
	std::vector<LoopClosure::PriorKeyframe> prior;
	forEachKeyframeScan(keyframes, *m_grid, [&](const mrpt::math::TPose2D& p, double t, ScanPoints pts) {
		m_mapEmpty = false;
		m_priorPoses.push_back(p);
		m_priorTimes.push_back(t);
		if (!m_loops) return;
		m_frames.addKeyframe(p);
		prior.push_back({p, t, std::move(pts)});
	});
	keepInitialKeyframes(keyframes);
	if (m_loops) m_loops->addPriorKeyframes(std::move(prior), graph);
	// The log may begin on ground the map does not hold (the start found further along it, carried
	// back): its first scan goes in at the start if the map cannot place it.
	m_tracker->startAtKnownPose();
}

std::vector<bool> PerfectMatchSlam::retireCoveredKeyframes(double linear, double angular)
{
	std::lock_guard<std::mutex> lock(mapMutex());
	const std::size_t prior = m_initialKeyframes.size();
	m_retired.assign(prior, false);
	if (!m_loops || m_loops->priorCount() != prior || prior + m_keyframes.size() != m_loops->nodeCount())
		return m_retired;
	for (std::size_t i = 0; i < prior; ++i)
	{
		const mrpt::math::TPose2D a = m_loops->nodePose(i);
		for (std::size_t j = prior; j < m_loops->nodeCount() && !m_retired[i]; ++j)
		{
			const mrpt::math::TPose2D b = m_loops->nodePose(j);
			m_retired[i] = std::hypot(a.x - b.x, a.y - b.y) <= linear &&
						   std::abs(mrpt::math::wrapToPi(a.phi - b.phi)) <= angular;
		}
	}
	for (std::size_t i = prior; i-- > 0;)
		if (m_retired[i]) m_initialKeyframes.remove(i);
	// The map anew from the keyframes kept, at their final poses.
	auto grid = std::make_shared<OccupancyDistanceGridMap>(PM_options.grid);
	forEachKeyframeScan(m_keyframes.toSimpleMap(m_initialKeyframes), *grid, [](auto&&...) {});
	m_grid = std::move(grid);
	m_metricMap.maps.clear();
	m_metricMap.maps.push_back(m_grid);
	return m_retired;
}

PoseGraph PerfectMatchSlam::outputGraph() const
{
	if (!m_loops) return {};
	// Nothing retired: the graph as it is (its rejected loop edges included, written as comments).
	if (std::none_of(m_retired.begin(), m_retired.end(), [](bool r) { return r; })) return m_loops->graph();
	std::vector<bool> retired = m_retired;
	retired.resize(m_loops->nodeCount(), false);
	return m_loops->graphWithout(retired);
}

std::vector<mrpt::math::TPose2D> PerfectMatchSlam::correctedPriorPoses(const std::vector<mrpt::math::TPose2D>& poses,
																	   const std::vector<double>& times,
																	   std::size_t firstKeyframe,
																	   std::size_t keyframes) const
{
	// Each pose moves with the latest keyframe of its part taken before it (the one it was tracked
	// from), as the graph moved that keyframe.
	std::vector<mrpt::math::TPose2D> out = poses;
	if (!m_loops || m_loops->priorCount() != m_priorPoses.size()) return out;
	const std::size_t end = std::min(m_priorPoses.size(), firstKeyframe + keyframes);
	if (firstKeyframe >= end) return out;
	for (std::size_t i = 0; i < out.size(); ++i)
	{
		std::size_t k = firstKeyframe;
		while (k + 1 < end && m_priorTimes[k + 1] <= times[i]) ++k;
		const mrpt::poses::CPose2D offset = mrpt::poses::CPose2D(poses[i]) - mrpt::poses::CPose2D(m_priorPoses[k]);
		out[i] = (mrpt::poses::CPose2D(m_loops->nodePose(k)) + offset).asTPose();
	}
	return out;
}

void PerfectMatchSlam::processOdometry(const mrpt::math::TPose2D& odometry, double timestamp)
{
	m_motion->addReading(odometry, timestamp);
}

const PerfectMatchSlam::ScanResult& PerfectMatchSlam::processScan(
	const mrpt::obs::CObservation2DRangeScan& scan, const std::optional<mrpt::math::TPose2D>& odometryAtScan)
{
	std::lock_guard<std::mutex> lock(mapMutex());
	++m_scans;
	ScanResult r;
	// Predict the pose from odometry, and how far off the prediction may be.
	const MotionPrediction motion = predict(scan, odometryAtScan);
	r.predicted = r.pose = motion.pose;
	r.odometry = motion.odometryAtScanTime;
	const SearchWindow window = m_hypotheses->window(motion, m_tracker->lost(), m_tracker->lostFor(motion.time));

	// Match once odometry says the robot moved past the gate (without any odometry every scan is
	// matched), or once its scans say it moves while odometry says it stands still.
	const bool odometryMoved = !motion.odometry || m_gate->moved(r.predicted);
	const bool standstillCheck = !odometryMoved && !m_mapEmpty && m_standstill->scansSayMoved(scan);
	const bool moved = odometryMoved || standstillCheck;
	std::optional<TrackingState> verdict;  // none: not matched
	std::optional<ScanPoints> pts;	// none: not looked at
	if (m_mapEmpty || moved || !mapUpdating())
	{
		pts = scanToPoints(scan, PM_options.grid.scan);
		// D52: the σ of this lidar's noise, measured on the scans that go into the map (on a fixed
		// map, on the scans matched).
		if (!mapUpdating()) m_noise->add(scan.sensorLabel, pts->hits, {scan.sensorPose.x(), scan.sensorPose.y()});
		m_matcher.options.sigma = m_noise->sigma(scan.sensorLabel);
		if (!m_mapEmpty && (moved || !mapUpdating()) && pts->hits.size() >= PM_options.minPoints)
			verdict = matchScan(scan, *pts, motion, window, standstillCheck, r);
	}
	// Before an insertion, whose loop-closure sync may move the map's frame: the revised poses are
	// in the frame the lost scans were reported in.
	reviseLostStretch(verdict, r);
	// A rejected match is not inserted either: its pose is only the odometry guess, and a scan at a
	// wrong pose would corrupt the map for every later match. Nor is a scan the map already explains
	// (the keyframe gate).
	const bool rejected = !m_mapEmpty && !r.matched && !r.reanchored;
	if (pts && mapUpdating() && (m_mapEmpty || moved) && !pts->hits.empty() && !rejected &&
		(m_mapEmpty || m_gate->admits(r.pose, r.info.inlierFraction)))
		insertKeyframe(scan, *pts, motion.time, r);
	m_tracker->update(verdict, r.relocalized, r.inserted, motion.time);
	if (r.matched) m_motion->matched(r.pose, motion.time);
	// While look-alike rivals are undecided the scan is reported at the leader's pose, but the search
	// stays centred where the robot was last known: the leader may be the look-alike.
	m_pose = r.undecided && !m_rivals->empty() ? r.predicted : r.pose;
	if (m_loops) m_frames.addScan(m_loops->nodeCount());
	// The smoother works in the first frame, where the poses are continuous across map corrections.
	if (m_smoother) m_smoother->add(m_scans - 1, m_frames.toFirst(r.pose), r.odometry);
	m_last = r;
	return m_last;
}

void PerfectMatchSlam::reviseLostStretch(const std::optional<TrackingState>& verdict, const ScanResult& r)
{
	// While lost a scan is reported where the odometry predicts it, and across the loss (a drop-out, a
	// gap, a slip) that prediction carries one error, which the match ending the loss measures: the
	// same odometry chain, moved by it, is where those scans were. A scan inserted on new ground is in
	// the map where it was reported and stays; look-alike rivals' scans get the winner's path instead.
	if (verdict == TrackingState::Tracking)
	{
		const mrpt::poses::CPose2D error = mrpt::poses::CPose2D(r.pose) + (-mrpt::poses::CPose2D(r.predicted));
		for (const auto& [i, p] : m_lostPoses)
		{
			m_revised.emplace_back(i, (error + mrpt::poses::CPose2D(p)).asTPose());
			// Placed by this scan's match: they move with the graph as the keyframes after the loss do.
			if (m_loops) m_frames.anchorToNextKeyframe(i);
		}
		m_lostPoses.clear();
	}
	else if (!r.undecided && (verdict == TrackingState::Lost || (!verdict && m_tracker->lost())))
		m_lostPoses.emplace_back(m_scans - 1, r.pose);
	else
		m_lostPoses.clear();
}

Hypothesis PerfectMatchSlam::searchOrFollowRivals(const ScanPoints& pts, const ScanResult& r, const SearchWindow& window)
{
	// Rivals from an earlier scan: each moved as the scans say the robot moved since (the
	// prediction's motion where they cannot tell), matched, and judged.
	if (!m_rivals->empty())
	{
		const auto guess = (mrpt::poses::CPose2D(r.predicted) - mrpt::poses::CPose2D(m_pose)).asTPose();
		const auto motion = m_scanMotion->motion(m_matcher, pts.hits, guess).value_or(guess);
		m_rivals->follow(m_matcher, m_grid->distanceMap(), pts.hits, motion, {0, 0}, m_scans - 1);
		if (!m_rivals->empty())
		{
			Hypothesis h;
			h.pose = m_rivals->leader().pose;
			h.info = m_rivals->leader().info;
			h.wideSearch = true;
			h.relocalized = m_rivals->decide();
			h.undecided = !h.relocalized;
			if (h.relocalized)
			{
				const auto& path = m_rivals->leader().path;
				m_revised.insert(m_revised.end(), path.begin(), path.end() - 1);	 // this scan's pose is set as usual
			}
			if (h.relocalized || m_rivals->views() >= kMaxRivalViews) m_rivals->clear();
			return h;
		}
	}
	Hypothesis best = m_hypotheses->search(m_matcher, m_grid->distanceMap(), pts.hits, r.predicted, window);
	for (const auto& c : best.rivals) m_rivals->add(c.pose, c.pose, c.info, m_scans - 1, c.prior);
	if (!m_rivals->empty())
	{
		// A stale prediction's candidates, look-alikes or a lone one: nothing is decided (nor
		// inserted) until the scans from a new place agree.
		m_scanMotion->keep(pts.hits);
		m_rivals->decide();
		best.pose = m_rivals->leader().pose;  // reported (not matched) while undecided
		best.info = m_rivals->leader().info;
		best.relocalized = false;
		best.undecided = true;
	}
	return best;
}

MotionPrediction PerfectMatchSlam::predict(const mrpt::obs::CObservation2DRangeScan& scan,
										   const std::optional<mrpt::math::TPose2D>& odometryAtScan)
{
	const MotionPrediction motion = m_motion->predict(scan.timestamp, odometryAtScan, m_pose);
	if (motion.glitch)
	{
		std::ostringstream m;
		m << "odometry jumped " << motion.step << " m between two scans: ignored (constant-position prediction)";
		warn(m.str());
	}
	return motion;
}

std::optional<TrackingState> PerfectMatchSlam::matchScan(const mrpt::obs::CObservation2DRangeScan& scan,
														 const ScanPoints& pts, const MotionPrediction& motion,
														 const SearchWindow& window, bool standstillCheck, ScanResult& r)
{
	const auto t0 = std::chrono::steady_clock::now();
	const Hypothesis best = searchOrFollowRivals(pts, r, window);
	if (best.fromAlternative) r.predicted = *window.alternative;  // the prediction the scan agreed with
	r.matchMs = millisecondsSince(t0);
	r.info = best.info;
	r.wideSearch = best.wideSearch;
	r.relocalized = best.relocalized;
	r.undecided = best.undecided;
	m_wideSearches += best.wideSearch;
	m_relocalizations += best.relocalized;
	m_standstill->keep(scan);
	// A standstill check that finds the robot where odometry says keeps the prediction: not a
	// match, the pose and the gate stay as they were.
	if (standstillCheck && StandstillCheck::stillThere(best.pose, r.predicted)) return std::nullopt;
	// On a fixed map, space no scan observed is off the map: the robot cannot be "on new ground"
	// there (nothing would be inserted), only lost.
	TrackingState verdict = m_tracker->judge(r.info, r.undecided, motion.gap, motion.time, [&] {
		return mapUpdating() ? m_grid->unexploredFraction(pts.hits, r.predicted) : 0.0;
	});
	if (verdict == TrackingState::Tracking && crossesWalls(pts, best.pose))
	{
		verdict = TrackingState::Lost;
		++m_crossedWalls;
	}
	if (verdict != TrackingState::Tracking)
	{
		// Reported, for now, where the motion model has the robot: the odometry's prediction, or
		// without odometry (a stale one) the leading look-alike. A decision revises these poses.
		if (r.undecided && !m_rivals->empty() && !motion.odometry) r.pose = best.pose;
		r.rejected = true;
		++m_rejected;
		m_ambiguous += verdict == TrackingState::Ambiguous;
		r.reanchored = verdict == TrackingState::NewGround;
		m_reanchored += r.reanchored;
		return verdict;
	}
	r.pose = best.pose;
	// Along a direction the scan leaves open only odometry can say where the robot is: without any,
	// the prediction is where the robot was, and holding it would stop a lidar alone in a corridor.
	if (motion.odometry)
		if (const auto held = m_degenerate->hold(m_matcher, m_grid->distanceMap(), pts.hits, best.pose, r.predicted))
		{
			r.pose = *held;
			r.degenerate = true;
		}
	r.matched = true;
	++m_matched;
	m_lastHits = pts.hits;	// for getCurrentPoseEstimation()
	return verdict;
}

bool PerfectMatchSlam::crossesWalls(const ScanPoints& pts, const mrpt::math::TPose2D& pose) const
{
	// D47. Only a fixed map is trusted to say where walls are: a map being built may still hold a
	// wall the scans are about to see through (a door that opened), and its walls came from the
	// very poses being judged.
	if (mapUpdating()) return false;
	return m_grid->crossedWallFraction(pts, pose, kWallCrossingMargin) > kMaxWallCrossing;
}

void PerfectMatchSlam::placeAt(const mrpt::math::TPose2D& pose)
{
	std::lock_guard<std::mutex> lock(mapMutex());
	// The recent matches move with the robot: the velocity a lidar alone is predicted with is the
	// one they had, not a jump from where the robot was thought to be to where it is.
	m_motion->correct(mrpt::poses::CPose2D(pose) + (-mrpt::poses::CPose2D(m_pose)));
	m_pose = m_last.pose = pose;
	m_gate.emplace(gateOptions(PM_options), m_pose);
	m_rivals->clear();
}

double PerfectMatchSlam::untrackedFor(double now) const { return m_tracker->lostFor(now); }

bool PerfectMatchSlam::lost() const { return m_tracker->lost(); }

void PerfectMatchSlam::insertKeyframe(const mrpt::obs::CObservation2DRangeScan& scan, const ScanPoints& pts,
									  double now, ScanResult& r)
{
	// The back-end's work since the last keyframe: a new map at corrected poses, if any.
	const auto tw = std::chrono::steady_clock::now();
	if (m_loops)
		if (auto u = m_loops->sync()) applyMapCorrection(*u, r);
	const auto t0 = std::chrono::steady_clock::now();
	r.backendWaitMs = std::chrono::duration<double, std::milli>(t0 - tw).count();
	r.cellsFlipped = m_grid->insertScan(pts, r.pose);
	m_noise->add(scan.sensorLabel, pts.hits, {scan.sensorPose.x(), scan.sensorPose.y()});
	if (!m_standstill->hasReference()) m_standstill->keep(scan);
	r.updateMs = millisecondsSince(t0);
	r.inserted = true;
	m_gate->inserted(r.pose);
	m_mapEmpty = false;
	++m_inserted;
	if (PM_options.keepSimpleMap) m_keyframes.add(r.pose, scan);
	if (!m_loops) return;
	m_frames.addKeyframe(r.pose);
	const Tracker::KeyframeEvidence e = m_tracker->keyframeEvidence(r.matched, r.relocalized, m_loops->nodeCount() == 0);
	m_loops->addKeyframe(r.pose, now, pts, r.info.hessian, e.tracked, e.searched,
						 r.matched ? r.info.goodness : std::nan(""), m_noise->sigma(scan.sensorLabel));
}

std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> PerfectMatchSlam::takeSmoothedPoses(bool finish)
{
	std::lock_guard<std::mutex> lock(mapMutex());
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> out;
	if (m_smoother)
	{
		if (finish) m_smoother->finish();
		out = m_smoother->takeFinal();
		if (m_loops)  // back to the frame the front-end had at each scan
			for (auto& [i, p] : out) p = m_frames.toScanFrame(i, p);
	}
	// Scans reported while look-alike rivals were undecided: where the winner had them. The smoother
	// had them where they were reported (the prediction, or the leader of the moment), so its poses
	// of those scans, now or when it gets to them, give way to the winner's.
	for (auto& [i, p] : out)
		if (const auto it = m_revisedLater.find(i); it != m_revisedLater.end()) p = it->second;
	if (!out.empty()) m_revisedLater.erase(m_revisedLater.begin(), m_revisedLater.upper_bound(out.back().first));
	if (m_smoother)
		for (const auto& [i, p] : m_revised) m_revisedLater[i] = p;
	out.insert(out.end(), m_revised.begin(), m_revised.end());
	m_revised.clear();
	return out;
}

void PerfectMatchSlam::applyMapCorrection(LoopClosure::Update& u, ScanResult& r)
{
	// The map's changed blocks, at the graph's poses; every pose the front-end holds moves with it.
	const mrpt::poses::CPose2D& T = u.correction;
	const auto move = [&](mrpt::math::TPose2D& p) { p = (T + mrpt::poses::CPose2D(p)).asTPose(); };
	move(r.pose);
	move(r.predicted);
	move(m_pose);
	m_motion->correct(T);
	m_gate->correct(T);
	m_frames.correct(T);
	m_grid->replaceBlocks(*u.patch, *u.blocks);
	u.patch.reset();
	u.blocks.reset();
	malloc_trim(0);  // the patch's blocks came from the worker's heap: give its pages back
	r.mapCorrected = true;
}

void PerfectMatchSlam::finishLoopClosure()
{
	std::lock_guard<std::mutex> lock(mapMutex());
	if (!m_loops) return;
	for (auto& u : m_loops->finish())
	{
		ScanResult scratch;
		applyMapCorrection(u, scratch);
	}
	const std::size_t prior = m_loops->priorCount();
	if (PM_options.keepSimpleMap && prior + m_keyframes.size() == m_loops->nodeCount())
	{
		for (std::size_t i = 0; i < m_keyframes.size(); ++i) m_keyframes.setPose(i, m_loops->nodePose(prior + i));
		for (std::size_t i = 0; i < prior && i < m_initialKeyframes.size(); ++i)
		{
			auto& kf = m_initialKeyframes.getAsPair(i);
			kf.pose = mrpt::poses::CPose3DPDFGaussian::Create(
				mrpt::poses::CPose3D(mrpt::poses::CPose2D(m_loops->nodePose(i))), kf.pose->getCovariance());
		}
	}
}

std::vector<mrpt::math::TPose2D> PerfectMatchSlam::correctedTrajectory(const std::vector<mrpt::math::TPose2D>& online) const
{
	if (!m_loops) return online;
	return m_frames.corrected(online, *m_loops);
}

void PerfectMatchSlam::processObservation(const mrpt::obs::CObservation::Ptr& obs)
{
	if (!obs) return;
	if (const auto* odo = dynamic_cast<const mrpt::obs::CObservationOdometry*>(obs.get()))
		processOdometry(odo->odometry.asTPose(), odo->timestamp != INVALID_TIMESTAMP
													 ? mrpt::Clock::toDouble(odo->timestamp)
													 : std::nan(""));
	else if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(obs.get()))
		processScan(*scan);
}

void PerfectMatchSlam::processActionObservation(mrpt::obs::CActionCollection& action,
												   mrpt::obs::CSensoryFrame& in_SF)
{
	// Actions carry odometry increments: accumulate them into an odometry pose.
	if (const auto mov = action.getBestMovementEstimation())
		m_motion->addIncrement(mov->poseChange->getMeanVal());
	for (const auto& obs : in_SF) processObservation(obs);
}

mrpt::poses::CPose3DPDF::Ptr PerfectMatchSlam::getCurrentPoseEstimation() const
{
	auto pdf = mrpt::poses::CPose3DPDFGaussian::Create();
	pdf->mean = mrpt::poses::CPose3D(mrpt::poses::CPose2D(m_pose));
	if (m_last.matched)
	{
		// Along a plain corridor the pose is reported as unknown, not as fixed by dots and wall ends.
		Eigen::Matrix3d H = DegenerateDirections::surfaceCurvature(m_matcher, m_grid->distanceMap(), m_lastHits, m_pose);
		H.diagonal().array() += 1e-6;
		const Eigen::Matrix3d C = H.inverse();
		const int idx[3] = {0, 1, 3};  // x, y, yaw in the 6D covariance
		for (int i = 0; i < 3; ++i)
			for (int j = 0; j < 3; ++j) pdf->cov(idx[i], idx[j]) = C(i, j);
	}
	return pdf;
}

void PerfectMatchSlam::getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const
{
	out_map = m_keyframes.toSimpleMap(m_initialKeyframes);
}

unsigned int PerfectMatchSlam::getCurrentlyBuiltMapSize()
{
	return static_cast<unsigned>(m_initialKeyframes.size() + m_keyframes.size());
}

void PerfectMatchSlam::saveSimpleMapGz(const std::string& path) const
{
	m_keyframes.saveSimpleMapGz(path, m_initialKeyframes);
}

const mrpt::maps::CMultiMetricMap* PerfectMatchSlam::getCurrentlyBuiltMetricMap() const
{
	// MRPT code reads the grid as a dense COccupancyGridMap2D: give it a snapshot of the cells.
	m_grid->materialize();
	return &m_metricMap;
}

void PerfectMatchSlam::saveCurrentEstimationToImage(const std::string& file, bool)
{
	// MRPT's writer reads the dense view: made for the call, then given back.
	m_grid->materialize();
	const bool ok = m_grid->saveAsBitmapFile(file);
	m_grid->releaseMaterialized();
	if (!ok) throw std::runtime_error("cannot write map image '" + file + "'");
}

void PerfectMatchSlam::initializeWithFixedMap(const mrpt::maps::COccupancyGridMap2D& grid,
												 const mrpt::math::TPose2D& initialPose)
{
	const double r = grid.getResolution();
	const unsigned sx = grid.getSizeX(), sy = grid.getSizeY();
	if (!(r > 0) || sx == 0 || sy == 0)
		throw std::invalid_argument("PerfectMatchSlam::initializeWithFixedMap: empty grid");
	const auto& cells = grid.getRawMap();
	// MRPT stores the log-odds of a cell being free: negative = occupancy above 0.5.
	if (std::none_of(cells.begin(), cells.end(), [](auto c) { return c < 0; }))
		throw std::invalid_argument("PerfectMatchSlam::initializeWithFixedMap: the grid has no occupied cell");

	const mrpt::poses::CPosePDFGaussian x0{mrpt::poses::CPose2D(initialPose)};
	initialize(mrpt::maps::CSimpleMap(), &x0);

	std::lock_guard<std::mutex> lock(mapMutex());
	OccupancyGridUpdateOptions o = PM_options.grid;
	o.resolution = r;
	o.maxDistance = std::max(o.maxDistance, 2 * r);
	auto fixed = std::make_shared<OccupancyDistanceGridMap>(o);
	// The distance layer's cell (i, j) is [i·r, (i+1)·r) × [j·r, (j+1)·r): the grid's origin must be
	// a multiple of r. Grids made by MRPT's setSize() and by pmslam are; otherwise the same cells are
	// put on the nearest lattice origin (a shift < r/2). The raw cells are copied as they are.
	const long offX = std::lround(grid.getXMin() / r), offY = std::lround(grid.getYMin() / r);
	m_fixedMapShift = {offX * r - grid.getXMin(), offY * r - grid.getYMin()};
	if (std::abs(m_fixedMapShift.x) <= 1e-3 * r && std::abs(m_fixedMapShift.y) <= 1e-3 * r)
		m_fixedMapShift = {0, 0};
	else
	{
		char m[200];
		std::snprintf(
			m, sizeof(m),
			"fixed map origin (%.6f, %.6f) is not a multiple of its resolution %.4f m: map shifted by (%.4f, %.4f) m",
			grid.getXMin(), grid.getYMin(), r, m_fixedMapShift.x, m_fixedMapShift.y);
		warn(m);
	}
	if (std::abs(offX) > 1e8 || std::abs(offY) > 1e8)
		throw std::invalid_argument("PerfectMatchSlam::initializeWithFixedMap: grid origin out of range");
	fixed->assignCells(grid, int(offX), int(offY));

	m_grid = std::move(fixed);
	m_metricMap.maps.clear();
	m_metricMap.maps.push_back(m_grid);
	m_mapEmpty = false;
	m_loops.reset();  // the map is fixed: nothing to close
	setMapUpdating(false);
}

}  // namespace pmslam
