/* pmslam — a session (see Session.h). */
#include <mrpt/config/CConfigFile.h>
#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/PriorMap.h>
#include <pmslam/io/SimpleMapFile.h>
#include <pmslam/slam/Session.h>
#include <pmslam/util/ExceptionText.h>

#include <filesystem>
#include <sstream>

namespace pmslam
{
namespace fs = std::filesystem;

namespace
{
std::string need(const fs::path& dir, const char* name)
{
	const fs::path p = dir / name;
	if (!fs::is_regular_file(p))
		throw SessionError(p.string() + ": missing (expected a pm-slam-app output folder of a mapping run)");
	return p.string();
}

mrpt::maps::CSimpleMap readKeyframes(const std::string& path)
{
	try
	{
		return readSimpleMapFile(path);
	}
	catch (const SimpleMapFileError& e)
	{
		throw SessionError(e.what());
	}
}

/** session.ini's parts and resolution; false when the folder has none (written before it existed). */
bool readIndex(const fs::path& dir, Session& s)
{
	const fs::path p = dir / "session.ini";
	if (!fs::exists(p)) return false;
	const std::string file = p.string();
	mrpt::config::CConfigFile ini(file);
	const int format = ini.read_int("Session", "format", 0);
	if (format < 1)
		throw SessionError(file + ": [Session] format missing or not a positive integer (expected 1)");
	if (format > Session::kFormat)
		throw SessionError(file + ": format " + std::to_string(format) + " is newer than this pmslam reads (" +
						   std::to_string(Session::kFormat) + "): continue it with the pmslam that wrote it");
	s.resolution = ini.read_double("Session", "resolution", 0);
	if (!(s.resolution > 0)) throw SessionError(file + ": [Session] resolution missing or not positive (m)");
	const int parts = ini.read_int("Session", "parts", 0);
	if (parts < 1) throw SessionError(file + ": [Session] parts missing or below 1");
	for (int k = 1; k <= parts; ++k)
	{
		const std::string section = "Part" + std::to_string(k);
		SessionPart part;
		part.log = ini.read_string(section, "log", "");
		const long scans = ini.read_int(section, "scans", -1), keyframes = ini.read_int(section, "keyframes", -1);
		if (scans < 0) throw SessionError(file + ": [" + section + "] scans missing or negative");
		if (keyframes < 0) throw SessionError(file + ": [" + section + "] keyframes missing or negative");
		part.scans = std::size_t(scans);
		part.keyframes = std::size_t(keyframes);
		s.parts.push_back(part);
	}
	return true;
}
void readGraph(const fs::path& dir, Session& s)
{
	// Optional: a run without loop closure has none, and the keyframes are then chained by their poses.
	const fs::path p = dir / "graph.graph";
	if (!fs::is_regular_file(p)) return;
	try
	{
		s.graph = PoseGraph::readGraphFile(p.string());
	}
	catch (const std::exception& e)
	{
		throw SessionError(p.string() + ": not a readable pose graph (" + exceptionSummary(e.what()) + ")");
	}
	if (s.graph->nodeCount() != s.keyframes.size())
		throw SessionError(p.string() + ": " + std::to_string(s.graph->nodeCount()) + " nodes for " +
						   std::to_string(s.keyframes.size()) + " keyframes in map.simplemap.gz");
}
}  // namespace

Session loadSession(const std::string& folder)
{
	Session s;
	s.folder = folder;
	const fs::path dir(folder);
	if (!fs::is_directory(dir)) throw SessionError(folder + ": not a folder (expected a pm-slam-app output folder)");
	const bool indexed = readIndex(dir, s);
	const std::string trajectory = need(dir, "trajectory.txt");
	try
	{
		s.trajectory = loadTrajectory(trajectory);
	}
	catch (const std::exception& e)
	{
		throw SessionError(trajectory + ": " + exceptionSummary(e.what()));
	}
	s.keyframes = readKeyframes(need(dir, "map.simplemap.gz"));
	try
	{
		s.grid = loadPriorMap((dir / "map.gridmap.gz").string()).grid;
	}
	catch (const std::exception& e)
	{
		throw SessionError(exceptionSummary(e.what()));
	}
	if (!indexed)
	{
		s.resolution = s.grid.getResolution();
		s.parts = {{"", s.trajectory.size(), s.keyframes.size()}};
	}
	std::size_t scans = 0, keyframes = 0;
	for (const auto& p : s.parts) scans += p.scans, keyframes += p.keyframes;
	if (scans != s.trajectory.size())
		throw SessionError(folder + "/session.ini: its parts have " + std::to_string(scans) + " scans, trajectory.txt " +
						   std::to_string(s.trajectory.size()));
	if (keyframes != s.keyframes.size())
		throw SessionError(folder + "/session.ini: its parts have " + std::to_string(keyframes) +
						   " keyframes, map.simplemap.gz " + std::to_string(s.keyframes.size()));
	readGraph(dir, s);
	return s;
}

void saveSessionIndex(const std::string& folder, double resolution, const std::vector<SessionPart>& parts)
{
	writeFileAtomically((fs::path(folder) / "session.ini").string(), [&](std::ostream& out) {
		out << "# pmslam session: what `pm-slam-app --continue` needs of this folder (docs/formats.md).\n"
			<< "# Each part is a run that mapped into this map; its scans are the next lines of trajectory.txt.\n"
			<< "[Session]\nformat = " << Session::kFormat << "\nresolution = " << resolution
			<< "\nparts = " << parts.size() << "\n";
		for (std::size_t k = 0; k < parts.size(); ++k)
			out << "\n[Part" << k + 1 << "]\nlog = " << parts[k].log << "\nscans = " << parts[k].scans
				<< "\nkeyframes = " << parts[k].keyframes << "\n";
	});
}

std::string sessionPartsComment(const std::vector<SessionPart>& parts)
{
	std::ostringstream c;
	c << "sessions:";
	std::size_t first = 1;
	for (std::size_t k = 0; k < parts.size(); ++k)
	{
		c << (k ? "," : "") << " " << k + 1 << " = poses " << first << "-" << first + parts[k].scans - 1 << " ("
		  << (parts[k].log.empty() ? "log unknown" : parts[k].log) << ")";
		first += parts[k].scans;
	}
	return c.str();
}

}  // namespace pmslam
