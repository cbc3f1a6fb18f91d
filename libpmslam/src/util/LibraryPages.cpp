/* pmslam — giving back the library pages only start-up needed (see LibraryPages.h). */
#include <pmslam/util/LibraryPages.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pmslam
{
namespace
{
struct Mapping
{
	uintptr_t start = 0, end = 0;
	bool readOnlyFile = false;
	long rssKB = 0, anonymousKB = -1;
};
}  // namespace

double releaseStartupLibraryPages()
{
	std::ifstream in("/proc/self/smaps");
	if (!in) return 0.0;
	// Read everything first: madvise() while reading would change the file under the reader.
	std::vector<Mapping> maps;
	std::string line;
	while (std::getline(in, line))
	{
		unsigned long a = 0, b = 0;
		char perms[8] = {};
		char path[4096] = {};
		if (std::sscanf(line.c_str(), "%lx-%lx %7s %*s %*s %*s %4095s", &a, &b, perms, path) >= 3 &&
			line.find(':') > line.find(' '))
		{
			Mapping m;
			m.start = a;
			m.end = b;
			// Private, not writable, backed by a file: code, read-only data, symbol tables.
			m.readOnlyFile = perms[1] != 'w' && perms[3] == 'p' && path[0] == '/';
			maps.push_back(m);
			continue;
		}
		if (maps.empty()) continue;
		long kb = 0;
		if (std::sscanf(line.c_str(), "Rss: %ld kB", &kb) == 1)
			maps.back().rssKB = kb;
		else if (std::sscanf(line.c_str(), "Anonymous: %ld kB", &kb) == 1)
			maps.back().anonymousKB = kb;
	}
	long released = 0;
	for (const auto& m : maps)
	{
		// A mapping with any private page (RELRO data the loader relocated, then made read-only)
		// would lose it: only mappings without one are given back.
		if (!m.readOnlyFile || m.anonymousKB != 0 || m.rssKB == 0) continue;
		if (::madvise(reinterpret_cast<void*>(m.start), m.end - m.start, MADV_DONTNEED) == 0) released += m.rssKB;
	}
	return released / 1024.0;
}

}  // namespace pmslam
