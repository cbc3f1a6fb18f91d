// Test support: run a program, capture its exit code and output.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace pmslam::testing
{
struct RunResult
{
	int exitCode = -1;
	std::string output;	 // stdout and stderr, interleaved
};

/** Runs `command` through the shell with stderr merged into stdout. */
inline RunResult run(const std::string& command)
{
	RunResult r;
	FILE* p = ::popen((command + " 2>&1").c_str(), "r");
	if (!p) return r;
	std::array<char, 4096> buf{};
	std::size_t n;
	while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
	const int status = ::pclose(p);
	r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
	return r;
}

inline std::string quote(const std::string& s)
{
	std::string q = "'";
	for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
	return q + "'";
}
}  // namespace pmslam::testing
