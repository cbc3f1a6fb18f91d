/* pmslam — run statistics (see RunStatistics.h). */
#include <pmslam/RunStatistics.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstddef>

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

}  // namespace pmslam
