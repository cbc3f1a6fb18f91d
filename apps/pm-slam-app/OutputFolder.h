/* pm-slam-app — the --out folder, left as the user expects it.
 *
 * A run that fails before it wrote anything leaves no folder it created itself behind (an empty
 * pmslam-out after a typo in the log's name). A run into a folder holding an earlier run's outputs
 * removes those of them this run does not write, saying so in one line: a graph.graph of an earlier SLAM
 * run must not sit beside a new --localize trajectory as if they belonged together. Only pm-slam-app's
 * own output names (Outputs.h) are ever removed, nothing else in the folder.
 */
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pmslam_app
{
class OutputFolder
{
   public:
	explicit OutputFolder(std::string path);
	/** Creates the folder (and its parents) when missing and checks that `bytesNeeded` fit; throws
	 * std::runtime_error with one line. */
	void prepare(std::uint64_t bytesNeeded);
	/** The run failed before writing anything: removes the folders prepare() created (when still empty). */
	void abandon();
	/** After this run wrote `written` (names in the folder): removes the other pm-slam-app outputs an
	 * earlier run left there, and names them on stderr. A file the run read (`read`: the --localize map,
	 * the log, the configuration) is never removed, whatever its name. */
	void removeStale(const std::vector<std::string>& written, const std::vector<std::string>& read);

   private:
	std::string m_path;
	std::vector<std::string> m_created;	 // deepest first
};

}  // namespace pmslam_app
