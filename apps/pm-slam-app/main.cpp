/* pm-slam-app — online Perfect Match SLAM on a robot log.
 *
 *   pm-slam-app [options] [LOG]
 *
 * Reads an MRPT .rawlog or a Carmen log (or a log still being written, or live sensors), builds the map
 * and the trajectory scan by scan, and writes them to --out (see --help and README.md). The parts: the
 * command line (Options), the input (Input), the SLAM (SlamRun) and its loop (RunLoop), what watches it
 * scan by scan (Observers), the outputs (Outputs, OutputFolder), and the summary and exit status (Summary).
 */
#include <pmslam/io/MapExport.h>
#include <pmslam/io/PriorMap.h>
#include <pmslam/slam/Session.h>
#include <pmslam/slam/SlamConfig.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "../common/Message.h"
#include "GuiView.h"
#include "Hooks.h"
#include "Input.h"
#include "Observers.h"
#include "OutputFolder.h"
#include "Outputs.h"
#include "ProgressLine.h"
#include "RunLoop.h"
#include "StopSignal.h"
#include "Summary.h"

using namespace pmslam_app;

namespace
{
/** The configuration --config and --set give; exits 2 with one line when it is bad. */
pmslam::SlamConfig loadConfigOrExit(Options& options)
{
	pmslam::SlamConfig cfg;
	try
	{
		cfg = pmslam::loadSlamConfig(options.config, options.sets);
	}
	catch (const std::exception& e)
	{
		say(e.what());
		std::exit(2);
	}
	for (const auto& n : cfg.notes)
		if (!options.quiet) say("note: " + n);
	takeIcpSlamNames(options, cfg);
	return cfg;
}

/** A floor, not a forecast: the map files grow with the mapped area, unknown yet, but a trajectory and
 * timing line per scan and the smallest map files need at least this. */
std::uint64_t bytesNeeded(const pmslam::LogReader& reader)
{
	return (std::uint64_t(1) << 20) + 128 * std::uint64_t(reader.estimatedScanCount());
}

/** Every output said and flushed; a sensor thread stuck in its driver or the GUI toolkit's detached
 * thread could still use what static destructors would tear down (a SIGSEGV at exit now and then). */
[[noreturn]] void exitNow(int status)
{
	std::fflush(nullptr);
	std::_Exit(status);
}

/** --continue DIR: its session, which must be another folder than --out and have the configured map
 * resolution. False when not (said on stderr). */
bool loadSessionToContinue(const Options& o, const pmslam::SlamConfig& cfg, pmslam::Session& session)
{
	std::error_code ec;
	if (std::filesystem::equivalent(o.continueFrom, o.out, ec))
	{
		say("--continue " + o.continueFrom + " is never modified: give another --out");
		return false;
	}
	try
	{
		session = pmslam::loadSession(o.continueFrom);
	}
	catch (const std::exception& e)
	{
		say("--continue " + withoutLibraryPrefix(e.what()));
		return false;
	}
	if (std::abs(session.resolution - cfg.mapping.grid.resolution) > 1e-9)
	{
		say("--continue " + o.continueFrom + ": its map is at " + std::to_string(session.resolution) +
			" m per cell, the configuration asks for " + std::to_string(cfg.mapping.grid.resolution) +
			" ([MappingApplication] resolution must stay the same)");
		return false;
	}
	return true;
}

/** The input and the prior map, then --out: a bad input must not leave an empty folder behind. False
 * when one of them is bad (said on stderr). */
bool openInputAndOutput(const Options& o, const pmslam::SlamConfig& cfg, Input& input,
						mrpt::maps::COccupancyGridMap2D& priorMap, pmslam::Session& session, OutputFolder& folder)
{
	try
	{
		input.open(o, cfg.log);
	}
	catch (const std::exception& e)
	{
		say(e.what());
		if (o.isLive()) exitNow(2);	 // a sensor thread may be stuck inside its driver, using `input`
		return false;
	}
	try
	{
		if (o.localizing()) priorMap = pmslam::loadPriorMap(o.localize, cfg.mapping.grid.resolution).grid;
	}
	catch (const std::exception& e)
	{
		say("--localize " + withoutLibraryPrefix(e.what()));
		return false;
	}
	if (o.continuing() && !loadSessionToContinue(o, cfg, session)) return false;
	try
	{
		folder.prepare(bytesNeeded(input.reader()));
	}
	catch (const std::exception& e)
	{
		say("--out " + o.out + ": " + withoutLibraryPrefix(e.what()));
		return false;
	}
	return true;
}

/** How the search for the start ended; false when it found none (then nothing was tracked). */
bool sayStart(const pmslam::GlobalLocalizer& g, const Options& o)
{
	char line[400];
	const auto best = g.best();
	if (o.continuing() && g.state() != pmslam::GlobalLocalizer::State::Found)
	{
		std::snprintf(line, sizeof line,
					  "--continue: no place on %s's map explains any stretch of the log (%zu scans, %zu whole-map "
					  "searches along it): the log and the map do not overlap; nothing written (exit status 3)",
					  o.continueFrom.c_str(), g.scansUsed(), g.searches());
		say(line);
		return false;
	}
	if (g.state() == pmslam::GlobalLocalizer::State::Found)
	{
		std::snprintf(line, sizeof line,
					  "global localisation: start found at %.3f %.3f %.1f deg after %zu scans (its matches %.2f, the "
					  "best rival's %.2f; %zu whole-map searches, %.2f s)",
					  best->origin.x, best->origin.y, mrpt::RAD2DEG(best->origin.phi), g.scansUsed(), best->mean(),
					  g.runnerUp(), g.searches(), g.searchSeconds());
		say(line);
		return true;
	}
	if (best)
		std::snprintf(line, sizeof line,
					  "global localisation: UNDECIDED after %zu scans: %zu places explain the scans alike (best at "
					  "%.2f %.2f %.0f deg: %.2f, the next %.2f); nothing tracked: give --initial-pose, or start "
					  "where the map is distinctive (exit status 3)",
					  g.scansUsed(), g.hypotheses(), best->pose.x, best->pose.y, mrpt::RAD2DEG(best->pose.phi),
					  best->mean(), g.runnerUp());
	else
		std::snprintf(line, sizeof line,
					  "global localisation: NOT FOUND after %zu scans: no place on the map explains the scans "
					  "(%zu whole-map searches); nothing tracked: is it the right map? (exit status 3)",
					  g.scansUsed(), g.searches());
	say(line);
	return false;
}

void sayNoScans(const Options& o, const pmslam::LogReadStats& st)
{
	say("no laser scan in '" + o.log + "' (" + std::to_string(st.linesOrObjects) + " lines/objects read, " +
		std::to_string(st.skipped) +
		" skipped): expected FLASER/RLASER/ROBOTLASER1 lines or CObservation2DRangeScan objects (or 3D "
		"observations to slice: CObservation3DRangeScan, CObservationPointCloud, CObservationVelodyneScan)");
}

/** Why the run ended before its input did, if it did. */
void sayEarlyEnd(const Options& o, std::size_t scans, const RunEnd& end)
{
	if (stopRequested() && !o.openEnded())
		say("interrupted after " + std::to_string(scans) + " scans: writing what was computed");
	if (end.failed)
		say("error after " + std::to_string(scans) + " scans: " + withoutLibraryPrefix(end.failure) + ": writing what was computed");
}

/** Writes the outputs and removes an earlier run's outputs this run did not write. False when writing
 * failed (said). */
bool finishOutputs(const Options& o, const SlamRun& run, const pmslam::Trajectory& online, const Observers& obs,
				   const RunEnd& end, OutputFolder& folder)
{
	const std::string scans = std::to_string(run.trajectory().size());
	const bool interrupted = stopRequested() && !o.openEnded();
	std::ostringstream header;
	header << "pm-slam-app " << o.log << " (" << scans << " scans)";
	if (o.localizing()) header << " localised on " << o.localize;
	if (o.continuing()) header << " continuing " << o.continueFrom;
	try
	{
		writeOutputs(o.out, run, online, obs.timing, header.str(), o.localizing(), o.log);
	}
	catch (const std::exception& e)
	{
		say("cannot write outputs to " + o.out + ": " + withoutLibraryPrefix(e.what()));
		return false;
	}
	auto written = finalOutputNames(o.localizing(), run.slam().loopClosure() != nullptr);
	if (obs.snapshots.written()) written.push_back("pose.txt");
	folder.removeStale(written, {o.localize, o.continueFrom, o.log, o.config});
	if (interrupted || end.failed) say("wrote the map and the trajectory of " + scans + " scans to " + o.out);
	return true;
}
}  // namespace

