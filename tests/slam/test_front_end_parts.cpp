// The front-end's parts on their own (PerfectMatchSlam wires them; the end-to-end tests cover the
// whole): the motion model's prediction, glitches, gaps and stale predictions; the tracker's states
// and gaps; the keyframe gate; the search window.
#include <gtest/gtest.h>
#include <mrpt/core/Clock.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/system/datetime.h>
#include <pmslam/slam/HypothesisSearch.h>
#include <pmslam/slam/KeyframeGate.h>
#include <pmslam/slam/MotionModel.h>
#include <pmslam/slam/Tracker.h>

#include <cmath>

using mrpt::math::TPose2D;

namespace
{
pmslam::MotionModelOptions motionOptions()
{
	pmslam::MotionModelOptions o;
	o.odometryToScanTime = true;
	o.scanLatency = 0.08;
	o.relocalizeAfterGap = 2.0;
	o.relocalizeAfterJump = 1.0;
	return o;
}

mrpt::Clock::time_point at(double t) { return mrpt::Clock::fromDouble(t); }

pmslam::PerfectMatchMatcher::MatchInfo match(double goodness)
{
	pmslam::PerfectMatchMatcher::MatchInfo m;
	m.goodness = goodness;
	m.inlierGoodness = goodness;
	m.inlierFraction = 1.0;
	m.nPoints = 100;
	return m;
}

/** The Tracker's acceptance thresholds as MapBuilderOptions has them: D7's minGoodness, D13's overlap. */
pmslam::TrackerOptions acceptance()
{
	pmslam::TrackerOptions o;
	o.minGoodness = 0.3;
	o.minOverlapGoodness = 0.6;
	o.minPoints = 20;
	return o;
}
}  // namespace

TEST(MotionModel, PredictsTheEstimateMovedByTheOdometryIncrement)
{
	pmslam::MotionModel m(motionOptions());
	m.addReading(TPose2D(5, 5, M_PI / 2), std::nan(""));
	EXPECT_FALSE(m.predict(at(10.0), std::nullopt, TPose2D(1, 2, 0)).glitch);
	// 0.3 m ahead in the odometry's frame is 0.3 m ahead of the estimate in the map's.
	m.addReading(TPose2D(5, 5.3, M_PI / 2), std::nan(""));
	const auto p = m.predict(at(10.1), std::nullopt, TPose2D(1, 2, 0));
	EXPECT_NEAR(p.pose.x, 1.3, 1e-9);
	EXPECT_NEAR(p.pose.y, 2.0, 1e-9);
	EXPECT_NEAR(p.step, 0.3, 1e-9);
	EXPECT_NEAR(p.sincePrevious, 0.1, 1e-6);
	EXPECT_FALSE(p.gap || p.jump || p.stale || p.glitch);
}

TEST(MotionModel, AnImplausibleJumpIsAGlitchAndIgnored)
{
	pmslam::MotionModel m(motionOptions());
	m.predict(at(10.0), TPose2D(0, 0, 0), TPose2D(1, 2, 0));
	const auto p = m.predict(at(10.1), TPose2D(50, 0, 0), TPose2D(1, 2, 0));
	EXPECT_TRUE(p.glitch);
	EXPECT_TRUE(p.jump);
	EXPECT_EQ(p.pose.x, 1.0);
	EXPECT_EQ(p.pose.y, 2.0);
	// The same step over a long enough gap is driving, not a glitch.
	pmslam::MotionModel slow(motionOptions());
	slow.predict(at(10.0), TPose2D(0, 0, 0), TPose2D(0, 0, 0));
	const auto q = slow.predict(at(40.0), TPose2D(50, 0, 0), TPose2D(0, 0, 0));
	EXPECT_FALSE(q.glitch);
	EXPECT_TRUE(q.gap);
	EXPECT_NEAR(q.pose.x, 50.0, 1e-9);
}

TEST(MotionModel, AGapWithoutOdometryMakesTheBeforeGapPredictionStale)
{
	pmslam::MotionModel m(motionOptions());
	m.predict(at(10.0), std::nullopt, TPose2D(0, 0, 0));
	const auto near = m.predict(at(10.5), std::nullopt, TPose2D(0, 0, 0));
	EXPECT_FALSE(near.gap || near.stale);
	const auto far = m.predict(at(13.0), std::nullopt, TPose2D(0, 0, 0));
	EXPECT_TRUE(far.gap);
	EXPECT_TRUE(far.stale);
	EXPECT_FALSE(far.odometry);
	// With odometry the same gap is no stale prediction: the odometry covers it.
	pmslam::MotionModel withOdometry(motionOptions());
	withOdometry.predict(at(10.0), TPose2D(0, 0, 0), TPose2D(0, 0, 0));
	const auto g = withOdometry.predict(at(13.0), TPose2D(0.5, 0, 0), TPose2D(0, 0, 0));
	EXPECT_TRUE(g.gap);
	EXPECT_FALSE(g.stale);
}

