/* pm-slam-app — a one-line progress display for terminals. */
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>

namespace pmslam
{
/** Shows "scans done/total, scans per second, ETA" on stderr, redrawn at most
 * 4 times a second; does nothing when disabled (not a terminal, CI). */
class ProgressLine
{
   public:
	ProgressLine(bool enabled, std::size_t total);
	void update(std::size_t done);
	/** A line of the caller's (live runs: received / processed / dropped, latency), made only when due. */
	void updateText(const std::function<std::string()>& line);
	/** Erases the line (before other output and at the end). */
	void clear();

   private:
	bool m_enabled;
	std::size_t m_total;
	bool m_shown = false;
	std::size_t m_width = 60;  // of the longest line shown, for clear()
	std::chrono::steady_clock::time_point m_start, m_last;
};
}  // namespace pmslam

#include "ScanObserver.h"

namespace pmslam_app
{
/** A log run's progress line: scans done out of the log's estimate (a live run's line is
 * LiveStatistics'). */
class ScanProgress : public ScanObserver
{
   public:
	explicit ScanProgress(pmslam::ProgressLine& line) : m_line(line) {}
	void onScan(const ScanStep& step) override;

   private:
	pmslam::ProgressLine& m_line;
};
}  // namespace pmslam_app
