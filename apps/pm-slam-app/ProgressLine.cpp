/* pm-slam-app — progress line (see ProgressLine.h). */
#include "ProgressLine.h"

#include <cstdio>

namespace pmslam
{
ProgressLine::ProgressLine(bool enabled, std::size_t total)
	: m_enabled(enabled), m_total(total), m_start(std::chrono::steady_clock::now()), m_last(m_start)
{
}

void ProgressLine::update(std::size_t done)
{
	updateText([&] {
		const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
		const double rate = s > 0 ? done / s : 0.0;
		char b[160];
		if (m_total > done && rate > 0)
			std::snprintf(b, sizeof b, "%zu/%zu scans, %.0f scans/s, ETA %.0f s", done, m_total, rate, (m_total - done) / rate);
		else
			std::snprintf(b, sizeof b, "%zu scans, %.0f scans/s", done, rate);
		return std::string(b);
	});
}

void ProgressLine::updateText(const std::function<std::string()>& line)
{
	if (!m_enabled) return;
	const auto now = std::chrono::steady_clock::now();
	if (now - m_last < std::chrono::milliseconds(250)) return;
	m_last = now;
	const std::string text = line();
	if (text.size() + 3 > m_width) m_width = text.size() + 3;
	std::fprintf(stderr, "\r%s   ", text.c_str());
	std::fflush(stderr);
	m_shown = true;
}

void ProgressLine::clear()
{
	if (!m_shown) return;
	std::fprintf(stderr, "\r%*s\r", int(m_width), "");
	std::fflush(stderr);
	m_shown = false;
}
}  // namespace pmslam

#include "SlamRun.h"

namespace pmslam_app
{
void ScanProgress::onScan(const ScanStep& s) { m_line.update(s.run.trajectory().size()); }
}  // namespace pmslam_app