TEST(MotionModel, ACopiedReadingIsMovedToTheScanTimeForTheSmootherOnly)
{
	pmslam::MotionModel m(motionOptions());
	for (int k = 0; k <= 10; ++k) m.addReading(TPose2D(0.1 * k, 0, 0), 10.0 + 0.1 * k);  // 1 m/s
	// A scan stamped 0.18 s after the last reading was taken 0.1 s after it.
	const auto p = m.predict(at(11.18), std::nullopt, TPose2D(0, 0, 0));
	ASSERT_TRUE(p.odometry && p.odometryAtScanTime);
	EXPECT_NEAR(p.odometry->x, 1.0, 1e-9);
	EXPECT_NEAR(p.odometryAtScanTime->x, 1.1, 1e-6);
	// Odometry of the scan's own (not the latest reading copied) is kept as it is.
	const auto own = m.predict(at(11.28), TPose2D(1.15, 0, 0), TPose2D(0, 0, 0));
	EXPECT_NEAR(own.odometryAtScanTime->x, 1.15, 1e-12);
}

TEST(Tracker, JudgesMatchesAndKeepsTheGaps)
{
	pmslam::TrackerOptions o = acceptance();
	o.newGroundUnexplored = 0.8;
	o.newGroundAfter = 2.0;
	pmslam::Tracker t(o);
	int asked = 0;
	const auto unexplored = [&] {
		++asked;
		return 0.9;
	};
	EXPECT_EQ(t.judge(match(0.8), false, false, 1.0, unexplored), pmslam::TrackingState::Tracking);
	t.update(pmslam::TrackingState::Tracking, false, false, 1.0);
	EXPECT_FALSE(t.lost());
	EXPECT_TRUE(t.gaps().empty());

	// A poor match at 2 s opens a gap; not lost long enough for new ground (the map is not asked).
	const auto v = t.judge(match(0.1), false, false, 2.0, unexplored);
	EXPECT_EQ(v, pmslam::TrackingState::Lost);
	EXPECT_EQ(asked, 0);
	t.update(v, false, false, 2.0);
	EXPECT_TRUE(t.lost());
	EXPECT_NEAR(t.lostFor(3.5), 1.5, 1e-12);
	// A scan not matched leaves the state as it was.
	t.update(std::nullopt, false, false, 3.0);
	EXPECT_EQ(t.state(), pmslam::TrackingState::Lost);
	// Undecided at 3 s: ambiguous, still in the gap.
	EXPECT_EQ(t.judge(match(0.9), true, false, 3.0, unexplored), pmslam::TrackingState::Ambiguous);
	t.update(pmslam::TrackingState::Ambiguous, false, false, 3.0);
	// Lost for 2.5 s over unexplored space: new ground.
	EXPECT_EQ(t.judge(match(0.1), false, false, 4.5, unexplored), pmslam::TrackingState::NewGround);
	EXPECT_EQ(asked, 1);
	t.update(pmslam::TrackingState::NewGround, false, true, 4.5);
	ASSERT_EQ(t.gaps().size(), 1u);
	EXPECT_TRUE(t.gaps()[0].open);
	EXPECT_EQ(t.gaps()[0].scans, 3u);
	// An accepted match closes the gap.
	t.update(pmslam::TrackingState::Tracking, false, false, 5.0);
	EXPECT_EQ(t.state(), pmslam::TrackingState::Tracking);
	ASSERT_EQ(t.gaps().size(), 1u);
	EXPECT_FALSE(t.gaps()[0].open);
	EXPECT_EQ(t.gaps()[0].from, 2.0);
	EXPECT_EQ(t.gaps()[0].to, 5.0);
}

TEST(Tracker, MostlyNewGroundIsAcceptedWhereTheOverlapAgrees)
{
	pmslam::Tracker t(acceptance());
	auto m = match(0.2);
	m.inlierGoodness = 0.8;
	m.inlierFraction = 0.25;  // 25 of 100 points overlap the map, and agree
	EXPECT_EQ(t.judge(m, false, false, 0, [] { return 0.0; }), pmslam::TrackingState::Tracking);
	m.inlierFraction = 0.1;  // 10: too few to trust
	EXPECT_EQ(t.judge(m, false, false, 0, [] { return 0.0; }), pmslam::TrackingState::Lost);
}

