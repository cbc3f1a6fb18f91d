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
#include <pmslam/match/CorrelativeSearch.h>
#include <pmslam/sensor/SurfaceNormals.h>
#include <pmslam/slam/PerfectMatchSlam.h>
#include <malloc.h>

#include <Eigen/Eigenvalues>
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
// An odometry step between two scans longer than this, and than kMaxSpeed times the time between
// them, is a glitch (a reset, a corrupt reading), not motion.
constexpr double kMaxOdometryStep = 10.0;  // m
constexpr double kMaxSpeed = 3.0;  // m/s
// odometryToScanTime: two readings closer in time than this are a burst (no usable velocity),
// farther apart than kMaxOdometryGap a pause; a scan this far beyond the newest reading is
// extrapolated no further than kMaxOdometryGap.
constexpr double kMinOdometryGap = 0.01, kMaxOdometryGap = 0.5;  // s
}

void MapBuilderOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
	insertionLinDistance = c.read_double(s, "insertionLinDistance", insertionLinDistance);
	insertionAngDistance = mrpt::DEG2RAD(
		c.read_double(s, "insertionAngDistance_deg", mrpt::RAD2DEG(insertionAngDistance)));
	minGoodness = c.read_double(s, "minGoodness", minGoodness);
	mapInsertLinDistance = c.read_double(s, "mapInsertLinDistance", mapInsertLinDistance);
	mapInsertAngDistance =
		mrpt::DEG2RAD(c.read_double(s, "mapInsertAngDistance_deg", mrpt::RAD2DEG(mapInsertAngDistance)));
	mapInsertBelowInliers = c.read_double(s, "mapInsertBelowInliers", mapInsertBelowInliers);
	minPoints = static_cast<unsigned>(c.read_int(s, "minPoints", static_cast<int>(minPoints)));
	minOverlapGoodness = c.read_double(s, "minOverlapGoodness", minOverlapGoodness);
	degenerateBelow = c.read_double(s, "degenerateBelow", degenerateBelow);
	wideSearchBelowGoodness = c.read_double(s, "wideSearchBelowGoodness", wideSearchBelowGoodness);
	wideSearchLinear = c.read_double(s, "wideSearchLinear", wideSearchLinear);
	wideSearchAngular = mrpt::DEG2RAD(c.read_double(s, "wideSearchAngular_deg", mrpt::RAD2DEG(wideSearchAngular)));
	relocalizeAfterGap = c.read_double(s, "relocalizeAfterGap", relocalizeAfterGap);
	relocalizeAfterJump = c.read_double(s, "relocalizeAfterJump", relocalizeAfterJump);
	relocalizeSpeed = c.read_double(s, "relocalizeSpeed", relocalizeSpeed);
	relocalizeTurnRate =
		mrpt::DEG2RAD(c.read_double(s, "relocalizeTurnRate_deg", mrpt::RAD2DEG(relocalizeTurnRate)));
	relocalizeMaxLinear = c.read_double(s, "relocalizeMaxLinear", relocalizeMaxLinear);
	relocalizeOdometryError = c.read_double(s, "relocalizeOdometryError", relocalizeOdometryError);
	relocalizeAmbiguity = c.read_double(s, "relocalizeAmbiguity", relocalizeAmbiguity);
	newGroundUnexplored = c.read_double(s, "newGroundUnexplored", newGroundUnexplored);
	newGroundAfter = c.read_double(s, "newGroundAfter", newGroundAfter);
	matchWhenScanChanged = c.read_double(s, "matchWhenScanChanged", matchWhenScanChanged);
	odometrySmoothing = c.read_bool(s, "odometrySmoothing", odometrySmoothing);
	odometrySmoothingLag =
		static_cast<unsigned>(c.read_int(s, "odometrySmoothingLag", static_cast<int>(odometrySmoothingLag)));
	odometryToScanTime = c.read_bool(s, "odometryToScanTime", odometryToScanTime);
	scanLatency = c.read_double(s, "scanLatency", scanLatency);
	keepSimpleMap = c.read_bool(s, "keepSimpleMap", keepSimpleMap);
	grid.loadFromConfigFile(c, s);
	auto need = [](bool ok, const std::string& what) {
		if (!ok) throw std::invalid_argument("[MappingApplication] " + what);
	};
	need(insertionLinDistance >= 0 && insertionLinDistance <= 100, "insertionLinDistance: expected 0..100 m");
	need(insertionAngDistance >= 0 && insertionAngDistance <= 2 * M_PI, "insertionAngDistance_deg: expected 0..360");
	need(minGoodness >= 0 && minGoodness <= 1, "minGoodness: expected 0..1");
	need(minOverlapGoodness >= 0 && minOverlapGoodness <= 1, "minOverlapGoodness: expected 0..1 (0 = off)");
	need(wideSearchBelowGoodness >= 0 && wideSearchBelowGoodness <= 1, "wideSearchBelowGoodness: expected 0..1 (0 = off)");
	need(wideSearchLinear >= 0 && wideSearchLinear <= 10, "wideSearchLinear: expected 0..10 m");
	need(wideSearchAngular >= 0 && wideSearchAngular <= M_PI + 1e-9, "wideSearchAngular_deg: expected 0..180");
	need(relocalizeAfterGap > 0, "relocalizeAfterGap: expected > 0 s");
	need(relocalizeAfterJump > 0, "relocalizeAfterJump: expected > 0 m");
	need(relocalizeSpeed >= 0 && relocalizeSpeed <= 10, "relocalizeSpeed: expected 0..10 m/s");
	need(relocalizeTurnRate >= 0 && relocalizeTurnRate <= 2 * M_PI, "relocalizeTurnRate_deg: expected 0..360 deg/s");
	need(relocalizeMaxLinear >= 0 && relocalizeMaxLinear <= 20, "relocalizeMaxLinear: expected 0..20 m");
	need(relocalizeOdometryError >= 0 && relocalizeOdometryError <= 1, "relocalizeOdometryError: expected 0..1");
	need(relocalizeAmbiguity >= 0 && relocalizeAmbiguity <= 1, "relocalizeAmbiguity: expected 0..1 (0 = off)");
	need(newGroundUnexplored >= 0 && newGroundUnexplored <= 1, "newGroundUnexplored: expected 0..1 (0 = off)");
	need(newGroundAfter >= 0, "newGroundAfter: expected >= 0 s");
	need(matchWhenScanChanged >= 0 && matchWhenScanChanged <= 1, "matchWhenScanChanged: expected 0..1 (0 = off)");
	need(degenerateBelow >= 0 && degenerateBelow < 1, "degenerateBelow: expected 0..1 (0 = off)");
	need(mapInsertLinDistance >= 0 && mapInsertAngDistance >= 0, "mapInsertLinDistance, mapInsertAngDistance_deg: expected >= 0");
	need((mapInsertLinDistance > 0) == (mapInsertAngDistance > 0),
		 "mapInsertLinDistance and mapInsertAngDistance_deg: set both (> 0) or neither (0)");
	need(mapInsertBelowInliers >= 0 && mapInsertBelowInliers <= 1, "mapInsertBelowInliers: expected 0..1");
	need(odometrySmoothingLag <= 100, "odometrySmoothingLag: expected 0..100 scans");
	need(scanLatency >= 0 && scanLatency <= 1, "scanLatency: expected 0..1 s");
	need(grid.resolution >= 0.005 && grid.resolution <= 2, "resolution: expected 0.005..2 m");
	need(grid.maxDistance > grid.resolution && grid.maxDistance <= 10, "maxDistance: expected resolution..10 m");
	need(grid.hitProbability > 0.5 && grid.hitProbability < 1, "hitProbability: expected (0.5, 1)");
	need(grid.missProbability > 0 && grid.missProbability < 0.5, "missProbability: expected (0, 0.5)");
	need(grid.clampProbability > 0.5 && grid.clampProbability < 1, "clampProbability: expected (0.5, 1)");
	need(grid.scan.minRange >= 0, "minRange: expected >= 0");
	need(grid.scan.maxHitRange >= 0, "maxHitRange: expected >= 0 (0 = no limit)");
	need(grid.scan.noReturnCarveRange >= 0, "noReturnCarveRange: expected >= 0 (0 = off)");
	need(grid.freeCarveLength >= 0, "freeCarveLength: expected >= 0 m (0 = whole beam)");
	need(grid.freeCarveMarginBeforeHit >= 0 && grid.freeCarveMarginBeforeHit <= 10,
		 "freeCarveMarginBeforeHit: expected 0..10 m");
	need(grid.joinHitsCloserThan >= 0, "joinHitsCloserThan: expected >= 0 m (0 = off)");
}

