/* pm-slam-app — where tests and benchmarks hook into a run. pm-slam-app itself has none: the hooks
 * are set only in pm-slam-app-instrumented (the same sources compiled with PMSLAM_INSTRUMENTED and
 * Instrumented.cpp; built with the tests and benchmarks, never installed), so that no user run reads
 * a test's or a benchmark's environment variable. */
#pragma once

#include <pmslam/util/LibraryPages.h>

#include <functional>
#include <memory>
#include <vector>

#include "Options.h"
#include "ScanObserver.h"

namespace pmslam_app
{
struct Hooks
{
	/** Shown each scan first, before the run's own observers. */
	std::vector<std::unique_ptr<ScanObserver>> observers;
	/** Keep the start-up library pages (to measure what giving them back saves). */
	bool keepLibraryPages = false;
	/** Called with ".before" and ".after" around giving the start-up library pages back. */
	std::function<void(const char* when)> aroundPageRelease;
};

#ifdef PMSLAM_INSTRUMENTED
/** The hooks the environment asks for (Instrumented.cpp lists them). */
Hooks instrumentedHooks(const Options& options);
#endif

/** Start-up is over: the library pages only the loader read go back (util/LibraryPages.h). Returns
 * the MB given back. */
inline double releaseStartupPages(const Hooks& hooks)
{
	if (hooks.aroundPageRelease) hooks.aroundPageRelease(".before");
	const double released = hooks.keepLibraryPages ? 0.0 : pmslam::releaseStartupLibraryPages();
	if (hooks.aroundPageRelease) hooks.aroundPageRelease(".after");
	return released;
}

}  // namespace pmslam_app
