/* pm-slam-app — Ctrl-C and SIGTERM (see StopSignal.h). */
#include "StopSignal.h"

#include <atomic>
#include <csignal>
#include <ctime>

namespace pmslam_app
{
namespace
{
std::atomic<unsigned> g_stops{0};
std::atomic<long long> g_stopAtNs{0};  // CLOCK_MONOTONIC of the first signal

void onSignal(int sig)
{
	timespec ts{};
	::clock_gettime(CLOCK_MONOTONIC, &ts);	// async-signal-safe
	const long long now = (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
	if (g_stops)
	{
		// A second Ctrl-C / SIGTERM: stop now, without writing outputs. Not a repeat within half a
		// second: coreutils' timeout sends its signal to the process and to its group, so one timeout can
		// deliver it twice.
		if (now - g_stopAtNs.load() < 500000000LL) return;
		std::signal(sig, SIG_DFL);
		std::raise(sig);
	}
	g_stopAtNs = now;
	++g_stops;
}
}  // namespace

void installStopSignals()
{
	std::signal(SIGINT, onSignal);
	std::signal(SIGTERM, onSignal);
}

bool stopRequested() { return g_stops.load() > 0; }
unsigned stopCount() { return g_stops.load(); }

}  // namespace pmslam_app
