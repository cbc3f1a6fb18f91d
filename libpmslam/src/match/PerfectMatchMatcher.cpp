/* pmslam — Perfect Match matcher (see PerfectMatchMatcher.h). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/match/PerfectMatchMatcher.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>

namespace pmslam
{
std::string toString(PerfectMatchMatcher::Optimizer o)
{
	switch (o)
	{
		case PerfectMatchMatcher::Optimizer::RPROP: return "RPROP";
		case PerfectMatchMatcher::Optimizer::GaussNewton: return "GaussNewton";
		case PerfectMatchMatcher::Optimizer::LevenbergMarquardt: return "LevenbergMarquardt";
	}
	return "?";
}

std::string toString(PerfectMatchMatcher::RobustKernel k)
{
	switch (k)
	{
		case PerfectMatchMatcher::RobustKernel::PerfectMatch: return "PerfectMatch";
		case PerfectMatchMatcher::RobustKernel::None: return "None";
		case PerfectMatchMatcher::RobustKernel::Huber: return "Huber";
	}
	return "?";
}

namespace
{
/** Everything the optimisers need from one pass over the points. */
struct Evaluation
{
	double cost = 0;  // Σ ln(1 + Δ²/σ²)
	double kernelCost = 0;	// cost of the GN/LM kernel
	Eigen::Vector3d gradient = Eigen::Vector3d::Zero();	 // of cost
	Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();	// Gauss-Newton curvature of cost
	Eigen::Matrix3d JtWJ = Eigen::Matrix3d::Zero();
	Eigen::Vector3d JtWr = Eigen::Vector3d::Zero();
	std::size_t n = 0, inliers = 0;
	double likelihoodSum = 0, inlierLikelihoodSum = 0;
};

int sign(double v) { return (v > 0) - (v < 0); }

// ln(y) for y >= 1 to about 1e-4: exponent from the float's bits plus a polynomial for the
// mantissa's log2. RPROP only compares costs of nearby poses, for which this is plenty,
// and it is several times cheaper than std::log1p in the hot loop.
inline float fastLog(float y)
{
	uint32_t bits;
	std::memcpy(&bits, &y, sizeof bits);
	const float exponent = static_cast<float>(static_cast<int>(bits >> 23) - 127);
	bits = (bits & 0x7FFFFFu) | 0x3F800000u;
	float m;
	std::memcpy(&m, &bits, sizeof m);
	const float log2m = -1.7417939f + (2.8212026f + (-1.4699568f + (0.44717955f - 0.056570851f * m) * m) * m) * m;
	return (exponent + log2m) * 0.69314718f;
}

// Per-point terms of one evaluation, laid out for gradientAndFastCost's second pass: arrays of
// floats padded with zeros to a whole number of lanes. One buffer per thread, reused.
constexpr std::size_t kLanes = 8;
struct Terms
{
	std::vector<float> d, dU, dV, ru, rv;
	std::size_t padded = 0;
	void resize(std::size_t n)
	{
		padded = (n + kLanes - 1) / kLanes * kLanes;
		for (auto* v : {&d, &dU, &dV, &ru, &rv})
		{
			if (v->size() < padded) v->resize(padded);
			std::fill(v->begin() + std::ptrdiff_t(n), v->begin() + std::ptrdiff_t(padded), 0.0f);
		}
	}
};
Terms& terms()
{
	thread_local Terms t;
	return t;
}

class CostFunction
{
   public:
	CostFunction(const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& pts,
				 const PerfectMatchMatcher::TConfigParams& o, const PerfectMatchMatcher::PosePrior* prior = nullptr,
				 const std::vector<mrpt::math::TPoint2Df>* normals = nullptr)
		: m_map(map), m_pts(pts), m_step(std::max(1u, o.decimation)), m_s2(o.sigma * o.sigma),
		  m_invS2(1.0 / (o.sigma * o.sigma)), m_sigma(o.sigma),
		  m_kernel(o.robustKernel), m_far(map.maxDistance() * (1.0 - 1e-6)), m_prior(prior),
		  m_normals(normals && normals->size() == pts.size() ? normals->data() : nullptr)
	{
	}

