/* pmslam — private helpers shared by the text-file readers (not installed). */
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>

namespace pmslam::detail
{
inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

/** Parse exactly `n` whitespace-separated finite numbers filling the whole line.
 * Locale-independent. Returns false on any deviation. */
inline bool parseNumbers(std::string_view line, double* out, std::size_t n)
{
	std::size_t i = 0, k = 0;
	for (;;)
	{
		while (i < line.size() && isBlank(line[i])) ++i;
		if (i == line.size()) return k == n;
		if (k == n) return false;  // trailing garbage
		std::size_t j = i;
		while (j < line.size() && !isBlank(line[j])) ++j;
		std::string_view tok = line.substr(i, j - i);
		if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
		double v = 0;
		const auto res = std::from_chars(tok.data(), tok.data() + tok.size(), v);
		if (res.ec != std::errc() || res.ptr != tok.data() + tok.size() || !std::isfinite(v)) return false;
		out[k++] = v;
		i = j;
	}
}

/** True for lines to skip: empty, whitespace only, or starting with '#'. */
inline bool isCommentOrBlank(std::string_view line)
{
	std::size_t i = 0;
	while (i < line.size() && isBlank(line[i])) ++i;
	return i == line.size() || line[i] == '#';
}

/** The offending line for an error message, trimmed and shortened. */
inline std::string quoteForError(std::string_view line)
{
	while (!line.empty() && isBlank(line.back())) line.remove_suffix(1);
	while (!line.empty() && isBlank(line.front())) line.remove_prefix(1);
	constexpr std::size_t kMax = 80;
	std::string s(line.substr(0, kMax));
	if (line.size() > kMax) s += "...";
	return "'" + s + "'";
}

}  // namespace pmslam::detail
