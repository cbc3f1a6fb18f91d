/* pm-slam-app-instrumented — the test and benchmark hooks (see Hooks.h), each asked for by an
 * environment variable:
 *   PMSLAM_TEST_SCAN_DELAY_MS=N   --live: each scan takes N ms more, a SLAM slower than its sensors
 *                                 (tests/apps/test_live.cpp: the oldest scans must be dropped)
 *   PMSLAM_KEEP_LIBRARY_PAGES=1   keep the start-up library pages (bench/memory.sh: what giving them back saves)
 *   PMSLAM_SMAPS_DUMP=FILE        /proc/self/smaps just before (FILE.before) and after (FILE.after) the
 *                                 start-up pages go back (bench/memory.sh: what each library costs)
 *   PMSLAM_KEYFRAMES_DUMP=FILE    each loop-closure keyframe's time, pose and match Hessian, appended
 *                                 (bench/calibrate_information.py)
 * This file is compiled into pm-slam-app-instrumented only. */
#include <pmslam/graph/KeyframeProbe.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "Hooks.h"

namespace pmslam_app
{
namespace
{
class ScanDelay : public ScanObserver
{
   public:
	explicit ScanDelay(int ms) : m_ms(ms) {}
	void onScan(const ScanStep&) override { std::this_thread::sleep_for(std::chrono::milliseconds(m_ms)); }

   private:
	int m_ms;
};

const char* variable(const char* name)
{
	const char* v = std::getenv(name);
	return v && *v ? v : nullptr;
}

void dumpKeyframesTo(const std::string& path)
{
	pmslam::setKeyframeProbe([path](const pmslam::KeyframeSample& k) {
		if (FILE* f = std::fopen(path.c_str(), "a"))
		{
			const auto& h = k.hessian;
			std::fprintf(f, "%.6f %.6f %.6f %.6f %.6g %.6g %.6g %.6g %.6g %.6g\n", k.timestamp, k.pose.x, k.pose.y,
						 k.pose.phi, h(0, 0), h(0, 1), h(0, 2), h(1, 1), h(1, 2), h(2, 2));
			std::fclose(f);
		}
	});
}
}  // namespace

Hooks instrumentedHooks(const Options& options)
{
	Hooks h;
	if (const char* delay = variable("PMSLAM_TEST_SCAN_DELAY_MS"); delay && options.isLive() && std::atoi(delay) > 0)
		h.observers.push_back(std::make_unique<ScanDelay>(std::atoi(delay)));
	if (const char* keep = variable("PMSLAM_KEEP_LIBRARY_PAGES")) h.keepLibraryPages = *keep != '0';
	if (const char* smaps = variable("PMSLAM_SMAPS_DUMP"))
		h.aroundPageRelease = [path = std::string(smaps)](const char* when) {
			std::ifstream in("/proc/self/smaps");
			std::ofstream(path + when) << in.rdbuf();
		};
	if (const char* keyframes = variable("PMSLAM_KEYFRAMES_DUMP")) dumpKeyframesTo(keyframes);
	return h;
}

}  // namespace pmslam_app
