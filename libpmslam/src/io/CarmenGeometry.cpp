/* pmslam — the beam geometry of Carmen laser lines (see CarmenGeometry.h). */
#include "CarmenGeometry.h"

#include <cmath>

namespace pmslam::carmen
{
double flaserBeamStep(std::size_t n)
{
	if (n < 2) return M_PI;
	return (n % 2 == 1) ? M_PI / static_cast<double>(n - 1) : M_PI / static_cast<double>(n);
}

}  // namespace pmslam::carmen