void MapBuilderOptions::dumpToTextStream(std::ostream& out) const
{
	out << "insertionLinDistance = " << insertionLinDistance
		<< "\ninsertionAngDistance_deg = " << mrpt::RAD2DEG(insertionAngDistance) << "\nminGoodness = " << minGoodness
		<< "\nmapInsertLinDistance = " << mapInsertLinDistance
		<< "\nmapInsertAngDistance_deg = " << mrpt::RAD2DEG(mapInsertAngDistance)
		<< "\nmapInsertBelowInliers = " << mapInsertBelowInliers
		<< "\nminPoints = " << minPoints << "\nminOverlapGoodness = " << minOverlapGoodness
		<< "\ndegenerateBelow = " << degenerateBelow
		<< "\nwideSearchBelowGoodness = " << wideSearchBelowGoodness << "\nwideSearchLinear = " << wideSearchLinear
		<< "\nwideSearchAngular_deg = " << mrpt::RAD2DEG(wideSearchAngular)
		<< "\nrelocalizeAfterGap = " << relocalizeAfterGap << "\nrelocalizeAfterJump = " << relocalizeAfterJump
		<< "\nrelocalizeSpeed = " << relocalizeSpeed
		<< "\nrelocalizeTurnRate_deg = " << mrpt::RAD2DEG(relocalizeTurnRate)
		<< "\nrelocalizeMaxLinear = " << relocalizeMaxLinear << "\nrelocalizeOdometryError = " << relocalizeOdometryError
		<< "\nrelocalizeAmbiguity = " << relocalizeAmbiguity
		<< "\nnewGroundUnexplored = " << newGroundUnexplored << "\nnewGroundAfter = " << newGroundAfter << "\nmatchWhenScanChanged = " << matchWhenScanChanged
		<< "\nodometryToScanTime = " << odometryToScanTime << "\nscanLatency = " << scanLatency
		<< "\nodometrySmoothing = " << odometrySmoothing << "\nodometrySmoothingLag = " << odometrySmoothingLag
		<< "\nkeepSimpleMap = " << keepSimpleMap
		<< "\n";
	grid.dumpToTextStream(out);
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
	m_lastInsertPose = m_pose;
	m_lastMapPose = m_pose;
	m_odometry.reset();
	m_timedOdometry[0].reset();
	m_timedOdometry[1].reset();
	m_timedReadings = m_burstReadings = 0;
	m_odometryAtLastScan.reset();
	m_smoother.reset();
	if (PM_options.odometrySmoothing)
	{
		OdometrySmootherOptions so;
		so.lag = PM_options.odometrySmoothingLag;
		m_smoother.emplace(so);
	}
	m_mapEmpty = true;
	m_scans = m_matched = m_inserted = m_rejected = 0;
	m_wideSearches = m_relocalizations = m_reanchored = 0;
	m_gaps.clear();
	m_lastScanTime = m_lastAcceptedTime = std::nan("");
	m_lost = false;
	m_last = ScanResult();
	m_lastHits.clear();
	m_referenceRanges.clear();
	m_last.pose = m_last.predicted = m_pose;
	m_loops.reset();
	if (LC_options.enabled) m_loops = std::make_unique<LoopClosure>(LC_options, PM_params, PM_options.grid);
	m_trackedSinceKeyframe = true;
	m_searchedSinceKeyframe = false;
	m_frame = mrpt::poses::CPose2D();
	m_frames.assign(1, m_frame);
	m_scanFrame.clear();
	m_scanAnchor.clear();
	m_nodeInFirstFrame.clear();
	// Re-insert a given map's keyframes at their stored poses.
	for (const auto& [posePDF, sf] : initialMap)
	{
		if (!posePDF || !sf) continue;
		const mrpt::math::TPose2D p = mrpt::poses::CPose2D(posePDF->getMeanVal()).asTPose();
		for (const auto& obs : *sf)
			if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(obs.get()))
			{
				ScanPoints pts = scanToPoints(*scan, PM_options.grid.scan);
				m_grid->insertScan(pts, p);
				if (m_loops) m_loops->addFixedScan(p, std::move(pts));
				m_mapEmpty = false;
			}
		if (PM_options.keepSimpleMap) m_initialKeyframes.insert(posePDF, sf);
	}
}

