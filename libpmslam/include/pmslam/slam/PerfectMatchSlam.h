/* pmslam — online Perfect Match SLAM.
 *
 * Feed it odometry and laser scans (or MRPT action/observation pairs and plain
 * observations) and it keeps the current pose, the map (an
 * OccupancyDistanceGridMap inside a CMultiMetricMap) and the keyframes that
 * built it (a CSimpleMap). CMetricMapBuilderPM puts the same object behind
 * MRPT's mrpt::slam::CMetricMapBuilder interface; this class needs no mrpt-slam,
 * so a program that only maps (pm-slam-app) does not load it and the ~120
 * shared libraries behind it (about 30 MB of resident memory).
 *
 * The loop (Pedrosa, Lau, Reis): the first scan is inserted at (0,0,0) without
 * matching. Each later scan's pose is predicted from odometry; once the robot
 * has moved more than the insertion thresholds since the last insertion, the
 * scan is matched against the map with the Perfect Match aligner starting from
 * the prediction, and inserted at the corrected pose. Scans below the threshold
 * keep the odometry-propagated pose. Every scan gets a pose.
 *
 * The front-end is a pipeline of small parts that processScan() wires, each made
 * anew from the options by initialize(): MotionModel (odometry as a measurement:
 * the prediction, and how far to trust it), KeyframeGate (which scans are matched,
 * which go into the map), StandstillCheck (a robot odometry says stands still while
 * its scans say it moves), HypothesisSearch (the match from the prediction, the wide
 * and re-localisation searches), DegenerateDirections (the prediction kept along a
 * plain corridor), Tracker (tracking, ambiguous, lost, new ground; the untracked
 * gaps) and FrameHistory (the frames of the loop closure's corrections).
 *
 * Localisation: initializeWithFixedMap() loads a prior COccupancyGridMap2D
 * and turns map updating off; every scan is then matched against that fixed
 * map and nothing is inserted.
 *
 * Frames: poses are of the robot base in the map frame (metres, radians);
 * the first scan's pose is the origin of the map frame unless initialize()
 * is given x0 (or the fixed map's frame is used). Scans carry their own
 * sensorPose relative to the base (offset, yawed or upside-down lasers).
 * Odometry is used only through its increments, so its frame does not matter.
 */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/poses/CPosePDF.h>
#include <pmslam/graph/LoopClosure.h>
#include <pmslam/slam/DegenerateDirections.h>
#include <pmslam/slam/FrameHistory.h>
#include <pmslam/slam/HypothesisSearch.h>
#include <pmslam/slam/KeyframeGate.h>
#include <pmslam/slam/KeyframeStore.h>
#include <pmslam/slam/MotionModel.h>
#include <pmslam/slam/OdometrySmoother.h>
#include <pmslam/slam/Rivals.h>
#include <pmslam/slam/ScanToScan.h>
#include <pmslam/slam/SensorNoise.h>
#include <pmslam/slam/StandstillCheck.h>
#include <pmslam/slam/Tracker.h>
#include <pmslam/map/OccupancyDistanceGridMap.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <optional>
#include <utility>
#include <vector>

