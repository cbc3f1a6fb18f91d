// Synthetic pose graphs for the PoseGraph tests and benchmark: a robot driving laps around a W x H rectangle
// (metres), one node every perimeter / nodesPerLap metres, heading along the side it is on. Odometry edges are the
// true increments with a constant heading bias (a miscalibrated odometry: the drift of metres, 0.3 rad a lap) plus
// Gaussian noise; their information matrix is the inverse covariance of the odometry's stated error model
// (sigmaXY, sigmaPhi per step), which covers that error: honest, bias included. The nodes' initial poses are the
// dead reckoning of the odometry (the unoptimised estimate).
#pragma once

#include <pmslam/graph/PoseGraph.h>

#include <mrpt/math/wrap2pi.h>

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace pmslam::test
{
struct RingOptions
{
	std::size_t nodesPerLap = 200;
	std::size_t laps = 1;
	double width = 100, height = 80;		 // m
	double sigmaXY = 0.01, sigmaPhi = 0.002;	 // odometry error model per step (m, rad): the information
	double noiseXY = 0.001, noisePhi = 0.0001;	 // the odometry's actual random error per step (m, rad)
	double headingBias = 0.0015;				 // and its constant heading error, rad per step
	double loopSigmaXY = 0.02, loopSigmaPhi = 0.002;  // loop edge noise (m, rad)
	std::size_t loopEvery = 0;	// from lap 2 on: a loop edge to the previous lap every this many nodes (0: none)
	unsigned seed = 1;
};

inline mrpt::math::TPose2D relativePose(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& b)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi), dx = b.x - a.x, dy = b.y - a.y;
	return {c * dx + s * dy, -s * dx + c * dy, mrpt::math::wrapToPi(b.phi - a.phi)};
}

inline mrpt::math::TPose2D composePose(const mrpt::math::TPose2D& a, const mrpt::math::TPose2D& d)
{
	const double c = std::cos(a.phi), s = std::sin(a.phi);
	return {a.x + c * d.x - s * d.y, a.y + s * d.x + c * d.y, mrpt::math::wrapToPi(a.phi + d.phi)};
}

inline mrpt::math::CMatrixDouble33 diagonalInformation(double sigmaXY, double sigmaPhi)
{
	mrpt::math::CMatrixDouble33 I;
	I.setZero();
	I(0, 0) = I(1, 1) = 1 / (sigmaXY * sigmaXY);
	I(2, 2) = 1 / (sigmaPhi * sigmaPhi);
	return I;
}

struct Ring
{
	RingOptions options;
	std::vector<mrpt::math::TPose2D> truth;	 // node i's true pose
	PoseGraph graph;						 // nodes 0..n-1 at the dead reckoning, odometry (+ loop) edges
	std::mt19937 rng;

	// A loop edge from -> to measured with the loop noise, plus `error` (a false loop when non-zero).
	std::size_t addLoop(std::size_t from, std::size_t to, const mrpt::math::TPose2D& error = {0, 0, 0})
	{
		std::normal_distribution<double> nxy(0, options.loopSigmaXY), nphi(0, options.loopSigmaPhi);
		mrpt::math::TPose2D z = relativePose(truth[from], truth[to]);
		z = {z.x + error.x + nxy(rng), z.y + error.y + nxy(rng), mrpt::math::wrapToPi(z.phi + error.phi + nphi(rng))};
		return graph.addEdge(from, to, z, diagonalInformation(options.loopSigmaXY, options.loopSigmaPhi),
							 PoseGraphEdgeKind::Loop);
	}

	// Largest and RMS position error of the graph's poses against the truth (m).
	void positionError(double& maxError, double& rmsError) const
	{
		maxError = 0;
		double sum = 0;
		for (std::size_t i = 0; i < truth.size(); ++i)
		{
			const auto& p = graph.pose(i);
			const double e = std::hypot(p.x - truth[i].x, p.y - truth[i].y);
			maxError = std::max(maxError, e);
			sum += e * e;
		}
		rmsError = std::sqrt(sum / truth.size());
	}
};

inline Ring makeRing(const RingOptions& o)
{
	Ring r;
	r.options = o;
	r.rng.seed(o.seed);
	const double perimeter = 2 * (o.width + o.height), step = perimeter / o.nodesPerLap;
	const std::size_t n = o.nodesPerLap * o.laps;
	for (std::size_t i = 0; i < n; ++i)
	{
		double s = std::fmod(i * step, perimeter);
		mrpt::math::TPose2D p;
		if (s < o.width) p = {s, 0, 0};
		else if ((s -= o.width) < o.height) p = {o.width, s, M_PI / 2};
		else if ((s -= o.height) < o.width) p = {o.width - s, o.height, M_PI};
		else p = {0, o.height - (s - o.width), -M_PI / 2};
		r.truth.push_back(p);
	}
	std::normal_distribution<double> nxy(0, o.noiseXY), nphi(0, o.noisePhi);
	const auto info = diagonalInformation(o.sigmaXY, o.sigmaPhi);
	mrpt::math::TPose2D dead = r.truth[0];
	r.graph.addNode(0, dead);
	for (std::size_t i = 1; i < n; ++i)
	{
		const mrpt::math::TPose2D d = relativePose(r.truth[i - 1], r.truth[i]);
		const mrpt::math::TPose2D z{d.x + nxy(r.rng), d.y + nxy(r.rng), d.phi + o.headingBias + nphi(r.rng)};
		dead = composePose(dead, z);
		r.graph.addNode(i, dead);
		r.graph.addEdge(i - 1, i, z, info, PoseGraphEdgeKind::Odometry);
	}
	if (o.loopEvery)
		for (std::size_t i = o.nodesPerLap; i < n; i += o.loopEvery) r.addLoop(i - o.nodesPerLap, i);
	return r;
}

}  // namespace pmslam::test