	enum Need : unsigned
	{
		kGradient = 0,	// RPROP iterations: the gradient is all they use
		kCost = 1,
		kNormal = 2,  // GN/LM: weighted normal equations and the kernel's cost
		kCurvature = 4	// the final pose: curvature and statistics
	};

	Evaluation operator()(const Eigen::Vector3d& x, unsigned need) const
	{
		if (!(need & (kNormal | kCurvature))) return gradientAndFastCost(x, need & kCost);
		Evaluation e;
		const double c = std::cos(x[2]), s = std::sin(x[2]);
		double g0 = 0, g1 = 0, g2 = 0, cost = 0;
		for (std::size_t i = 0; i < m_pts.size(); i += m_step)
		{
			const double px = m_pts[i].x, py = m_pts[i].y;
			const double rx = c * px - s * py, ry = s * px + c * py;  // rotated point
			double gx, gy;
			const double d = m_map.distanceAt(x[0] + rx, x[1] + ry, &gx, &gy);
			if (m_normals) project(m_normals[i], c, s, gx, gy);
			const double ratio = 1.0 + d * d * m_invS2;	 // (σ² + Δ²) / σ²
			// dΔ/d(x, y, θ): the map gradient chained through the endpoint's pose Jacobian;
			// d ln(σ²+Δ²) / dΔ = 2Δ / (σ²+Δ²).
			const double jth = -gx * ry + gy * rx;
			const double k = 2.0 * d * m_invS2 / ratio;
			g0 += k * gx;
			g1 += k * gy;
			g2 += k * jth;
			const double denom = m_s2 * ratio;
			const double pointCost = std::log1p(d * d / m_s2);
			++e.n;
			cost += pointCost;
			if (need & kCurvature)
			{
				const Eigen::Vector3d J(gx, gy, jth);
				e.likelihoodSum += m_s2 / denom;
				if (d < m_far)
				{
					++e.inliers;
					e.inlierLikelihoodSum += m_s2 / denom;
				}
				e.hessian += (2.0 / denom) * (J * J.transpose());
			}
			if (need & kNormal)
			{
				const Eigen::Vector3d J(gx, gy, jth);
				double w = 1.0;
				switch (m_kernel)
				{
					case PerfectMatchMatcher::RobustKernel::PerfectMatch:
						w = m_s2 / denom;
						e.kernelCost += pointCost;
						break;
					case PerfectMatchMatcher::RobustKernel::None:
						e.kernelCost += d * d / m_s2;
						break;
					case PerfectMatchMatcher::RobustKernel::Huber:
						w = d <= m_sigma ? 1.0 : m_sigma / d;
						e.kernelCost += d <= m_sigma ? d * d / m_s2 : 2.0 * d / m_sigma - 1.0;
						break;
				}
				e.JtWJ += w * (J * J.transpose());
				e.JtWr += w * d * J;
			}
		}
		e.cost = cost;
		e.gradient = Eigen::Vector3d(g0, g1, g2);
		if (m_prior) addPrior(x, need, e);
		return e;
	}