namespace pmslam
{
/** Builder options; INI section [MappingApplication] (grid keys in the same section). */
struct MapBuilderOptions : public mrpt::config::CLoadableOptions
{
	// Each key's one-line doc is in MapBuilderKeys.cpp (and docs/configuration.md); why each
	// default is what it is, with the evidence, is the decision named (docs/decisions.md).
	double matchLinDistance = 0.01;	 ///< m moved before a scan is matched (D6)
	double matchAngDistance = 2.0 * M_PI / 180.0;  ///< rad turned before a scan is matched (D6)
	double minGoodness = 0.3;  ///< matches scoring below are rejected (D7)
	double mapInsertLinDistance = 0.3;	///< m moved before a matched scan goes into the map (D8)
	double mapInsertAngDistance = mrpt::DEG2RAD(6.0);  ///< rad, likewise (D8)
	double mapInsertBelowInliers = 0.95;  ///< new ground: inserted below this share of inliers (D8)
	bool odometryToScanTime = true;	 ///< the smoother gets odometry at the scan's time (D20)
	double scanLatency = 0.08;	///< s between a scan being taken and its stamp (D20)
	/** Reported trajectory fused with the odometry increments, final odometrySmoothingLag scans
	 * later; the map and the predictions keep the matched poses (D21). Read with takeSmoothedPoses(). */
	bool odometrySmoothing = true;
	unsigned odometrySmoothingLag = 3;
	double minOverlapGoodness = 0.6;  ///< mostly-new-ground matches accepted when the overlap agrees (D13)
	double degenerateBelow = 0.02;	///< directions the scan leaves open keep the prediction (D19)
	double wideSearchBelowGoodness = 0.7;  ///< the wide basin's trigger (D12)
	double wideSearchLinear = 0.5;	///< m, its half-width (D12)
	double wideSearchAngular = mrpt::DEG2RAD(30.0);	 ///< rad (D12)
	double relocalizeAfterGap = 2.0;  ///< s: a longer step between scans is a gap (D15)
	double relocalizeAfterJump = 1.0;  ///< m: a longer odometry step is one too (D15)
	double relocalizeSpeed = 0.5;  ///< m/s: growth of the window while matches are rejected (D16)
	double relocalizeTurnRate = mrpt::DEG2RAD(30.0);  ///< rad/s, likewise (D16)
	double relocalizeOdometryError = 0.1;  ///< share of the odometry over a gap (D15)
	double relocalizeMaxLinear = 8.0;  ///< m: the widest window (D16)
	double relocalizeAmbiguity = 0.05;	///< a re-localisation must win by this (D17)
	double newGroundUnexplored = 0.8;  ///< lost on new ground: insert at the odometry pose (D14)
	double newGroundAfter = 2.0;  ///< s lost before that (D14)
	double matchWhenScanChanged = 0.3;	///< scans that move while odometry stands still (D18)
	unsigned minPoints = 20;  ///< scans with fewer usable returns are not matched
	bool keepSimpleMap = true;	///< keep every inserted scan and pose as a CSimpleMap
	OccupancyGridUpdateOptions grid;

	/** Every INI key of this struct, the grid's included (ConfigKeys.h; MapBuilderKeys.cpp). */
	static const std::vector<config::Key<MapBuilderOptions>>& keys();
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
	void dumpToTextStream(std::ostream& out) const override;
};

class PerfectMatchSlam
{
   public:
	PerfectMatchSlam();
	virtual ~PerfectMatchSlam();

	MapBuilderOptions PM_options;  ///< mapping options (apply before initialize())
	PerfectMatchMatcher::TConfigParams PM_params;  ///< matcher options
	LoopClosureOptions LC_options;	///< loop closure (apply before initialize(); off in localisation)

	/** What happened to the last scan. */
	struct ScanResult
	{
		mrpt::math::TPose2D pose;  ///< robot pose assigned to the scan (map frame)
		mrpt::math::TPose2D predicted;	///< odometry prediction it started from
		std::optional<mrpt::math::TPose2D> odometry;  ///< odometry at the scan's time, as the smoother got it (its own frame)
		bool matched = false, inserted = false;
		bool wideSearch = false;  ///< the wide search ran for this scan
		bool relocalized = false;  ///< the wide search found a better pose than the match from the prediction
		bool undecided = false;	 ///< a stale prediction's search found look-alike poses: not matched, searched again
		bool rejected = false;	///< matched, but the match was not trusted (the pose is the prediction)
		bool degenerate = false;  ///< the scan left a direction unconstrained: the prediction was kept along it
		bool reanchored = false;  ///< lost on new ground: inserted at the odometry pose (newGroundUnexplored)
		bool mapCorrected = false;	///< a loop closure's new map was handed over at this scan (poses moved)
		double matchMs = 0, updateMs = 0;  ///< wall time of matching and of the map update
		/** Wall time waiting for the loop-closure back-end (at keyframes, while it still works on the
		 * previous one) and taking over its new map: not front-end work. */
		double backendWaitMs = 0;
		std::size_t cellsFlipped = 0;
		PerfectMatchMatcher::MatchInfo info;
	};