TEST(Tracker, AfterAGapAMatchIsTakenOnlyWhereItsOverlapWithTheMapAgrees)
{
	pmslam::Tracker t(acceptance());
	// intel, the first scan after a 120 s gap: 0.42 of the scan explained, its 79 % that overlaps the
	// map agreeing only 0.53. Taken while tracking; after a gap, where the prediction is in doubt, not.
	auto m = match(0.42);
	m.inlierGoodness = 0.53;
	m.inlierFraction = 0.79;
	EXPECT_EQ(t.judge(m, false, false, 0, [] { return 0.0; }), pmslam::TrackingState::Tracking);
	EXPECT_EQ(t.judge(m, false, true, 0, [] { return 0.0; }), pmslam::TrackingState::Lost);
	// The same share explained by a pose whose overlap agrees (the rest new ground) is taken.
	m.inlierGoodness = 0.85;
	m.inlierFraction = 0.49;
	EXPECT_EQ(t.judge(m, false, true, 0, [] { return 0.0; }), pmslam::TrackingState::Tracking);
}

TEST(Tracker, AKeyframeAfterARejectionIsNotTracked)
{
	pmslam::Tracker t(pmslam::TrackerOptions{});
	EXPECT_TRUE(t.keyframeEvidence(true, false, false).tracked);
	t.update(pmslam::TrackingState::Lost, false, false, 1.0);
	EXPECT_FALSE(t.keyframeEvidence(true, false, false).tracked);
	t.update(pmslam::TrackingState::Tracking, true, false, 2.0);  // placed by a re-localisation
	EXPECT_TRUE(t.keyframeEvidence(true, false, false).searched);
	t.update(pmslam::TrackingState::Tracking, false, true, 3.0);  // a keyframe: afresh
	const auto e = t.keyframeEvidence(true, false, false);
	EXPECT_TRUE(e.tracked);
	EXPECT_FALSE(e.searched);
}

TEST(KeyframeGate, MatchesPastTheThresholdsAndInsertsOnlyWhatTheMapDoesNotExplain)
{
	pmslam::KeyframeGateOptions o;
	o.matchLinDistance = 0.01;
	o.matchAngDistance = mrpt::DEG2RAD(2.0);
	o.mapInsertLinDistance = 0.3;
	o.mapInsertAngDistance = mrpt::DEG2RAD(6.0);
	o.mapInsertBelowInliers = 0.95;
	pmslam::KeyframeGate g(o, TPose2D(0, 0, 0));
	EXPECT_FALSE(g.moved(TPose2D(0.005, 0, 0)));
	EXPECT_TRUE(g.moved(TPose2D(0.02, 0, 0)));
	EXPECT_TRUE(g.moved(TPose2D(0, 0, mrpt::DEG2RAD(3.0))));
	// Close to the last keyframe and explained by the map: matched, not inserted, and the next
	// match is gated from there.
	EXPECT_FALSE(g.admits(TPose2D(0.1, 0, 0), 0.99));
	EXPECT_FALSE(g.moved(TPose2D(0.105, 0, 0)));
	// New ground (few inliers), or far enough: a keyframe.
	EXPECT_TRUE(g.admits(TPose2D(0.1, 0, 0), 0.5));
	EXPECT_TRUE(g.admits(TPose2D(0.4, 0, 0), 0.99));
	g.inserted(TPose2D(0.4, 0, 0));
	EXPECT_FALSE(g.admits(TPose2D(0.5, 0, 0), 0.99));
	// A loop closure's correction moves the origins with the map.
	g.correct(mrpt::poses::CPose2D(1, 0, 0));
	EXPECT_FALSE(g.moved(TPose2D(1.5, 0, 0)));
	EXPECT_TRUE(g.moved(TPose2D(0.5, 0, 0)));
}