	// The RPROP iteration: gradient (and the approximate cost) only, in float cell units
	// relative to the cell under the pose, so single precision stays exact to ~1e-4 cell
	// however far the robot is from the origin. Same cost and gradient as the general path.
	//
	// Two passes: the map lookups, one point at a time (a gather from the blocks), then the
	// per-point terms and their sums in kLanes independent float lanes, which the compiler turns
	// into vector instructions (one running sum would chain every point on the one before).
	Evaluation gradientAndFastCost(const Eigen::Vector3d& x, bool withCost) const
	{
		Evaluation e;
		const double inv = 1.0 / m_map.resolution();
		const double u0 = x[0] * inv - 0.5, v0 = x[1] * inv - 0.5;	// cell-centre lattice
		const float far = static_cast<float>(m_map.maxDistance());
		const std::size_t n = (m_pts.size() + m_step - 1) / m_step;
		if (!(std::abs(u0) < 1e9 && std::abs(v0) < 1e9))
		{
			// Nowhere near anything mapped: every point at the truncation, no gradient.
			e.n = n;
			e.cost = withCost ? n * std::log1p(double(far) * far * m_invS2) : 0.0;
			if (m_prior) addPrior(x, withCost ? kCost : kGradient, e);
			return e;
		}
		const double bu = std::floor(u0), bv = std::floor(v0);
		const int baseI = static_cast<int>(bu), baseJ = static_cast<int>(bv);
		const float fu = static_cast<float>(u0 - bu), fv = static_cast<float>(v0 - bv);
		const float cs = static_cast<float>(std::cos(x[2]) * inv), sn = static_cast<float>(std::sin(x[2]) * inv);
		const float c0 = static_cast<float>(std::cos(x[2])), s0 = static_cast<float>(std::sin(x[2]));

		// Pass 1: distance, its gradient (per cell) and the rotated point (cells), per point.
		Terms& t = terms();
		t.resize(n);
		std::size_t k = 0;
		for (std::size_t i = 0; i < m_pts.size(); i += m_step, ++k)
		{
			const float px = m_pts[i].x, py = m_pts[i].y;
			const float ru = cs * px - sn * py, rv = sn * px + cs * py;	// rotated point, cells
			const float u = fu + ru, v = fv + rv;
			float d = far, dU = 0, dV = 0;
			if (std::abs(u) < 1e8f && std::abs(v) < 1e8f)
			{
				int iu = static_cast<int>(u), iv = static_cast<int>(v);
				iu -= u < static_cast<float>(iu);  // floor
				iv -= v < static_cast<float>(iv);
				d = m_map.sampleBilinear(baseI + iu, baseJ + iv, u - iu, v - iv, dU, dV);
				if (m_normals) project(m_normals[i], c0, s0, dU, dV);
			}
			t.d[k] = d;
			t.dU[k] = dU;
			t.dV[k] = dV;
			t.ru[k] = ru;
			t.rv[k] = rv;
		}

		// Pass 2: d ln(σ²+Δ²)/dΔ = 2Δ/(σ²+Δ²) chained through the endpoint's pose Jacobian
		// (∂u/∂θ = −rv, ∂v/∂θ = ru, cells), and the cost ln(1 + Δ²/σ²); the points that do not
		// fill a last group of lanes go in as Δ = 0 (no gradient) and leave the cost alone.
		const float invS2 = static_cast<float>(m_invS2);
		const float* __restrict D = t.d.data();
		const float* __restrict DU = t.dU.data();
		const float* __restrict DV = t.dV.data();
		const float* __restrict RU = t.ru.data();
		const float* __restrict RV = t.rv.data();
		float g0[kLanes] = {}, g1[kLanes] = {}, g2[kLanes] = {}, cost[kLanes] = {};
		for (std::size_t b = 0; b < t.padded; b += kLanes)
			for (std::size_t l = 0; l < kLanes; ++l)
			{
				const float d = D[b + l], dU = DU[b + l], dV = DV[b + l];
				const float ratio = 1.0f + d * d * invS2;  // (σ² + Δ²) / σ²
				const float kk = 2.0f * d * invS2 / ratio;
				g0[l] += kk * dU;
				g1[l] += kk * dV;
				g2[l] += kk * (dV * RU[b + l] - dU * RV[b + l]);
				cost[l] += fastLog(ratio);
			}
		double G0 = 0, G1 = 0, G2 = 0, C = 0;
		for (std::size_t l = 0; l < kLanes; ++l) G0 += g0[l], G1 += g1[l], G2 += g2[l], C += cost[l];
		e.n = n;
		// The padding's Δ = 0 added fastLog(1) (not quite 0) to the cost each.
		e.cost = withCost ? C - double(t.padded - n) * fastLog(1.0f) : 0.0;
		// dU, dV and the θ term are per cell: ×1/resolution gives per metre (θ: cells × m/cell
		// cancels to the same units as the general path).
		e.gradient = Eigen::Vector3d(G0 * inv, G1 * inv, G2);
		if (m_prior) addPrior(x, withCost ? kCost : kGradient, e);
		return e;
	}

