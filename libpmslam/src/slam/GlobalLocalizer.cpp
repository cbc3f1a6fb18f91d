/* pmslam — finding the robot on a fixed map without a start pose (see GlobalLocalizer.h). */
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/slam/GlobalLocalizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace pmslam
{
namespace
{
using mrpt::math::TPose2D;

TPose2D compose(const TPose2D& a, const TPose2D& b) { return (mrpt::poses::CPose2D(a) + mrpt::poses::CPose2D(b)).asTPose(); }

/** b⁻¹ ⊕ a: the motion from b to a. */
TPose2D between(const TPose2D& a, const TPose2D& b) { return (mrpt::poses::CPose2D(a) - mrpt::poses::CPose2D(b)).asTPose(); }

/** The rotation step that moves the scan's far points (90th percentile of range, at least 2 m) by
 * about one cell: the max range would make a single far return set the cost of the whole search. */
double rotationStep(const std::vector<mrpt::math::TPoint2Df>& points, double resolution)
{
	std::vector<float> r;
	r.reserve(points.size());
	for (const auto& p : points) r.push_back(std::hypot(p.x, p.y));
	const auto k = r.begin() + std::ptrdiff_t(r.size() * 9 / 10);
	std::nth_element(r.begin(), k, r.end());
	return resolution / std::max(2.0, double(*k));
}
/** The two-stage search can miss the true place (its coarse ranking ties easily), so a lone place it
 * proposes is confirmed by a second view before it is believed. */
RivalsOptions rivalsFor(const GlobalLocalizerOptions& o)
{
	RivalsOptions r = o.rivals;
	if (o.coarseToFine) r.minViews = std::max<std::size_t>(r.minViews, 2);
	return r;
}
}  // namespace

GlobalLocalizer::GlobalLocalizer(const mrpt::maps::COccupancyGridMap2D& map,
								 const PerfectMatchMatcher::TConfigParams& matcher, const ScanPointsOptions& scanOptions,
								 const GlobalLocalizerOptions& options)
	: m_opts(options),
	  m_scanOpts(scanOptions),
	  m_matcher(matcher),
	  m_distance(PerfectMatchMatcher::distanceMapFromGrid(map, matcher.maxDistance, matcher.occupiedThreshold)),
	  m_rivals(rivalsFor(options))
{
	const double r = map.getResolution();
	m_shift = {map.getXMin() - std::lround(map.getXMin() / r) * r, map.getYMin() - std::lround(map.getYMin() / r) * r};
	m_pyramid = std::make_unique<LikelihoodPyramid>(
		LikelihoodPyramid::fromGrid(map, matcher.maxDistance, matcher.occupiedThreshold));
	if (m_opts.coarseToFine)
		m_coarse = std::make_unique<LikelihoodPyramid>(BranchAndBoundSearch(*m_pyramid).coarsePyramid());
}

GlobalLocalizer::State GlobalLocalizer::addScan(const mrpt::obs::CObservation2DRangeScan& scan,
												const std::optional<TPose2D>& odometry)
{
	if (m_state != State::Searching) return m_state;
	const auto points = scanToPoints(scan, m_scanOpts).hits;
	if (m_scans == 0) m_firstOdometry = odometry;
	if (odometry) m_lastOdometry = odometry;
	++m_scans;
	if (points.size() >= 10)
	{
		// Since the last scan the places were matched at: a scan with too few points moves them too.
		const TPose2D motion =
			odometry && m_matchedOdometry ? between(*odometry, *m_matchedOdometry) : TPose2D(0, 0, 0);
		if (odometry) m_matchedOdometry = odometry;
		if (!m_rivals.empty()) m_rivals.follow(m_matcher, m_distance, points, motion, m_shift);
		if (m_rivals.empty()) searchAnew(points);  // at the start, or every place has been dropped
		if (m_rivals.decide()) m_state = State::Found;
	}
	if (m_state == State::Searching &&
		(views() >= m_opts.maxViews || (m_rivals.empty() && m_searches >= m_opts.maxSearches)))
		m_state = State::Undecided;
	return m_state;
}

TPose2D GlobalLocalizer::refine(const std::vector<mrpt::math::TPoint2Df>& points, const TPose2D& start,
								PerfectMatchMatcher::MatchInfo& info) const
{
	TPose2D p = m_matcher.alignPoints(m_distance, points, {start.x - m_shift.x, start.y - m_shift.y, start.phi}, &info);
	return {p.x + m_shift.x, p.y + m_shift.y, mrpt::math::wrapToPi(p.phi)};
}

void GlobalLocalizer::searchAnew(const std::vector<mrpt::math::TPoint2Df>& points)
{
	BranchAndBoundSearch::Options o;
	o.candidates = m_opts.candidates;
	o.minRelativeScore = m_opts.candidateFloor;
	o.maxPoints = m_opts.searchPoints;
	o.angularStep = rotationStep(points, m_pyramid->resolution());
	o.coarse.candidates = m_opts.coarseCandidates;
	o.coarse.minRelativeScore = m_opts.coarseFloor;
	o.coarse.maxPoints = m_opts.coarsePoints;
	const auto t0 = std::chrono::steady_clock::now();
	const BranchAndBoundSearch search(*m_pyramid, o);
	const auto result = m_coarse ? search.searchGlobalCoarseToFine(points, *m_coarse) : search.searchGlobal(points);
	m_searchSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	++m_searches;
	// Carried back to the first scan by the odometry since (no odometry: where the search found it).
	const TPose2D back =
		m_firstOdometry && m_lastOdometry ? between(*m_firstOdometry, *m_lastOdometry) : TPose2D(0, 0, 0);
	for (const auto& c : result.candidates)
	{
		PerfectMatchMatcher::MatchInfo info;
		const TPose2D pose = refine(points, c.pose, info);
		if (info.goodness >= m_opts.rivals.minGoodness) m_rivals.add(pose, compose(pose, back), info);
	}
}

std::optional<GlobalLocalizer::Hypothesis> GlobalLocalizer::best() const
{
	if (m_rivals.empty()) return std::nullopt;
	return m_rivals.leader();
}

}  // namespace pmslam