	// --- what CMetricMapBuilder asks for (CMetricMapBuilderPM makes these its overrides) ---
	/** Resets; optionally starts from an existing map (its scans are re-inserted) and pose x0. */
	void initialize(const mrpt::maps::CSimpleMap& initialMap = mrpt::maps::CSimpleMap(),
					const mrpt::poses::CPosePDF* x0 = nullptr);
	/** Localisation on a prior map: resets the builder, loads `grid` (any COccupancyGridMap2D,
	 * e.g. read from a .gridmap.gz written by pm-slam-app or by MRPT) as the fixed map, puts the
	 * robot at `initialPose` (robot base in the grid's frame; m, m, rad) and turns map updating
	 * off (setMapUpdating(false)): from then on every scan with enough returns is
	 * matched against the fixed map starting from the odometry prediction, and nothing is inserted
	 * (the keyframe CSimpleMap stays empty). Cells with occupancy above 0.5 are the obstacles.
	 *
	 * The map keeps the grid's own resolution (PM_options.grid.resolution is not used; the
	 * distance truncation PM_options.grid.maxDistance is, at least two cells). The distance layer
	 * needs cell boundaries on multiples of the resolution. MRPT's setSize() and deserialisation
	 * put every grid there; one whose origin is off that lattice (resizeGrid() tolerates 5 % of a
	 * cell) is moved onto the nearest lattice position, cells unchanged, i.e. shifted by less than
	 * half a cell per axis (see fixedMapShift()), with a warning (warn()).
	 * Throws std::invalid_argument for an empty grid or one without any occupied cell.
	 * To map again afterwards: setMapUpdating(true) and initialize(). */
	void initializeWithFixedMap(const mrpt::maps::COccupancyGridMap2D& grid, const mrpt::math::TPose2D& initialPose);
	/** pm-slam-app --continue: resets, puts an earlier session's `keyframes` (with their scans) into the map
	 * and, with loop closure, into the pose graph as its first nodes (LoopClosure::addPriorKeyframes;
	 * `graph`: that session's graph over them, if any), and puts the robot at `start`. Mapping then goes
	 * on; the keyframes may move as the graph is optimised (finishLoopClosure() gives them their final
	 * poses in the simple map). */
	void continueSession(const mrpt::maps::CSimpleMap& keyframes, const PoseGraph* graph, const mrpt::math::TPose2D& start);
	/** After continueSession() and finishLoopClosure(): `poses` of an earlier session (at `times`, s),
	 * each moved with the latest of the keyframes [firstKeyframe, firstKeyframe + keyframes) taken at
	 * or before it (the part of the session it belongs to), as the graph moved that keyframe. */
	std::vector<mrpt::math::TPose2D> correctedPriorPoses(const std::vector<mrpt::math::TPose2D>& poses,
														 const std::vector<double>& times, std::size_t firstKeyframe,
														 std::size_t keyframes) const;
	/** Lifelong use, after continueSession() and finishLoopClosure(): each earlier keyframe that a keyframe of
	 * this run covers (within `linear` m and `angular` rad, final poses) is retired: out of the keyframes
	 * (getCurrentlyBuiltMap()), and the map is rebuilt from those kept, so it shows the place as this run saw
	 * it (a moved cabinet) and the keyframe count follows the area, not the hours driven. Returns, per
	 * earlier keyframe, whether it was retired. outputGraph() leaves them out as well. */
	std::vector<bool> retireCoveredKeyframes(double linear, double angular);
	/** The pose graph to write: the back-end's (rejected loop edges included); after retireCoveredKeyframes()
	 * retired some, without them (and without the rejected edges); empty without loop closure. */
	PoseGraph outputGraph() const;
	/** Sub-cell shift (m) applied to the last fixed map to put it on the resolution lattice
	 * (zero for every grid pmslam or MRPT's setSize() made). */
	mrpt::math::TPoint2D fixedMapShift() const { return m_fixedMapShift; }

	mrpt::poses::CPose3DPDF::Ptr getCurrentPoseEstimation() const;
	void processActionObservation(mrpt::obs::CActionCollection& action, mrpt::obs::CSensoryFrame& in_SF);
	void getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out_map) const;
	unsigned int getCurrentlyBuiltMapSize();
	const mrpt::maps::CMultiMetricMap* getCurrentlyBuiltMetricMap() const;
	void saveCurrentEstimationToImage(const std::string& file, bool formatEMF_BMP = true);

	/** Observation-only entry: CObservationOdometry updates odometry, CObservation2DRangeScan is processed. */
	void processObservation(const mrpt::obs::CObservation::Ptr& obs);