	// ½ eᵀ Λ e with e = x − mean. The normal equations above approximate (σ²/2)·cost, so the
	// prior enters them with the same factor.
	void addPrior(const Eigen::Vector3d& x, unsigned need, Evaluation& e) const
	{
		const Eigen::Vector3d err(x[0] - m_prior->mean.x, x[1] - m_prior->mean.y,
								  std::remainder(x[2] - m_prior->mean.phi, 2 * M_PI));
		const Eigen::Matrix3d& L = m_prior->information;
		const Eigen::Vector3d Le = L * err;
		const double p = 0.5 * err.dot(Le);
		e.cost += p;
		e.kernelCost += p;
		e.gradient += Le;
		if (need & kCurvature) e.hessian += L;
		if (need & kNormal)
		{
			e.JtWJ += 0.5 * m_s2 * L;
			e.JtWr += 0.5 * m_s2 * Le;
		}
	}

   private:
	// The map gradient (gx, gy) reduced to its component along the point's surface normal n
	// (robot frame, rotated by the pose's c, s); no normal, no change.
	template <typename T>
	static void project(const mrpt::math::TPoint2Df& n, T c, T s, T& gx, T& gy)
	{
		if (n.x == 0 && n.y == 0) return;
		const T nx = c * n.x - s * n.y, ny = s * n.x + c * n.y;
		const T along = gx * nx + gy * ny;
		gx = along * nx;
		gy = along * ny;
	}

	const DynamicDistanceMap& m_map;
	const std::vector<mrpt::math::TPoint2Df>& m_pts;
	const std::size_t m_step;
	const double m_s2, m_invS2, m_sigma;
	const PerfectMatchMatcher::RobustKernel m_kernel;
	const double m_far;
	const PerfectMatchMatcher::PosePrior* m_prior;
	const mrpt::math::TPoint2Df* m_normals;
};

// What a match reports, from the evaluation at its pose (iterations are the caller's).
PerfectMatchMatcher::MatchInfo matchInfo(const Evaluation& e)
{
	PerfectMatchMatcher::MatchInfo info;
	info.nPoints = e.n;
	info.finalCost = e.n ? e.cost / e.n : 0.0;
	info.inlierFraction = e.n ? double(e.inliers) / e.n : 0.0;
	info.goodness = e.n ? e.likelihoodSum / e.n : 0.0;
	info.inlierGoodness = e.inliers ? e.inlierLikelihoodSum / e.inliers : 0.0;
	info.hessian = e.hessian;
	return info;
}

/** Damped (LM) or plain Gauss-Newton on the weighted normal equations, from x; `it` counts the
 * iterations. */
Eigen::Vector3d gaussNewton(const CostFunction& f, const PerfectMatchMatcher::TConfigParams& o, Eigen::Vector3d x,
							unsigned maxIterations, bool damped, unsigned& it)
{
	Evaluation cur = f(x, CostFunction::kNormal);
	double lambda = damped ? 1e-3 : 0.0;
	for (unsigned k = 0; k < maxIterations; ++k, ++it)
	{
		Eigen::Matrix3d A = cur.JtWJ;
		if (lambda > 0) A.diagonal() += lambda * cur.JtWJ.diagonal();
		A.diagonal().array() += 1e-9;
		if (!A.allFinite() || !cur.JtWr.allFinite()) break;	 // never hand NaN to the solver
		Eigen::Vector3d dx = A.ldlt().solve(-cur.JtWr);
		if (!dx.allFinite()) break;
		Eigen::Vector3d xn = x + dx;
		Evaluation next = f(xn, CostFunction::kNormal);
		if (damped)
		{
			if (next.kernelCost > cur.kernelCost)
			{
				lambda *= 10;
				if (lambda > 1e8) break;
				continue;
			}
			lambda = std::max(1e-7, lambda / 10);
		}
		else
		{
			// A full Gauss-Newton step can overshoot into another basin where the
			// linearisation is poor: halve it until the cost does not increase.
			int halvings = 0;
			while (next.kernelCost > cur.kernelCost && halvings < 4)
			{
				dx *= 0.5;
				xn = x + dx;
				next = f(xn, CostFunction::kNormal);
				++halvings;
			}
			if (next.kernelCost > cur.kernelCost) break;  // no descent left: at the minimum
		}
		x = xn;
		cur = next;
		if (std::abs(dx[0]) < o.minStepXY && std::abs(dx[1]) < o.minStepXY &&
			std::abs(dx[2]) < o.minStepPhi)
		{
			++it;
			break;
		}
	}
	return x;
}

