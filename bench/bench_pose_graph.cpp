// PoseGraph::optimize with each solver (Ceres, the default, and MRPT's sparse pose adjustment) on ring graphs of 5 000 and 20 000 nodes: laps of 200 nodes
// around a 100 m x 80 m rectangle with a loop edge to the previous lap every 50 nodes, from the dead-reckoning
// start of unbiased odometry (random error only, drifting metres). With the tests' heading bias (0.3 rad a lap)
// 25 laps of dead reckoning turn more than a revolution: a batch optimisation from there falls into a local
// minimum and the chi-square test then rejects correct loops (online, each closure is optimised as it comes). Reported per optimisation: time, Levenberg-Marquardt iterations, rounds,
// final chi2 and the position error against the truth.
#include <benchmark/benchmark.h>
#include <pmslam/graph/PoseGraph.h>

#include "RingGraph.h"

namespace
{
void BM_PoseGraphRing(benchmark::State& state, pmslam::PoseGraphSolver solver)
{
	pmslam::PoseGraphOptions options;
	options.solver = solver;
	pmslam::test::RingOptions o;
	o.laps = static_cast<std::size_t>(state.range(0)) / o.nodesPerLap;
	o.loopEvery = 50;
	o.headingBias = 0;
	o.noisePhi = 0.0003;
	const pmslam::test::Ring ring = pmslam::test::makeRing(o);
	pmslam::PoseGraphStats st;
	double maxError = 0, rmsError = 0;
	for (auto _ : state)
	{
		state.PauseTiming();
		pmslam::test::Ring r = ring;  // the perturbed start again
		state.ResumeTiming();
		st = r.graph.optimize(options);
		state.PauseTiming();
		r.positionError(maxError, rmsError);
		state.ResumeTiming();
	}
	state.counters["nodes"] = double(ring.graph.nodeCount());
	state.counters["edges"] = double(ring.graph.edgeCount());
	state.counters["iterations"] = double(st.iterations);
	state.counters["rounds"] = double(st.rounds);
	state.counters["rejected"] = double(st.rejectedEdges.size());
	state.counters["chi2_per_edge"] = st.finalChi2 / ring.graph.edgeCount();
	state.counters["max_error_m"] = maxError;
	state.counters["rms_error_m"] = rmsError;
}
BENCHMARK_CAPTURE(BM_PoseGraphRing, Ceres, pmslam::PoseGraphSolver::Ceres)
	->Arg(5000)
	->Arg(20000)
	->Unit(benchmark::kMillisecond)
	->Iterations(3);
BENCHMARK_CAPTURE(BM_PoseGraphRing, Mrpt, pmslam::PoseGraphSolver::Mrpt)
	->Arg(5000)
	->Arg(20000)
	->Unit(benchmark::kMillisecond)
	->Iterations(3);
}  // namespace

BENCHMARK_MAIN();
