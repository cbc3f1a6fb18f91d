/* pm-slam-app — the summary and the exit status (see Summary.h). */
#include "Summary.h"

#include <pmslam/util/RunStatistics.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include "StopSignal.h"

namespace pmslam_app
{
namespace
{
std::string mb(std::size_t bytes)
{
	char b[32];
	std::snprintf(b, sizeof b, "%.1f MB", double(bytes) / (1024.0 * 1024.0));
	return b;
}

void printLoopClosure(const pmslam::LoopClosure& lc, const std::string& out)
{
	const auto& ls = lc.stats();
	std::printf("  loop closure: %zu loops closed; loop edges %zu accepted, %zu of them rejected by the chi-square "
				"test (%zu matches verified in %zu attempts, %zu dropped as look-alikes of another visit); %zu revisit edges (front-end matches onto an earlier "
				"visit), %zu of them rejected; %zu whole-map searches after lost tracking (%zu places verified, %.2f s); %zu optimisations, %zu map updates (%zu keyframes re-inserted, %zu blocks "
				"rebuilt); back-end %.2f s on its thread "
				"(optimiser %.2f s), front-end waited %.2f s; graph: %s/graph.graph\n",
				ls.closures, ls.accepted, ls.rejected, ls.verified, ls.attempts, ls.ambiguous, ls.revisits, ls.revisitsRejected,
				ls.globalSearches, ls.globalVerified, ls.globalSeconds, ls.optimizations, ls.mapUpdates, ls.reinserted, ls.blocksReplaced, ls.backendSeconds, ls.optimizeSeconds, ls.waitSeconds,
				out.c_str());
}

void printRelocation(const SlamRun& run)
{
	// Localisation's own evidence (D47): matches whose beams would pass through the map's walls,
	// and the whole-map searches for a robot lost on the map.
	std::printf("  localisation: %zu matches rejected because their beams crossed the map's walls; %zu whole-map "
				"searches (after lost tracking or a re-localisation), the robot found again %zu times",
				run.slam().wallCrossings(), run.searchesWhenLost(), run.foundAgain().size());
	for (const auto& [t, p] : run.foundAgain())
		std::printf("%s t=%.3f at %.3f %.3f %.1f deg", &t == &run.foundAgain().front().first ? " (" : ",", t, p.x, p.y,
					p.phi * 180 / M_PI);
	std::printf("%s\n", run.foundAgain().empty() ? "" : ")");
}

void printTimes(const RunFacts& f)
{
	const auto& traj = f.run.trajectory();
	const std::vector<double> total = f.timing.frontEndMs();
	const double sumMs = std::accumulate(total.begin(), total.end(), 0.0);
	const double logSpan = traj.size() > 1 ? traj.back().timestamp - traj.front().timestamp : 0.0;
	std::printf("  time per scan (match + map update): mean %.3f ms, median %.3f ms, p99 %.3f ms\n",
				total.empty() ? 0.0 : sumMs / total.size(), pmslam::percentile(total, 0.5), pmslam::percentile(total, 0.99));
	// Whole-log processing: the front-end plus its waits for the back-end (and the final optimisation).
	const double slamS = (sumMs + f.timing.backendWaitMs()) / 1000.0 + f.finishSeconds;
	std::printf("  SLAM time %.2f s (front-end %.2f s, waiting for the back-end %.2f s), wall time %.2f s, "
				"realtime factor %.0fx\n",
				slamS, sumMs / 1000.0, slamS - sumMs / 1000.0, f.wallSeconds,
				slamS > 0 && logSpan > 0 ? logSpan / slamS : 0.0);
}

void printMemory(const RunFacts& f)
{
	// The process's peak includes MRPT's shared libraries (~100 MB mapped and relocated at
	// start-up, before any data); the map's own memory is reported beside it.
	const auto& slam = f.run.slam();
	const auto now = pmslam::residentMemoryNow();
	const double res = slam.grid().updateOptions().resolution;
	std::printf(
		"  peak memory %.1f MB (at the end: %.1f MB own, %.1f MB mapped library files, %.1f MB of start-up "
		"library pages given back; map: %.0f m² observed, grid %.1f MB + distance layer %.1f MB%s)\n",
		pmslam::peakResidentMemoryMB(), now.anonymousMB, now.fileMB, f.releasedMB,
		slam.grid().cells().observedCells() * res * res, slam.grid().cells().memoryBytes() / (1024.0 * 1024.0),
		slam.grid().distanceMap().memoryBytes() / (1024.0 * 1024.0),
		slam.loopClosure() ? (", loop closure " + mb(slam.loopClosure()->memoryBytes())).c_str() : "");
}
}  // namespace

// D52: how noisy each lidar's scans are, and the σ its scans were matched with.
void printSensors(const pmslam::SensorNoise& noise)
{
	for (const auto& [label, measured] : noise.sensors())
	{
		const auto n = measured.noise();
		if (!n) continue;
		const double sigma = noise.sigma(label);
		const std::string name = noise.sensors().size() > 1 ? " " + (label.empty() ? std::string("(no label)") : label) : "";
		char configured[64] = "as configured";
		if (sigma > noise.configuredSigma())
			std::snprintf(configured, sizeof configured, "instead of the configured %.3f m", noise.configuredSigma());
		std::printf("  lidar%s: range noise %.3f m (from its scans): matched with sigma %.3f m %s\n", name.c_str(), *n,
					sigma, configured);
	}
}

void printSummary(const Options& o, const RunFacts& f)
{
	const auto& slam = f.run.slam();
	const auto& st = f.input.reader().stats();
	std::printf("pm-slam-app: %s\n", o.log.c_str());
	std::printf("  scans %zu, matched %zu, inserted %zu, odometry readings %zu, skipped %zu, warnings %zu\n",
				f.run.trajectory().size(), slam.scansMatched(), slam.scansInserted(), st.odometry, st.skipped, st.warnings);
	printSensors(slam.sensorNoise());
	// "ok" only where every scan was matched within a few seconds of the last accepted one: a run that
	// went longer without (a gap, look-alike places undecided), or was found again by a whole-map
	// search, found its way back, and says so.
	const bool recovered = f.untracked.warned > 0 || !f.run.foundAgain().empty();
	const char* state = f.trackingLost ? "LOST (exit status 3)" : recovered ? "recovered" : "ok";
	std::printf("  tracking: %s; %zu matches rejected (%zu of them ambiguous between look-alike places), %zu wide "
				"searches, %zu re-localisations, %zu scans inserted at the odometry pose on new ground, longest span "
				"without an accepted match %.1f s (%zu over %.0f s)\n",
				state, slam.scansRejected(), slam.scansAmbiguous(), slam.wideSearches(), slam.relocalizations(),
				slam.reanchorings(), f.untracked.longest, f.untracked.warned, kWarnUntrackedSeconds);
	if (o.localizing()) printRelocation(f.run);
	if (const auto* session = f.run.session())
		std::printf("  session: continued %s (%zu earlier parts, %zu keyframes)%s\n", o.continueFrom.c_str(),
					session->parts.size(), session->keyframes.size(),
					o.lifelong ? (", " + std::to_string(f.run.retiredKeyframes()) + " of them retired (--lifelong)").c_str() : "");
	if (const auto* lc = slam.loopClosure()) printLoopClosure(*lc, o.out);
	if (f.live) f.live->printSummary(f.run.trajectory().size());
	if (o.snapshotEvery > 0)
		std::printf("  %zu snapshots written to %s (every %.1f s)\n", f.snapshots, o.out.c_str(), o.snapshotEvery);
	printTimes(f);
	printMemory(f);
	if (o.localizing())
		std::printf("  localised on %s (unchanged): %s/map.png, trajectory: %s/trajectory.txt\n", o.localize.c_str(),
					o.out.c_str(), o.out.c_str());
	else
		std::printf("  map: %s/map.png (and map.pgm/.yaml, map.gridmap.gz, map.simplemap.gz), trajectory: %s/trajectory.txt\n",
					o.out.c_str(), o.out.c_str());
}

int exitStatus(const Options& o, const RunEnd& end, const RunFacts& f)
{
	if (end.failed) return 1;
	if (stopRequested() && !o.openEnded()) return 130;
	if (!f.trackingLost) return 0;
	std::fprintf(stderr, "pm-slam-app: tracking was lost for %.1f s of log (more than --max-untracked %.1f s): exit status 3\n",
				 f.untracked.longest, o.maxUntracked);
	return 3;
}

}  // namespace pmslam_app