void PerfectMatchSlam::processOdometry(const mrpt::math::TPose2D& odometry, double timestamp)
{
	m_odometry = odometry;
	if (!std::isfinite(timestamp)) return;
	++m_timedReadings;
	if (m_timedOdometry[1] && timestamp - m_timedOdometry[1]->first < kMinOdometryGap) ++m_burstReadings;
	// A reading that does not advance in time (bursts, logs stepping back) is no velocity sample.
	if (m_timedOdometry[1] && timestamp <= m_timedOdometry[1]->first)
	{
		m_timedOdometry[0].reset();
		m_timedOdometry[1] = {timestamp, odometry};
		return;
	}
	m_timedOdometry[0] = m_timedOdometry[1];
	m_timedOdometry[1] = {{timestamp, odometry}};
}

std::optional<mrpt::math::TPose2D> PerfectMatchSlam::odometryAtTime(double t) const
{
	if (!m_timedOdometry[0] || !m_timedOdometry[1] || !std::isfinite(t)) return std::nullopt;
	if (m_timedReadings < 10 || 20 * m_burstReadings > m_timedReadings) return std::nullopt;  // bursty stream
	const auto& [ta, pa] = *m_timedOdometry[0];
	const auto& [tb, pb] = *m_timedOdometry[1];
	const double gap = tb - ta;
	if (gap < kMinOdometryGap || gap > kMaxOdometryGap) return std::nullopt;
	// Constant velocity over the last interval, from the newer reading, at most kMaxOdometryGap
	// ahead (and never before the older reading).
	const double f = std::clamp((t - tb) / gap, -1.0, kMaxOdometryGap / gap);
	const mrpt::poses::CPose2D d = mrpt::poses::CPose2D(pb) - mrpt::poses::CPose2D(pa);
	const mrpt::poses::CPose2D step(f * d.x(), f * d.y(), f * d.phi());
	return (mrpt::poses::CPose2D(pb) + step).asTPose();
}

