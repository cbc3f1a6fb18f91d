/* pm-slam-app — the --out folder (see OutputFolder.h). */
#include "OutputFolder.h"

#include <pmslam/io/AtomicFile.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "Outputs.h"

namespace pmslam_app
{
namespace fs = std::filesystem;

OutputFolder::OutputFolder(std::string path) : m_path(std::move(path)) {}

void OutputFolder::prepare(std::uint64_t bytesNeeded)
{
	std::error_code ec;
	for (fs::path p = fs::absolute(m_path.empty() ? "." : m_path, ec).lexically_normal(); !p.empty() && !fs::exists(p, ec);
		 p = p.parent_path())
	{
		m_created.push_back(p.string());
		if (p == p.parent_path()) break;
	}
	pmslam::checkDirectoryWritable(m_path, bytesNeeded);
}

void OutputFolder::abandon()
{
	std::error_code ec;
	for (const auto& dir : m_created)
		if (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec) || !fs::remove(dir, ec)) break;
	m_created.clear();
}

void OutputFolder::removeStale(const std::vector<std::string>& written, const std::vector<std::string>& read)
{
	std::string removed;
	std::error_code ec;
	for (const auto& name : allOutputNames())
	{
		if (std::find(written.begin(), written.end(), name) != written.end()) continue;
		const fs::path p = fs::path(m_path) / name;
		if (!fs::is_regular_file(fs::symlink_status(p, ec))) continue;
		if (std::any_of(read.begin(), read.end(), [&](const std::string& r) { return fs::equivalent(p, r, ec); }))
			continue;
		if (!fs::remove(p, ec)) continue;
		removed += (removed.empty() ? "" : ", ") + name;
	}
	if (!removed.empty())
		std::cerr << "pm-slam-app: removed from " << m_path << " what an earlier run left there and this run does not write: "
				  << removed << "\n";
}

}  // namespace pmslam_app
