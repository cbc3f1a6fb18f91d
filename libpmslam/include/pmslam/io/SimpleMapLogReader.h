/* pmslam — a simple map read as a log: each keyframe's scans, with the keyframe's pose as their odometry.
 *
 * What merging two sessions needs (pm-slam-app --continue A B/): B's keyframes, replayed in their order,
 * are a log whose "odometry" is B's own optimised trajectory, so the continuing run finds where B lies on
 * A's map and maps B's scans into it. Reads an MRPT .simplemap or .simplemap.gz, or a pm-slam-app output
 * folder (its map.simplemap.gz). Scans only (every CObservation2DRangeScan of each sensory frame); a
 * scan without a timestamp gets its keyframe's index in seconds.
 */
#pragma once

#include <mrpt/maps/CSimpleMap.h>
#include <pmslam/io/LogReader.h>

#include <string>

namespace pmslam
{
class SimpleMapLogReader : public LogReader
{
   public:
	/** Throws LogError (one line naming the file) when it is not a readable simple map with a keyframe. */
	explicit SimpleMapLogReader(const std::string& path);
	bool next(LogEvent& ev) override;
	std::size_t estimatedScanCount() const override { return m_keyframes.size(); }

	/** A path this reader takes: a .simplemap[.gz] file, or a folder holding map.simplemap.gz. */
	static bool accepts(const std::string& path);

   private:
	mrpt::maps::CSimpleMap m_keyframes;
	std::size_t m_next = 0;
	std::deque<LogEvent> m_queue;
};

}  // namespace pmslam