const PerfectMatchSlam::ScanResult& PerfectMatchSlam::processScan(
	const mrpt::obs::CObservation2DRangeScan& scan, const std::optional<mrpt::math::TPose2D>& odometryAtScan)
{
	using Clock = std::chrono::steady_clock;
	std::lock_guard<std::mutex> lock(mapMutex());
	++m_scans;
	ScanResult r;

	// Predict: apply the odometry increment since the previous scan to the current estimate.
	const std::optional<mrpt::math::TPose2D> odomNow = odometryAtScan ? odometryAtScan : m_odometry;
	// A scan's own odometry that is just the latest reading copied carries no timing of its own.
	// The reported trajectory's smoother gets it moved to the scan's time; the prediction keeps
	// the reading as it is: moving the predictions too changed which revisits snap back onto the
	// map (aces: loops missed in 4 of 15 perturbed runs instead of 3) for no gain of the median.
	std::optional<mrpt::math::TPose2D> odomAtScanTime = odomNow;
	const bool copied = !odometryAtScan || (m_odometry && odometryAtScan->x == m_odometry->x &&
											odometryAtScan->y == m_odometry->y && odometryAtScan->phi == m_odometry->phi);
	if (PM_options.odometryToScanTime && copied && scan.timestamp != INVALID_TIMESTAMP)
		if (const auto o = odometryAtTime(mrpt::Clock::toDouble(scan.timestamp) - PM_options.scanLatency))
			odomAtScanTime = o;
	r.predicted = m_pose;
	const double now = scan.timestamp != INVALID_TIMESTAMP ? mrpt::Clock::toDouble(scan.timestamp) : std::nan("");
	const double sincePrevious = now - m_lastScanTime;	// NaN when unknown
	double odometryStep = 0, odometryTurn = 0;	// m, rad between this scan's odometry and the previous scan's
	if (odomNow && m_odometryAtLastScan)
	{
		const mrpt::poses::CPose2D delta = mrpt::poses::CPose2D(*odomNow) - mrpt::poses::CPose2D(*m_odometryAtLastScan);
		odometryStep = std::hypot(delta.x(), delta.y());
		odometryTurn = delta.phi();
		// No robot moves 10 m between two scans, nor faster than kMaxSpeed across a logging gap:
		// such a jump is an odometry glitch, and following it would throw the robot (and the grid) away.
		const double plausible =
			std::max(kMaxOdometryStep, std::isfinite(sincePrevious) ? kMaxSpeed * sincePrevious : 0.0);
		if (odometryStep < plausible)
			r.predicted = (mrpt::poses::CPose2D(m_pose) + delta).asTPose();
		else
		{
			std::ostringstream m;
			m << "odometry jumped " << odometryStep << " m between two scans: ignored (constant-position prediction)";
			warn(m.str());
		}
	}
	if (odomNow) m_odometryAtLastScan = odomNow;
	r.odometry = odomAtScanTime;
	r.pose = r.predicted;

	const double lin = std::hypot(r.predicted.x - m_lastInsertPose.x, r.predicted.y - m_lastInsertPose.y);
	const double ang = std::abs(mrpt::math::wrapToPi(r.predicted.phi - m_lastInsertPose.phi));
	// Without any odometry the prediction never moves, so every scan is matched.
	const bool odometryMoved =
		!odomNow || lin >= PM_options.insertionLinDistance || ang >= PM_options.insertionAngDistance;
	// A robot that odometry says stands still is matched all the same when its scans say it moves
	// (most ranges changed since the scan last matched or inserted: carried, pushed, or a logger that
	// repeats a stale odometry reading).
	const bool check = !odometryMoved && !m_mapEmpty &&
					   (PM_options.matchWhenScanChanged > 0 && changedFraction(scan) > PM_options.matchWhenScanChanged);
	const bool moved = odometryMoved || check;

	// Where the prediction cannot be trusted, the match searches a wider window: while lost (the
	// last match was rejected), and after a time gap or an odometry jump.
	const bool gap = sincePrevious > PM_options.relocalizeAfterGap;
	const bool jump = odometryStep > PM_options.relocalizeAfterJump;
	double linWindow = PM_options.wideSearchLinear, angWindow = PM_options.wideSearchAngular;
	if (m_lost)
	{
		// Matches rejected: the odometry may be what is wrong (a robot carried, a wheel slipping),
		// so the window grows with the time since the last accepted match.
		const double since = std::isfinite(now - m_lastAcceptedTime) ? now - m_lastAcceptedTime : 0.0;
		linWindow += PM_options.relocalizeSpeed * since;
		angWindow += PM_options.relocalizeTurnRate * since;
	}
	if (gap || jump)
	{
		// A long step between two scans (no scan logged meanwhile): the prediction is as good as
		// the odometry over that step, off by a fraction of the distance and of the turn.
		linWindow += PM_options.relocalizeOdometryError * odometryStep;
		angWindow += PM_options.relocalizeOdometryError * std::abs(odometryTurn);
	}
	// No odometry at all (a lidar alone, live): across a gap the robot went anywhere it could drive
	// in that time (a sensor unplugged and back, scans lost), so the prediction is stale and the
	// window is searched even when the match there looks good (along a corridor it may be a
	// look-alike a few metres back).
	const bool stale = gap && !odomNow && std::isfinite(sincePrevious);
	// ...and, without odometry, until a search has decided where the robot is: the prediction
	// stays the stale one.
	const bool alwaysSearch = stale || (m_lost && !odomNow);
	if (stale)
	{
		linWindow += PM_options.relocalizeSpeed * sincePrevious;
		angWindow += PM_options.relocalizeTurnRate * sincePrevious;
	}
	linWindow = std::min(linWindow, PM_options.relocalizeMaxLinear);
	angWindow = std::min(angWindow, M_PI);
	if (std::isfinite(now)) m_lastScanTime = now;

	if (m_mapEmpty || moved || !mapUpdating())
	{
		const ScanPoints pts = scanToPoints(scan, PM_options.grid.scan);
		if (!m_mapEmpty && (moved || !mapUpdating()) && pts.hits.size() >= PM_options.minPoints)
		{
			const auto t0 = Clock::now();
			const mrpt::math::TPose2D est = matchScan(pts.hits, r.predicted, linWindow, angWindow, r, alwaysSearch);
			r.matchMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
			keepReferenceRanges(scan);
			// A periodic check that finds the robot where odometry says keeps the prediction: only
			// a real displacement (the robot was carried, pushed) moves it, not matching jitter.
			const bool stillThere = check && std::hypot(est.x - r.predicted.x, est.y - r.predicted.y) < 0.05 &&
									std::abs(mrpt::math::wrapToPi(est.phi - r.predicted.phi)) < mrpt::DEG2RAD(1.0);
			if (stillThere)
				;  // not a match: the pose and the insertion gate stay as they were
			else if (!r.undecided && acceptable(r.info))
			{
				r.pose = est;
				// Only odometry can say where the robot is along a direction the scan leaves open: without
				// any, the prediction is where the robot was, and holding it there would stop a lidar
				// alone in its tracks along a corridor.
				if (PM_options.degenerateBelow > 0 && odomNow)
				{
					if (const auto weak = weakDirection(surfaceCurvature(pts.hits, est)))
					{
						// Match again with the position along the weak direction held at the prediction
						// (a stiff prior there and nowhere else): across it and in heading the scan decides.
						// Where the scan only just constrains that direction, the match has a share of the
						// say there, so the position does not jump between match and prediction as a far
						// feature comes and goes from one scan to the next.
						const Eigen::Vector2d& dir = weak->direction;
						const Eigen::Vector2d off(est.x - r.predicted.x, est.y - r.predicted.y);
						const double keep = weak->matchShare * dir.dot(off);  // along dir, from the prediction
						PerfectMatchMatcher::PosePrior pin;
						pin.mean = mrpt::math::TPose2D(r.predicted.x + keep * dir[0], r.predicted.y + keep * dir[1], est.phi);
						pin.information.topLeftCorner<2, 2>() = 1e6 * dir * dir.transpose();
						const Eigen::Vector2d start = Eigen::Vector2d(est.x, est.y) - (dir.dot(off) - keep) * dir;
						r.pose = m_matcher.alignPoints(m_grid->distanceMap(), pts.hits,
													   mrpt::math::TPose2D(start[0], start[1], est.phi), nullptr,
													   nullptr, &pin);
						r.degenerate = true;
					}
				}
				r.matched = true;
				++m_matched;
				// Placed by a re-localisation: a hypothesis for the back-end.
				if (r.relocalized) m_searchedSinceKeyframe = true;
				m_lastHits = pts.hits;  // for getCurrentPoseEstimation()
			}
			else
			{
				r.rejected = true;
				++m_rejected;
				// Lost for a while and the scan lies in space no scan has observed yet, at the
				// prediction: the robot is on new ground (after a gap it drove somewhere never mapped).
				// Nothing can be matched, so the scan goes in at the odometry pose and the map grows from
				// there on. A scan over mapped space that does not match (the prediction is off) keeps
				// being rejected instead of corrupting the map.
				const double lostFor = m_gaps.empty() || !m_gaps.back().open ? 0.0 : now - m_gaps.back().from;
				if (PM_options.newGroundUnexplored > 0 && lostFor >= PM_options.newGroundAfter &&
					m_grid->unexploredFraction(pts.hits, r.predicted) >= PM_options.newGroundUnexplored)
				{
					r.reanchored = true;
					++m_reanchored;
				}
			}
		}
		// A rejected match is not inserted either: its pose is only the odometry guess,
		// and a scan at a wrong pose would corrupt the map for every later match.
		const bool rejected = !m_mapEmpty && !r.matched && !r.reanchored;
		bool insert = mapUpdating() && (m_mapEmpty || moved) && !pts.hits.empty() && !rejected;
		// Keyframe-like insertion: a scan the map already explains is matched but not inserted,
		// so the map is not redrawn (and blurred) at every slightly drifted pose.
		if (insert && !m_mapEmpty && PM_options.mapInsertLinDistance > 0)
		{
			const double ml = std::hypot(r.pose.x - m_lastMapPose.x, r.pose.y - m_lastMapPose.y);
			const double ma = std::abs(mrpt::math::wrapToPi(r.pose.phi - m_lastMapPose.phi));
			if (ml < PM_options.mapInsertLinDistance && ma < PM_options.mapInsertAngDistance &&
				r.info.inlierFraction >= PM_options.mapInsertBelowInliers)
			{
				m_lastInsertPose = r.pose;	// the next match is gated from here
				insert = false;
			}
		}
		if (insert)
		{
			// The back-end's work since the last keyframe: a new map at corrected poses, if any.
			const auto tw = Clock::now();
			if (m_loops)
				if (auto u = m_loops->sync()) applyMapCorrection(*u, r);
			const auto t0 = Clock::now();
			r.backendWaitMs = std::chrono::duration<double, std::milli>(t0 - tw).count();
			r.cellsFlipped = m_grid->insertScan(pts, r.pose);
			if (m_referenceRanges.empty()) keepReferenceRanges(scan);
			r.updateMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
			r.inserted = true;
			m_lastInsertPose = r.pose;
			m_lastMapPose = r.pose;
			m_mapEmpty = false;
			++m_inserted;
			if (PM_options.keepSimpleMap) m_keyframes.add(r.pose, scan);
			if (m_loops)
			{
				m_nodeInFirstFrame.push_back((-m_frame + mrpt::poses::CPose2D(r.pose)).asTPose());
				m_loops->addKeyframe(r.pose, now, pts, r.info.hessian, (r.matched || m_loops->nodeCount() == 0) && m_trackedSinceKeyframe,
									 m_searchedSinceKeyframe, r.matched ? r.info.goodness : std::nan(""));
				m_trackedSinceKeyframe = true;
				m_searchedSinceKeyframe = false;
			}
		}
	}
	if (r.rejected || r.reanchored) m_trackedSinceKeyframe = false;
	// Tracking state: a rejected match opens (or extends) a gap, an accepted one closes it.
	if (r.rejected)
	{
		if (m_gaps.empty() || !m_gaps.back().open) m_gaps.push_back({now, now, 0, true});
		m_gaps.back().to = now;
		++m_gaps.back().scans;
		m_lost = true;
	}
	else if (r.matched)
	{
		if (!m_gaps.empty() && m_gaps.back().open)
		{
			m_gaps.back().to = now;
			m_gaps.back().open = false;
		}
		m_lost = false;
		m_lastAcceptedTime = now;
	}
	m_pose = r.pose;
	if (m_loops)
	{
		m_scanFrame.push_back(static_cast<uint32_t>(m_frames.size() - 1));
		m_scanAnchor.push_back(m_loops->nodeCount() ? static_cast<uint32_t>(m_loops->nodeCount() - 1) : UINT32_MAX);
	}
	// The smoother works in the first frame, where the poses are continuous across map corrections.
	if (m_smoother) m_smoother->add(m_scans - 1, (-m_frame + mrpt::poses::CPose2D(r.pose)).asTPose(), r.odometry);
	m_last = r;
	return m_last;
}

