/* pmslam — surface normals of scan points (see SurfaceNormals.h). */
#include <pmslam/sensor/SurfaceNormals.h>

#include <cmath>

namespace pmslam
{
std::vector<mrpt::math::TPoint2Df> surfaceNormals(const std::vector<mrpt::math::TPoint2Df>& pts)
{
	constexpr float kSpan = 0.3f;  // m each side: a shorter piece of wall gives a normal of range noise
	constexpr int kMaxSteps = 40;  // neighbours looked at each side
	constexpr float kMaxGap = 5.0f;  // m to the next return: beyond, no surface between them
	std::vector<mrpt::math::TPoint2Df> n(pts.size(), mrpt::math::TPoint2Df(0, 0));
	const int count = static_cast<int>(pts.size());
	// Squared distances against squared limits: this runs for every point of every matched scan.
	constexpr float kSpan2 = kSpan * kSpan, kMaxGap2 = kMaxGap * kMaxGap;
	auto dist2 = [&](int a, int b) {
		const float dx = pts[a].x - pts[b].x, dy = pts[a].y - pts[b].y;
		return dx * dx + dy * dy;
	};
	for (int i = 0; i < count; ++i)
	{
		// The neighbours within kSpan each side, and at least the next one each side however far
		// (far returns on a wall seen at a grazing angle are metres apart: the fit decides).
		int a = i - 1, b = i + 1;
		if (a < 0 || b >= count || dist2(a, i) > kMaxGap2 || dist2(b, i) > kMaxGap2) continue;
		while (a > 0 && i - a < kMaxSteps && dist2(a - 1, i) <= kSpan2) --a;
		while (b + 1 < count && b - i < kMaxSteps && dist2(b + 1, i) <= kSpan2) ++b;
		// Line fit (principal axis) of the window's points; its scatter across the line must be
		// range noise, not a corner or clutter. One pass, about point i (the window's points are
		// within kSpan of it, or are its two neighbours: the sums stay well conditioned).
		const int m = b - a + 1;
		double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
		for (int k = a; k <= b; ++k)
		{
			const double dx = pts[k].x - pts[i].x, dy = pts[k].y - pts[i].y;
			sx += dx, sy += dy, sxx += dx * dx, sxy += dx * dy, syy += dy * dy;
		}
		sxx -= sx * sx / m, sxy -= sx * sy / m, syy -= sy * sy / m;	 // about the window's mean
		const double tr = sxx + syy, det = sxx * syy - sxy * sxy;
		const double small = 0.5 * tr - std::sqrt(std::max(0.0, 0.25 * tr * tr - det));  // smaller eigenvalue
		const double range2 = double(pts[i].x) * pts[i].x + double(pts[i].y) * pts[i].y;
		const double tol = 0.01 + 0.005 * std::sqrt(range2);
		if (!(tr > 0) || small / m > tol * tol) continue;
		// Normal: the eigenvector of the smaller eigenvalue.
		double nx = sxy, ny = small - sxx;
		if (nx * nx + ny * ny < 1e-24) nx = sxx <= syy ? 1 : 0, ny = sxx <= syy ? 0 : 1;
		const double len = std::sqrt(nx * nx + ny * ny);
		n[i] = mrpt::math::TPoint2Df(static_cast<float>(nx / len), static_cast<float>(ny / len));
	}
	return n;
}

}  // namespace pmslam