	// --- direct entry points (what the above call) ---
	/** Latest odometry reading of the robot base (any frame; only increments are used), with
	 * its time (s; NaN = unknown) for odometryToScanTime. */
	void processOdometry(const mrpt::math::TPose2D& odometry, double timestamp = std::nan(""));
	/** Processes one scan; `odometryAtScan`, when given, is the odometry at the scan's time
	 * (Carmen FLASER lines carry it) and takes precedence over processOdometry() readings. */
	const ScanResult& processScan(const mrpt::obs::CObservation2DRangeScan& scan,
								  const std::optional<mrpt::math::TPose2D>& odometryAtScan = std::nullopt);

	/** With odometrySmoothing: the scans whose reported pose became final since the last call,
	 * oldest first, as (scan number from 0 in processScan() order, pose). With `finish`, every
	 * pose still waiting for its look-ahead is finalised too (end of the log). */
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> takeSmoothedPoses(bool finish = false);
	const OdometrySmoother* smoother() const { return m_smoother ? &*m_smoother : nullptr; }

	/** Loop closure, at the end of the log: waits for the back-end, optimises what is pending and
	 * rebuilds the map at the final poses (so the map written matches the final trajectory); the
	 * keyframes (getCurrentlyBuiltMap()) get their optimised poses. No-op without loop closure. */
	void finishLoopClosure();
	/** The final trajectory: each scan's pose as reported online (takeSmoothedPoses() or
	 * ScanResult::pose, scan order) moved with the keyframe it was tracked from to where the
	 * optimised graph has it. Without loop closure: `online` as it is. */
	std::vector<mrpt::math::TPose2D> correctedTrajectory(const std::vector<mrpt::math::TPose2D>& online) const;
	/** The back-end (nullptr when loop closure is off). */
	const LoopClosure* loopClosure() const { return m_loops.get(); }

	const ScanResult& lastScanResult() const { return m_last; }
	mrpt::math::TPose2D currentPose() const { return m_pose; }
	const OccupancyDistanceGridMap& grid() const { return *m_grid; }
	/** Writes getCurrentlyBuiltMap()'s keyframes to a .simplemap.gz without materialising
	 * them all at once (see KeyframeStore). */
	void saveSimpleMapGz(const std::string& path) const;
	std::size_t scansProcessed() const { return m_scans; }
	std::size_t scansMatched() const { return m_matched; }
	std::size_t scansInserted() const { return m_inserted; }
	std::size_t scansRejected() const { return m_rejected; }
	/** Scans among the rejected whose pose look-alike places left undecided (reported at the leader's). */
	std::size_t scansAmbiguous() const { return m_ambiguous; }
	std::size_t wideSearches() const { return m_wideSearches; }
	std::size_t relocalizations() const { return m_relocalizations; }
	std::size_t reanchorings() const { return m_reanchored; }
	/** On a fixed map: matches rejected because their beams crossed the map's walls (D47). */
	std::size_t wallCrossings() const { return m_crossedWalls; }
	/** Each lidar's range noise as its scans show it, and the likelihood field's σ from it (D52). */
	const SensorNoise& sensorNoise() const { return *m_noise; }

	/** The robot is at `pose` now, as something other than the tracker found (a global search on
	 * a fixed map after tracking was lost): the next scan is predicted from there. */
	void placeAt(const mrpt::math::TPose2D& pose);
	/** Seconds of log from the last accepted match to `now` while tracking is lost; 0 while tracking. */
	double untrackedFor(double now) const;
	/** No match accepted since the last rejected one (or since the start). */
	bool lost() const;

	/** A stretch of the log where no match was accepted (see Tracker.h). */
	using TrackingGap = pmslam::TrackingGap;
	/** Every such stretch so far, oldest first. */
	const std::vector<TrackingGap>& trackingGaps() const { return m_tracker->gaps(); }

	/** Whether scans are inserted into the map (off after initializeWithFixedMap()). */
	virtual bool mapUpdating() const { return m_mapUpdating; }
	virtual void setMapUpdating(bool on) { m_mapUpdating = on; }