Eigen::Matrix3d PerfectMatchSlam::surfaceCurvature(const std::vector<mrpt::math::TPoint2Df>& hits,
												   const mrpt::math::TPose2D& pose) const
{
	// Each point pulling only across its surface: dots and wall ends in the map do not count as
	// constraints, so a plain corridor shows that it does not fix the pose along it.
	const std::vector<mrpt::math::TPoint2Df> normals = surfaceNormals(hits);
	return m_matcher.evaluate(m_grid->distanceMap(), hits, pose, &normals).hessian;
}

std::optional<PerfectMatchSlam::WeakDirection> PerfectMatchSlam::weakDirection(const Eigen::Matrix3d& hessian) const
{
	// The information on the position at the matched heading: a plain corridor fixes the heading
	// and the position across it, not along it. Below degenerateBelow x the largest the scan has no
	// say along it; up to five times that, a share growing linearly from none to all.
	if (!hessian.allFinite()) return std::nullopt;
	const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(hessian.topLeftCorner<2, 2>());
	if (eig.info() != Eigen::Success) return std::nullopt;
	const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
	constexpr double kAllAt = 5;  // x degenerateBelow: from there on the match alone decides
	const double t = PM_options.degenerateBelow;
	if (!(lambda[1] > 0) || lambda[0] >= kAllAt * t * lambda[1]) return std::nullopt;
	const double ratio = std::max(lambda[0], 0.0) / lambda[1];
	return WeakDirection{Eigen::Vector2d(eig.eigenvectors().col(0)), std::clamp((ratio - t) / ((kAllAt - 1) * t), 0.0, 1.0)};
}