/** iRprop−: each parameter has its own step that grows while the gradient keeps its sign and shrinks
 * when it flips; only the sign of the gradient is used, which makes it insensitive to the scale of the
 * cost. It can overshoot, so the best pose seen is the answer (its cost in `bestCost`); `it` counts
 * the iterations. */
Eigen::Vector3d rprop(const CostFunction& f, const PerfectMatchMatcher::TConfigParams& o,
					  const Eigen::Vector3d& initial, unsigned& it, double& bestCost)
{
	Eigen::Vector3d x = initial, best = initial;
	Evaluation cur = f(x, CostFunction::kCost);
	bestCost = cur.cost;
	Eigen::Vector3d step(o.rpropInitialStepXY, o.rpropInitialStepXY, o.rpropInitialStepPhi);
	const Eigen::Vector3d maxStep(o.rpropMaxStepXY, o.rpropMaxStepXY, o.rpropMaxStepPhi);
	const Eigen::Vector3d minStep(o.minStepXY, o.minStepXY, o.minStepPhi);
	Eigen::Vector3d prevGrad = Eigen::Vector3d::Zero();
	for (it = 0; it < o.maxIterations; ++it)
	{
		Eigen::Vector3d g = cur.gradient;
		for (int k = 0; k < 3; ++k)
		{
			const double agree = g[k] * prevGrad[k];
			if (agree > 0)
				step[k] = std::min(step[k] * o.rpropIncrease, maxStep[k]);
			else if (agree < 0)
			{
				step[k] = step[k] * o.rpropDecrease;
				g[k] = 0;  // skip the update after a sign change
			}
			x[k] -= sign(g[k]) * step[k];
		}
		prevGrad = g;
		cur = f(x, CostFunction::kCost);
		if (cur.cost < bestCost - 1e-9 * std::abs(bestCost))
		{
			bestCost = cur.cost;
			best = x;
		}
		// Converged: every step is tiny.
		if ((step.array() < minStep.array()).all())
		{
			++it;
			break;
		}
	}
	return best;
}
}  // namespace

PerfectMatchMatcher::PosePrior PerfectMatchMatcher::PosePrior::diagonal(const mrpt::math::TPose2D& mean,
																		  double sigmaXY, double sigmaPhi)
{
	PosePrior p;
	p.mean = mean;
	p.information.diagonal() << 1.0 / (sigmaXY * sigmaXY), 1.0 / (sigmaXY * sigmaXY), 1.0 / (sigmaPhi * sigmaPhi);
	return p;
}

PerfectMatchMatcher::MatchInfo PerfectMatchMatcher::evaluate(const DynamicDistanceMap& map,
															   const std::vector<mrpt::math::TPoint2Df>& points,
															   const mrpt::math::TPose2D& pose,
															   const std::vector<mrpt::math::TPoint2Df>* normals) const
{
	TConfigParams o = options;
	o.decimation = 1;
	const Evaluation e =
		CostFunction(map, points, o, nullptr, normals)(Eigen::Vector3d(pose.x, pose.y, pose.phi), CostFunction::kCurvature);
	return matchInfo(e);
}

