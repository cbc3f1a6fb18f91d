/* pmslam — a simple map read as a log (see SimpleMapLogReader.h). */
#include <mrpt/poses/CPose2D.h>
#include <pmslam/io/SimpleMapFile.h>
#include <pmslam/io/SimpleMapLogReader.h>

#include <filesystem>

namespace pmslam
{
namespace fs = std::filesystem;

namespace
{
std::string fileOf(const std::string& path)
{
	return fs::is_directory(path) ? (fs::path(path) / "map.simplemap.gz").string() : path;
}
}  // namespace

bool SimpleMapLogReader::accepts(const std::string& path)
{
	std::error_code ec;
	if (fs::is_directory(path, ec)) return fs::is_regular_file(fs::path(path) / "map.simplemap.gz", ec);
	return isSimpleMapName(path);
}

SimpleMapLogReader::SimpleMapLogReader(const std::string& path) : LogReader(path)
{
	try
	{
		m_keyframes = readSimpleMapFile(fileOf(path));
	}
	catch (const SimpleMapFileError& e)
	{
		throw LogError(std::string("pmslam: ") + e.what());
	}
}

bool SimpleMapLogReader::next(LogEvent& ev)
{
	while (m_queue.empty() && m_next < m_keyframes.size())
	{
		const std::size_t k = m_next++;
		const auto [pose, sf] = m_keyframes.get(k);
		++m_stats.linesOrObjects;
		if (!pose || !sf) continue;
		const auto odometry = mrpt::poses::CPose2D(pose->getMeanVal()).asTPose();
		for (const auto& obs : *sf)
			if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs))
			{
				LogEvent e;
				e.kind = LogEvent::Kind::Scan;
				e.scan = scan;
				e.timestamp = scan->timestamp != INVALID_TIMESTAMP ? mrpt::Clock::toDouble(scan->timestamp) : double(k);
				e.scanHasOdometry = true;
				e.scanOdometry = odometry;
				e.sourceIndex = k + 1;
				m_queue.push_back(e);
			}
	}
	return !m_queue.empty() && deliver(m_queue, ev);
}

}  // namespace pmslam
