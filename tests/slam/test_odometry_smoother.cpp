// OdometrySmoother on synthetic tracks with known truth: matched poses with white noise,
// odometry with a slow random walk (smoothed), drifting odometry (left alone), a snap-back.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/OdometrySmoother.h>

#include <cmath>
#include <optional>
#include <random>
#include <vector>

using mrpt::math::TPose2D;
using mrpt::poses::CPose2D;

namespace
{
struct Track
{
	std::vector<TPose2D> truth, matched, odometry;
};

// A corridor walk: 0.06 m per scan along x with a slow turn; matched = truth + white noise
// (alongSigma, crossSigma in the robot frame); odometry = truth composed with a random walk of
// odoStep per scan (and a scale error).
Track makeTrack(std::size_t n, double alongSigma, double crossSigma, double odoStep, double scaleError, unsigned seed)
{
	std::mt19937 rng(seed);
	std::normal_distribution<double> g(0.0, 1.0);
	Track t;
	CPose2D pose(2, 3, 0.3), odo(0, 0, 0);
	for (std::size_t i = 0; i < n; ++i)
	{
		const CPose2D step(0.06, 0, 0.004);
		if (i)
		{
			pose = pose + step;
			odo = odo + CPose2D(0.06 * (1 + scaleError) + odoStep * g(rng), odoStep * g(rng), 0.004);
		}
		t.truth.push_back(pose.asTPose());
		t.matched.push_back((pose + CPose2D(alongSigma * g(rng), crossSigma * g(rng), 0)).asTPose());
		t.odometry.push_back(odo.asTPose());
	}
	return t;
}

// RMS error of the one-scan relations of `est` against the truth (the benchmark metric's view).
double relationRms(const std::vector<TPose2D>& est, const std::vector<TPose2D>& truth, std::size_t from)
{
	double s = 0;
	std::size_t n = 0;
	for (std::size_t i = from; i + 1 < est.size(); ++i)
	{
		const CPose2D e = (CPose2D(est[i + 1]) - CPose2D(est[i])) - (CPose2D(truth[i + 1]) - CPose2D(truth[i]));
		s += e.x() * e.x() + e.y() * e.y();
		++n;
	}
	return std::sqrt(s / double(n));
}

std::vector<TPose2D> smooth(const Track& t, pmslam::OdometrySmoother& s)
{
	std::vector<TPose2D> out(t.matched.size(), TPose2D(NAN, NAN, NAN));
	auto take = [&] {
		for (const auto& [i, p] : s.takeFinal()) out.at(i) = p;
	};
	for (std::size_t i = 0; i < t.matched.size(); ++i)
	{
		s.add(i, t.matched[i], t.odometry[i]);
		take();
	}
	s.finish();
	take();
	return out;
}
}  // namespace

TEST(OdometrySmoother, DampsMatchNoiseWhereOdometryIsPrecise)
{
	const Track t = makeTrack(2000, 0.02, 0.004, 0.002, 0.0, 1);
	pmslam::OdometrySmoother s;
	const auto out = smooth(t, s);
	for (const auto& p : out) ASSERT_TRUE(std::isfinite(p.x)) << "every scan gets its pose";
	// The noise levels are learned along and across the track.
	EXPECT_NEAR(s.matchSigma()[0], 0.02, 0.004);
	EXPECT_NEAR(s.matchSigma()[1], 0.004, 0.002);
	EXPECT_NEAR(s.odometrySigma()[0], 0.002, 0.0015);
	const double before = relationRms(t.matched, t.truth, 300), after = relationRms(out, t.truth, 300);
	EXPECT_LT(after, 0.5 * before) << "matched " << before << " m, smoothed " << after << " m";
	// The heading is the matched one; the position stays anchored to the matches (no drift).
	for (std::size_t i = 300; i < out.size(); ++i)
	{
		EXPECT_EQ(out[i].phi, t.matched[i].phi);
		EXPECT_LT(std::hypot(out[i].x - t.truth[i].x, out[i].y - t.truth[i].y), 0.05);
	}
}

TEST(OdometrySmoother, LeavesMatchesAloneWhereOdometryDrifts)
{
	// Precise matches, odometry with 3 % scale error and 2 cm per scan of noise (fr079-like).
	const Track t = makeTrack(2000, 0.002, 0.002, 0.02, 0.03, 2);
	pmslam::OdometrySmoother s;
	const auto out = smooth(t, s);
	EXPECT_GT(s.odometrySigma()[0], 5 * s.matchSigma()[0]);
	const double before = relationRms(t.matched, t.truth, 300), after = relationRms(out, t.truth, 300);
	EXPECT_LT(after, 1.1 * before) << "matched " << before << " m, smoothed " << after << " m";
}

TEST(OdometrySmoother, FollowsASnapBackAtOnce)
{
	Track t = makeTrack(1000, 0.02, 0.004, 0.002, 0.0, 3);
	// From scan 600 on the matches jump 0.4 m sideways (a revisit correcting drift).
	for (std::size_t i = 600; i < t.matched.size(); ++i) t.matched[i].y += 0.4, t.truth[i].y += 0.4;
	pmslam::OdometrySmoother s;
	const auto out = smooth(t, s);
	for (std::size_t i = 600; i < 610; ++i)
		EXPECT_LT(std::abs(out[i].y - t.truth[i].y), 0.05) << "scan " << i;
}

TEST(OdometrySmoother, FilterOnlyAndGapsInTheOdometry)
{
	const Track t = makeTrack(600, 0.02, 0.004, 0.002, 0.0, 4);
	pmslam::OdometrySmootherOptions o;
	o.lag = 0;
	pmslam::OdometrySmoother s(o);
	for (std::size_t i = 0; i < t.matched.size(); ++i)
	{
		// Odometry missing for a stretch: those scans report their matched pose.
		const bool gap = i >= 400 && i < 420;
		s.add(i, t.matched[i], gap ? std::nullopt : std::optional<TPose2D>(t.odometry[i]));
		const auto f = s.takeFinal();
		ASSERT_EQ(f.size(), 1u) << "lag 0: final at once";
		EXPECT_EQ(f[0].first, i);
		if (gap)
		{
			EXPECT_EQ(f[0].second.x, t.matched[i].x);
			EXPECT_EQ(f[0].second.y, t.matched[i].y);
		}
	}
	EXPECT_THROW(pmslam::OdometrySmoother(pmslam::OdometrySmootherOptions{3, 1, 5.0, 100}), std::invalid_argument);
}
