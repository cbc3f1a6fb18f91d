/* pm-slam-app — Ctrl-C and SIGTERM: the first asks the run to stop (it still writes its outputs), a
 * second one later ends the process at once. */
#pragma once

namespace pmslam_app
{
/** Installs the handlers (first thing in main(): a signal at any time ends with outputs and status 130). */
void installStopSignals();
/** Whether a stop was asked for. */
bool stopRequested();
/** How many stops were asked for so far (repeats within half a second count once). */
unsigned stopCount();

}  // namespace pmslam_app