double PerfectMatchMatcher::cost(const DynamicDistanceMap& map, const std::vector<mrpt::math::TPoint2Df>& points,
								 const mrpt::math::TPose2D& pose) const
{
	TConfigParams o = options;
	o.decimation = 1;
	return CostFunction(map, points, o)(Eigen::Vector3d(pose.x, pose.y, pose.phi), CostFunction::kCost).cost;
}

mrpt::math::TPose2D PerfectMatchMatcher::alignPoints(const DynamicDistanceMap& map,
													 const std::vector<mrpt::math::TPoint2Df>& points,
													 const mrpt::math::TPose2D& initial, MatchInfo* info,
													 Eigen::Matrix3d* covariance, const PosePrior* prior) const
{
	// Non-finite points (a corrupt scan) would poison every sum: leave them out.
	std::vector<mrpt::math::TPoint2Df> finitePoints;
	const std::vector<mrpt::math::TPoint2Df>* pts = &points;
	if (!std::all_of(points.begin(), points.end(), [](const auto& p) { return std::isfinite(p.x) && std::isfinite(p.y); }))
	{
		for (const auto& p : points)
			if (std::isfinite(p.x) && std::isfinite(p.y)) finitePoints.push_back(p);
		pts = &finitePoints;
	}
	if (!std::isfinite(initial.x) || !std::isfinite(initial.y) || !std::isfinite(initial.phi))
		throw std::invalid_argument("PerfectMatchMatcher: the initial pose is not finite");
	const CostFunction f(map, *pts, options, prior);
	Eigen::Vector3d best(initial.x, initial.y, initial.phi);
	unsigned it = 0;
	if (options.optimizer == Optimizer::RPROP)
	{
		double bestCost = 0;
		best = rprop(f, options, best, it, bestCost);
		// RPROP finds the basin; its sign-only steps end in a small oscillation. A few
		// Gauss-Newton steps on the same cost land on the minimum itself, and are kept
		// only if the cost agrees.
		if (options.rpropRefineIterations > 0)
		{
			const Eigen::Vector3d refined = gaussNewton(f, options, best, options.rpropRefineIterations, false, it);
			if (f(refined, CostFunction::kCost).cost <= bestCost) best = refined;
		}
	}
	else
		best = gaussNewton(f, options, best, options.maxIterations, options.optimizer == Optimizer::LevenbergMarquardt, it);

	const Evaluation fin = f(best, CostFunction::kCurvature);
	if (info)
	{
		*info = matchInfo(fin);
		info->nIterations = it;
	}
	if (covariance)
	{
		// Inverse curvature; a tiny ridge keeps a degenerate direction (a corridor)
		// finite but very uncertain instead of singular.
		Eigen::Matrix3d H = fin.hessian;
		H.diagonal().array() += 1e-6;
		*covariance = H.inverse();
	}
	return mrpt::math::TPose2D(best[0], best[1], mrpt::math::wrapToPi(best[2]));
}

DynamicDistanceMap PerfectMatchMatcher::distanceMapFromGrid(const mrpt::maps::COccupancyGridMap2D& grid,
															 double maxDistance, double occupiedThreshold)
{
	const double r = grid.getResolution();
	DynamicDistanceMap dm(r, maxDistance);
	const int offX = static_cast<int>(std::lround(grid.getXMin() / r));
	const int offY = static_cast<int>(std::lround(grid.getYMin() / r));
	// MRPT cells hold the probability of being free.
	const float freeBelow = static_cast<float>(1.0 - occupiedThreshold);
	for (unsigned iy = 0; iy < grid.getSizeY(); ++iy)
		for (unsigned ix = 0; ix < grid.getSizeX(); ++ix)
			if (grid.getCell(ix, iy) < freeBelow) dm.addObstacle(int(ix) + offX, int(iy) + offY);
	dm.update();
	return dm;
}

}  // namespace pmslam