   protected:
	/** One-line warnings (an odometry glitch, a fixed map moved onto the lattice); std::cerr here. */
	virtual void warn(const std::string& message) const;
	/** Held while a scan or the map changes; CMetricMapBuilderPM uses MRPT's critZoneChangingMap. */
	virtual std::mutex& mapMutex() const { return m_mutex; }

   private:
	bool m_mapUpdating = true;
	mutable std::mutex m_mutex;
	std::shared_ptr<OccupancyDistanceGridMap> m_grid;
	mrpt::maps::CMultiMetricMap m_metricMap;
	mrpt::maps::CSimpleMap m_initialKeyframes;  // of initialize(initialMap), kept as given
	KeyframeStore m_keyframes;	// the scans inserted since, compact
	PerfectMatchMatcher m_matcher;
	// The front-end's parts, made anew from the options by initialize().
	std::optional<MotionModel> m_motion;
	std::optional<KeyframeGate> m_gate;
	std::optional<StandstillCheck> m_standstill;
	std::optional<HypothesisSearch> m_hypotheses;
	std::optional<DegenerateDirections> m_degenerate;
	std::optional<Tracker> m_tracker;
	std::optional<ScanToScan> m_scanMotion;	// the rivals' motion: the scans' own odometry
	std::optional<SensorNoise> m_noise;	 // each lidar's range noise, and the σ its scans are matched with
	std::optional<Rivals> m_rivals;	// look-alike poses of a lidar alone after a gap, until the scans decide
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> m_revised;	 // the winner's poses of undecided scans
	std::map<std::size_t, mrpt::math::TPose2D> m_revisedLater;	// ... replacing the smoother's, still to come
	// Scans reported at the prediction while lost, since the last accepted match or insertion (D57).
	std::vector<std::pair<std::size_t, mrpt::math::TPose2D>> m_lostPoses;
	std::optional<OdometrySmoother> m_smoother;
	mrpt::math::TPose2D m_pose{0, 0, 0};  // current estimate
	bool m_mapEmpty = true;
	std::size_t m_scans = 0, m_matched = 0, m_inserted = 0, m_rejected = 0, m_ambiguous = 0;
	std::size_t m_wideSearches = 0, m_relocalizations = 0, m_reanchored = 0, m_crossedWalls = 0;
	ScanResult m_last;
	std::vector<mrpt::math::TPoint2Df> m_lastHits;	// of the last matched scan (robot frame)
	mrpt::math::TPoint2D m_fixedMapShift{0, 0};
	std::vector<mrpt::math::TPose2D> m_priorPoses;	// continueSession's keyframes, as given
	std::vector<double> m_priorTimes;  // and their scans' times (s)
	std::vector<bool> m_retired;  // per continueSession keyframe: retired (retireCoveredKeyframes)
	// Loop closure: the back-end, and the frames the front-end worked in as its maps came in.
	std::unique_ptr<LoopClosure> m_loops;
	FrameHistory m_frames;

	// The steps of processScan().
	MotionPrediction predict(const mrpt::obs::CObservation2DRangeScan& scan,
							 const std::optional<mrpt::math::TPose2D>& odometryAtScan);
	bool crossesWalls(const ScanPoints& pts, const mrpt::math::TPose2D& pose) const;
	/** D57: the scans reported at the prediction while lost, moved by the error of that prediction
	 * that the match ending the loss measured (into m_revised). */
	void reviseLostStretch(const std::optional<TrackingState>& verdict, const ScanResult& r);
	template <class F>
	void forEachKeyframeScan(const mrpt::maps::CSimpleMap& keyframes, OccupancyDistanceGridMap& grid, F&& f) const;
	void keepInitialKeyframes(const mrpt::maps::CSimpleMap& keyframes);
	Hypothesis searchOrFollowRivals(const ScanPoints& pts, const ScanResult& r, const SearchWindow& window);
	std::optional<TrackingState> matchScan(const mrpt::obs::CObservation2DRangeScan& scan, const ScanPoints& pts,
										   const MotionPrediction& motion, const SearchWindow& window,
										   bool standstillCheck, ScanResult& r);
	void insertKeyframe(const mrpt::obs::CObservation2DRangeScan& scan, const ScanPoints& pts, double now,
						ScanResult& r);
	void applyMapCorrection(LoopClosure::Update& u, ScanResult& r);
};

}  // namespace pmslam