double PerfectMatchSlam::changedFraction(const mrpt::obs::CObservation2DRangeScan& scan) const
{
	// Beams valid in both scans whose range moved by more than 0.1 m.
	const std::size_t n = scan.getScanSize();
	std::size_t both = 0, moved = 0;
	if (m_referenceRanges.size() != n) return 1.0;	// another sensor, or none yet: unknown, so check
	for (std::size_t i = 0; i < n; ++i)
		if (scan.getScanRangeValidity(i) && m_referenceRanges[i] > 0)
		{
			++both;
			moved += std::abs(scan.getScanRange(i) - m_referenceRanges[i]) > 0.1f;
		}
	return both >= 10 ? double(moved) / double(both) : 0.0;
}

void PerfectMatchSlam::keepReferenceRanges(const mrpt::obs::CObservation2DRangeScan& scan)
{
	const std::size_t n = scan.getScanSize();
	m_referenceRanges.resize(n);
	for (std::size_t i = 0; i < n; ++i) m_referenceRanges[i] = scan.getScanRangeValidity(i) ? scan.getScanRange(i) : 0.0f;
}

bool PerfectMatchSlam::acceptable(const PerfectMatchMatcher::MatchInfo& info) const
{
	if (info.goodness >= PM_options.minGoodness) return true;
	// Mostly new ground: trust the part that overlaps the map, if there is enough of it.
	return PM_options.minOverlapGoodness > 0 && info.inlierGoodness >= PM_options.minOverlapGoodness &&
		   info.inlierFraction * info.nPoints >= PM_options.minPoints;
}