TEST(HypothesisSearch, TheWindowGrowsWithWhatIsUncertain)
{
	pmslam::HypothesisSearchOptions o;
	o.wideSearchLinear = 0.5;
	o.wideSearchAngular = mrpt::DEG2RAD(30.0);
	o.relocalizeSpeed = 0.5;
	o.relocalizeTurnRate = mrpt::DEG2RAD(30.0);
	o.relocalizeOdometryError = 0.1;
	o.relocalizeMaxLinear = 8.0;
	const pmslam::HypothesisSearch h(o);
	pmslam::MotionPrediction m;
	m.odometry = TPose2D(0, 0, 0);
	auto w = h.window(m, false, 0);
	EXPECT_EQ(w.linear, 0.5);
	EXPECT_FALSE(w.alwaysSearch);
	w = h.window(m, true, 6.0);	 // lost for 6 s: 3 m more
	EXPECT_NEAR(w.linear, 3.5, 1e-12);
	EXPECT_EQ(w.angular, M_PI);	 // 30 + 180 deg, at most 180
	EXPECT_FALSE(w.alwaysSearch);
	m.jump = true;
	m.step = m.travelled = 5.0;  // a 5 m step: 0.5 m more
	EXPECT_NEAR(h.window(m, false, 0).linear, 1.0, 1e-12);
	EXPECT_EQ(h.window(m, true, 100.0).linear, 8.0);  // at most relocalizeMaxLinear
	// No odometry across a gap: searched always, as far as the robot could drive meanwhile.
	pmslam::MotionPrediction stale;
	stale.gap = stale.stale = true;
	stale.sincePrevious = 3.0;
	w = h.window(stale, false, 0);
	EXPECT_TRUE(w.alwaysSearch);
	EXPECT_NEAR(w.linear, 2.0, 1e-12);
}

TEST(MotionModel, AcrossAGapTheRobotMayHaveDrivenWhatItsMeanSpeedCoversInThatTime)
{
	pmslam::MotionModel m(motionOptions());
	// 10 s at 0.5 m/s, turning 0.1 rad/s: a scan and a reading every 0.1 s.
	TPose2D odo(0, 0, 0);
	for (int k = 0; k <= 100; ++k)
	{
		if (k > 0) odo = (mrpt::poses::CPose2D(odo) + mrpt::poses::CPose2D(0.05, 0, 0.01)).asTPose();
		const auto p = m.predict(at(10.0 + 0.1 * k), odo, odo);
		if (k > 0)
		{
			EXPECT_NEAR(p.travelled, 0.05, 1e-9);  // no gap: the step itself
		}
	}
	// 30 s unlogged; the readings' difference is 1 m and no turn (it came back round).
	const TPose2D after = (mrpt::poses::CPose2D(odo) + mrpt::poses::CPose2D(1.0, 0, 0)).asTPose();
	const auto p = m.predict(at(10.0 + 0.1 * 100 + 30.0), after, odo);
	ASSERT_TRUE(p.gap);
	EXPECT_NEAR(p.step, 1.0, 1e-9);
	EXPECT_NEAR(p.travelled, 0.5 * 30.0, 0.2);
	EXPECT_NEAR(p.turned, 0.1 * 30.0, 0.05);
}

TEST(MotionModel, AReadingThatStoodStillWhileTheScansMovedIsAlsoCountedFromWhereItStood)
{
	pmslam::MotionModel m(motionOptions());
	// A reading every scan: the prediction counts from the previous estimate and there is no other.
	EXPECT_FALSE(m.predict(at(10.0), TPose2D(0, 0, 0), TPose2D(0, 0, 0)).alternative);
	EXPECT_FALSE(m.predict(at(10.1), TPose2D(0.1, 0, 0), TPose2D(0.1, 0, 0)).alternative);
	// The reading stands still at (0.1, 0, 0) while the scans turn the robot by 60 degrees.
	EXPECT_FALSE(m.predict(at(10.2), TPose2D(0.1, 0, 0), TPose2D(0.1, 0, 0)).alternative);
	EXPECT_FALSE(m.predict(at(10.3), TPose2D(0.1, 0, 0), TPose2D(0.1, 0, M_PI / 6)).alternative);
	// Then it catches up with the whole turn: counted from the previous estimate (120 degrees), and from
	// where it stood still (60 degrees, the turn the scans measured).
	const auto p = m.predict(at(10.4), TPose2D(0.1, 0, M_PI / 3), TPose2D(0.1, 0, M_PI / 3));
	EXPECT_NEAR(p.pose.phi, 2 * M_PI / 3, 1e-9);
	ASSERT_TRUE(p.alternative);
	EXPECT_NEAR(p.alternative->phi, M_PI / 3, 1e-9);
	EXPECT_NEAR(p.alternative->x, 0.1, 1e-9);
	// A reading that stood still while the estimate stood still too offers nothing new.
	m.predict(at(10.5), TPose2D(0.1, 0, M_PI / 3), TPose2D(0.1, 0, M_PI / 3));
	EXPECT_FALSE(m.predict(at(10.6), TPose2D(0.2, 0, M_PI / 3), TPose2D(0.1, 0, M_PI / 3)).alternative);
}
