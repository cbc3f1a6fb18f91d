/* pmslam — run statistics (see RunStatistics.h). */
#include <pmslam/util/RunStatistics.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstddef>
#include <fstream>
#include <string>

namespace pmslam
{
double percentile(std::vector<double> values, double q)
{
	if (values.empty()) return 0;
	const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(q * (values.size() - 1) + 0.5));
	std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
	return values[k];
}

double peakResidentMemoryMB()
{
	rusage ru{};
	getrusage(RUSAGE_SELF, &ru);
	return ru.ru_maxrss / 1024.0;  // Linux reports KiB
}

ResidentMemory residentMemoryNow()
{
	ResidentMemory m;
	std::ifstream in("/proc/self/status");
	std::string key;
	double kib = 0;
	while (in >> key)
	{
		if (key == "RssAnon:" && in >> kib) m.anonymousMB = kib / 1024.0;
		else if (key == "RssFile:" && in >> kib) m.fileMB = kib / 1024.0;
		in.ignore(1 << 16, '\n');
	}
	return m;
}

}  // namespace pmslam