mrpt::math::TPose2D PerfectMatchSlam::matchScan(const std::vector<mrpt::math::TPoint2Df>& hits,
												 const mrpt::math::TPose2D& predicted, double linWindow,
												 double angWindow, ScanResult& r, bool alwaysSearch)
{
	const DynamicDistanceMap& dm = m_grid->distanceMap();
	// PM from `start`.
	auto align = [&](const mrpt::math::TPose2D& start, PerfectMatchMatcher::MatchInfo& info) {
		return m_matcher.alignPoints(dm, hits, start, &info);
	};
	mrpt::math::TPose2D best = align(predicted, r.info);
	// The cheap test: a match that explains the scan well needs no search, whatever came before
	// (after a gap, a jump or a rejection the window is only wider).
	const bool poor = PM_options.wideSearchBelowGoodness > 0 && r.info.goodness < PM_options.wideSearchBelowGoodness;
	if ((!poor && !alwaysSearch) || (linWindow <= 0 && angWindow <= 0)) return best;
	r.wideSearch = true;
	++m_wideSearches;

	const std::vector<CorrelativeSearch::Candidate> starts =
		CorrelativeSearch::coarseToFine(dm, hits, predicted, linWindow, angWindow);
	// A pose away from the prediction must be clearly better than the match there, and explain
	// the scan as a normal match does: after a gap or in a look-alike place a mediocre candidate
	// is more often a wrong pose than a right one. A stale prediction (alwaysSearch) has no such
	// claim: the best explanation of the scan wins.
	const double margin = alwaysSearch ? 0.0 : 0.15;
	double bestGoodness = std::max(r.info.goodness + margin, PM_options.wideSearchBelowGoodness);
	// A re-localisation window (wider than the wide basin's) holds look-alike places.
	const bool relocalizing = linWindow > PM_options.wideSearchLinear + 1e-9 || angWindow > PM_options.wideSearchAngular + 1e-9;
	std::vector<std::pair<mrpt::math::TPose2D, double>> refined;	// every candidate, refined, and its score
	const mrpt::math::TPose2D atPrediction = best;
	const PerfectMatchMatcher::MatchInfo predictionInfo = r.info;
	for (const auto& c : starts)
	{
		PerfectMatchMatcher::MatchInfo info;
		const mrpt::math::TPose2D p = align(c.pose, info);
		refined.emplace_back(p, info.goodness);
		if (info.goodness > bestGoodness)
		{
			bestGoodness = info.goodness;
			best = p;
			r.info = info;
			r.relocalized = true;
		}
	}
	// In a re-localisation window, a clearly different pose that explains the scan nearly as well
	// (a look-alike room, a repetitive corridor) leaves the pose undecided: keep searching on the
	// next scans, from where the robot moves to somewhere that tells them apart.
	if (r.relocalized && relocalizing && PM_options.relocalizeAmbiguity > 0)
		for (const auto& [p, g] : refined)
		{
			const bool distinct = std::hypot(p.x - best.x, p.y - best.y) > 0.5 ||
								  std::abs(mrpt::math::wrapToPi(p.phi - best.phi)) > mrpt::DEG2RAD(5.0);
			if (distinct && g > bestGoodness - PM_options.relocalizeAmbiguity)
			{
				// A stale prediction is no fallback: where a lidar alone was before a gap it is not now.
				r.undecided = alwaysSearch;
				r.relocalized = false;
				r.info = predictionInfo;
				best = atPrediction;
				break;
			}
		}
	if (r.relocalized) ++m_relocalizations;
	return best;
}