int main(int argc, char** argv)
{
	installStopSignals();  // first: a signal at any time ends with exit code 130 and outputs
	Options options = parseOptions(argc, argv);
	// A sensor driver writing to a connection the sensor has closed must get an error, not end the process.
	if (options.isLive()) std::signal(SIGPIPE, SIG_IGN);
	const pmslam::SlamConfig cfg = loadConfigOrExit(options);

	Input input;
	mrpt::maps::COccupancyGridMap2D priorMap;
	pmslam::Session session;
	OutputFolder folder(options.out);
	if (!openInputAndOutput(options, cfg, input, priorMap, session, folder)) return 2;

	const bool showProgress = options.progress == 1 || (options.progress == -1 && isatty(STDERR_FILENO) && !options.quiet);
	pmslam::ProgressLine progress(showProgress, input.reader().estimatedScanCount());
	input.reader().onWarning = [&](const std::string& w) { progress.clear(), say("warning: " + w); };
	SlamRun run(cfg);
	run.setLifelong(options.lifelong);
	try
	{
		if (options.localizing() && options.initialPoseGiven) run.localize(priorMap, options.initialPose, true);
		if (options.localizing() && !options.initialPoseGiven) run.findStart(priorMap);
		if (options.continuing())
			run.continueSession(session, options.initialPoseGiven ? std::optional(options.initialPose) : std::nullopt);
	}
	catch (const std::exception& e)
	{
		say((options.continuing() ? "--continue " + options.continueFrom : "--localize " + options.localize) + ": " +
			withoutLibraryPrefix(e.what()));
		folder.abandon();
		return 2;
	}
	auto gui = options.gui ? std::make_unique<GuiView>(options.log, cfg.mapping.grid.scan) : nullptr;
	Hooks hooks;
#ifdef PMSLAM_INSTRUMENTED
	hooks = instrumentedHooks(options);
#endif
	const double releasedMB = releaseStartupPages(hooks);
	Observers observers(options, input, progress, hooks, gui.get());

	const auto wallStart = std::chrono::steady_clock::now();
	RunEnd end = runLoop(input.reader(), run, observers.inOrder, options.isLive(), options.maxScans);
	progress.clear();
	const std::size_t stuckSensors = input.finish();  // nothing arrives any more: the counts are final
	pmslam::Trajectory online;
	const auto finishStart = std::chrono::steady_clock::now();
	try
	{
		run.finish(online);
	}
	catch (const std::exception& e)
	{
		end = {true, std::string("loop closure: ") + withoutLibraryPrefix(e.what())};
	}
	const auto secondsSince = [](auto t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); };
	const double finishS = secondsSince(finishStart), wallS = secondsSince(wallStart);

	if (const auto* start = run.startSearch())
		if (!sayStart(*start, options))
		{
			folder.abandon();
			return 3;
		}
	if (run.trajectory().empty() && !stopRequested() && !end.failed)
	{
		sayNoScans(options, input.reader().stats());
		folder.abandon();
		if (stuckSensors) exitNow(2);
		return 2;
	}
	sayEarlyEnd(options, run.trajectory().size(), end);
	const UntrackedSpans untracked = reportUntrackedSpans(run.slam());
	if (!finishOutputs(options, run, online, observers, end, folder)) return 1;
	const RunFacts facts{input, run, observers.timing, observers.live.get(), untracked,
						 untracked.longest > options.maxUntracked, observers.snapshots.written(), finishS, wallS, releasedMB};
	if (!options.quiet) printSummary(options, facts);
	const int status = exitStatus(options, end, facts);
	std::fflush(stdout);  // everything said so far must survive whatever the GUI toolkit does at exit
	std::fflush(stderr);
	if (stuckSensors) exitNow(status);
	if (gui && gui->isOpen())
	{
		gui->showFinalAndWait(run);
		exitNow(status);
	}
	return status;
}
