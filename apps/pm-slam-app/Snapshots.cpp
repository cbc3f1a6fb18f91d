/* pm-slam-app — --snapshot-every (see Snapshots.h). */
#include "Snapshots.h"

#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/MapExport.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "SlamRun.h"

#include "../common/Message.h"

namespace pmslam_app
{
Snapshots::Snapshots(const Options& options, pmslam::ProgressLine& progress) : m_options(options), m_progress(progress)
{
}

void Snapshots::onScan(const ScanStep& s)
{
	if (!(m_options.snapshotEvery > 0) ||
		std::chrono::steady_clock::now() - m_last <= std::chrono::duration<double>(m_options.snapshotEvery))
		return;
	try
	{
		write(s.run);
	}
	catch (const std::exception& e)
	{
		m_progress.clear();
		std::cerr << "pm-slam-app: warning: snapshot to " << m_options.out << " failed: " << withoutLibraryPrefix(e.what()) << "\n";
	}
	m_last = std::chrono::steady_clock::now();
}

void Snapshots::write(const SlamRun& run)
{
	namespace fs = std::filesystem;
	const auto at = [&](const char* name) { return (fs::path(m_options.out) / name).string(); };
	const pmslam::Trajectory now = run.corrected(run.trajectory());
	char line[160];
	std::snprintf(line, sizeof line, "%.6f %.4f %.4f %.5f\n", now.back().timestamp, now.back().x, now.back().y,
				  now.back().yaw);
	pmslam::writeFileAtomically(at("pose.txt"), [&](std::ostream& out) {
		out << "# timestamp x y yaw: the newest pose (m, m, rad), written every " << m_options.snapshotEvery
			<< " s while running\n"
			<< line;
	});
	pmslam::saveTrajectory(at("trajectory.txt"), now, "pm-slam-app " + m_options.log + ": snapshot while running");
	pmslam::saveMapPng(run.slam().grid(), now, at("map.png"), run.loopLinks());
	if (!m_options.localizing()) pmslam::saveMapPgmYaml(run.slam().grid(), at("map.pgm"), at("map.yaml"));
	++m_written;
}

}  // namespace pmslam_app