std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> PerfectMatchSlam::takeSmoothedPoses(bool finish)
{
	std::lock_guard<std::mutex> lock(mapMutex());
	if (!m_smoother) return {};
	if (finish) m_smoother->finish();
	auto out = m_smoother->takeFinal();
	if (m_loops)  // back to the frame the front-end had at each scan
		for (auto& [i, p] : out)
			if (i < m_scanFrame.size()) p = (m_frames[m_scanFrame[i]] + mrpt::poses::CPose2D(p)).asTPose();
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
	move(m_lastInsertPose);
	move(m_lastMapPose);
	m_frame = T + m_frame;
	m_frames.push_back(m_frame);
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
	if (PM_options.keepSimpleMap && m_keyframes.size() == m_loops->nodeCount())
		for (std::size_t i = 0; i < m_keyframes.size(); ++i) m_keyframes.setPose(i, m_loops->nodePose(i));
}

std::vector<mrpt::math::TPose2D> PerfectMatchSlam::correctedTrajectory(const std::vector<mrpt::math::TPose2D>& online) const
{
	std::vector<mrpt::math::TPose2D> out = online;
	if (!m_loops) return out;
	for (std::size_t i = 0; i < out.size() && i < m_scanAnchor.size(); ++i)
	{
		const uint32_t n = m_scanAnchor[i];
		if (n == UINT32_MAX || n >= m_nodeInFirstFrame.size()) continue;
		// In the first frame the scan sits at a fixed offset from its keyframe; the keyframe
		// goes where the graph has it, and the scan with it.
		const mrpt::poses::CPose2D inFirst = -m_frames[m_scanFrame[i]] + mrpt::poses::CPose2D(online[i]);
		const mrpt::poses::CPose2D offset = inFirst - mrpt::poses::CPose2D(m_nodeInFirstFrame[n]);
		out[i] = (mrpt::poses::CPose2D(m_loops->nodePose(n)) + offset).asTPose();
	}
	return out;
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
	{
		const mrpt::poses::CPose2D base = m_odometry ? mrpt::poses::CPose2D(*m_odometry) : mrpt::poses::CPose2D();
		m_odometry = (base + mov->poseChange->getMeanVal()).asTPose();
		if (!m_odometryAtLastScan) m_odometryAtLastScan = base.asTPose();
	}
	for (const auto& obs : in_SF) processObservation(obs);
}

mrpt::poses::CPose3DPDF::Ptr PerfectMatchSlam::getCurrentPoseEstimation() const
{
	auto pdf = mrpt::poses::CPose3DPDFGaussian::Create();
	pdf->mean = mrpt::poses::CPose3D(mrpt::poses::CPose2D(m_pose));
	if (m_last.matched)
	{
		// Along a plain corridor the pose is reported as unknown, not as fixed by dots and wall ends.
		Eigen::Matrix3d H = surfaceCurvature(m_lastHits, m_pose);
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
