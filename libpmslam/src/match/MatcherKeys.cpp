/* pmslam — the [PerfectMatch] keys: PerfectMatchMatcher::TConfigParams as configuration data (ConfigKeys.h). */
#include <pmslam/match/PerfectMatchMatcher.h>

#include <stdexcept>

namespace pmslam
{
namespace
{
using P = PerfectMatchMatcher::TConfigParams;
using config::Level;

PerfectMatchMatcher::Optimizer optimizerFrom(const std::string& v)
{
	for (auto o : {PerfectMatchMatcher::Optimizer::RPROP, PerfectMatchMatcher::Optimizer::GaussNewton,
				   PerfectMatchMatcher::Optimizer::LevenbergMarquardt})
		if (toString(o) == v) return o;
	throw std::invalid_argument("optimizer: " + v);
}

PerfectMatchMatcher::RobustKernel kernelFrom(const std::string& v)
{
	for (auto k : {PerfectMatchMatcher::RobustKernel::PerfectMatch, PerfectMatchMatcher::RobustKernel::None,
				   PerfectMatchMatcher::RobustKernel::Huber})
		if (toString(k) == v) return k;
	throw std::invalid_argument("robustKernel: " + v);
}

std::vector<config::Key<P>> makeKeys()
{
	using config::closed;
	return {
		config::word<P>(
			"optimizer", {"RPROP", "GaussNewton", "LevenbergMarquardt"}, Level::Basic,
			"Optimiser of the pose: RPROP (the paper's), GaussNewton or LevenbergMarquardt on the same cost (D3).",
			[](auto& o) -> auto& { return o.optimizer; },
			[](PerfectMatchMatcher::Optimizer v) { return toString(v); }, optimizerFrom),
		config::word<P>("robustKernel", {"PerfectMatch", "None", "Huber"}, Level::Expert,
						"Residual weights of GaussNewton/LevenbergMarquardt: PerfectMatch (1/(sigma^2+d^2), the PM "
						"cost itself), None (least squares) or Huber. RPROP always uses the PM cost.",
						[](auto& o) -> auto& { return o.robustKernel; },
						[](PerfectMatchMatcher::RobustKernel v) { return toString(v); }, kernelFrom),
		config::number<P>("sigma", "m", closed(1e-4, 10), Level::Basic,
						  "Sigma of the likelihood field p = sigma^2/(sigma^2+d^2): the range noise of the lidar "
						  "plus the map's blur (a SICK LMS: 0.055) (D2); the least used: a lidar whose scans read "
						  "noisier is matched with 0.7 x its noise (D52).",
						  [](auto& o) -> auto& { return o.sigma; }),
		config::count<P>("maxIterations", "", closed(1, 10000), Level::Expert, "Optimiser iterations at most per scan.",
						 [](auto& o) -> auto& { return o.maxIterations; }),
		config::number<P>("rpropInitialStepXY", "m", closed(1e-6, 10), Level::Expert, "RPROP: first step in x and y.",
						  [](auto& o) -> auto& { return o.rpropInitialStepXY; }),
		config::number<P>("rpropInitialStepPhi", "rad", closed(1e-6, 3), Level::Expert, "RPROP: first step in heading.",
						  [](auto& o) -> auto& { return o.rpropInitialStepPhi; }),
		config::number<P>("rpropIncrease", "", closed(1, 10), Level::Expert,
						  "RPROP: step growth while the gradient keeps its sign.",
						  [](auto& o) -> auto& { return o.rpropIncrease; }),
		config::number<P>("rpropDecrease", "", closed(0.01, 1), Level::Expert,
						  "RPROP: step shrink when the gradient changes sign.",
						  [](auto& o) -> auto& { return o.rpropDecrease; }),
		config::number<P>("rpropMaxStepXY", "m", closed(1e-6, 10), Level::Expert, "RPROP: largest step in x and y.",
						  [](auto& o) -> auto& { return o.rpropMaxStepXY; }),
		config::number<P>("rpropMaxStepPhi", "rad", closed(1e-6, 3), Level::Expert, "RPROP: largest step in heading.",
						  [](auto& o) -> auto& { return o.rpropMaxStepPhi; }),
		config::count<P>("rpropRefineIterations", "", closed(0, 100), Level::Expert,
						 "Gauss-Newton steps on the same cost after RPROP, to settle on the minimum (0 = pure RPROP).",
						 [](auto& o) -> auto& { return o.rpropRefineIterations; }),
		config::number<P>("minStepXY", "m", closed(0, 1), Level::Expert,
						  "Converged when every x, y step is below this (D51).",
						  [](auto& o) -> auto& { return o.minStepXY; }),
		config::number<P>("minStepPhi", "rad", closed(0, 1), Level::Expert,
						  "Converged when the heading step is below this (and the x, y steps below minStepXY).",
						  [](auto& o) -> auto& { return o.minStepPhi; }),
		config::count<P>("decimation", "", closed(1, 1000), Level::Expert, "Use every k-th point of the scan (1 = all).",
						 [](auto& o) -> auto& { return o.decimation; }),
		config::number<P>("maxDistance", "m", closed(1e-3, 100), Level::Expert,
						  "Matching a plain MRPT grid (PerfectMatchAligner, not the SLAM map): truncation of the "
						  "distance layer built for it.",
						  [](auto& o) -> auto& { return o.maxDistance; }),
		config::number<P>("occupiedThreshold", "", closed(0.01, 0.99), Level::Expert,
						  "Matching a plain MRPT grid: the occupancy above which a cell is an obstacle.",
						  [](auto& o) -> auto& { return o.occupiedThreshold; }),
	};
}
}  // namespace

const std::vector<config::Key<P>>& P::keys()
{
	static const std::vector<config::Key<P>> k = makeKeys();
	return k;
}

void P::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) { config::load(keys(), *this, c, s); }

void P::dumpToTextStream(std::ostream& out) const { config::dump(keys(), *this, out); }

}  // namespace pmslam
