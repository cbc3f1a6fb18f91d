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

// m: a return this close to an obstacle of the map is on it, within the map's and the pose's error.
constexpr double kFreeSpaceMargin = 0.15;
// searchAlong: the scans a place is checked against (the last ones, every kHistoryPointStride-th point).
constexpr std::size_t kHistoryScans = 300, kHistoryPointStride = 4;

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
	if (o.searchAlong)
	{
		r.minViews = std::max(r.minViews, o.alongMinViews);
		r.minLeaderGoodness = std::max(r.minLeaderGoodness, o.alongLeaderGoodness);
	}
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
	if (m_opts.searchAlong)
	{
		// Observed free: clearly above the unknown 0.5 (MRPT's cell value is the probability of free
		// space; one observation of free space takes a cell to about 0.6).
		m_freeX0 = map.getXMin();
		m_freeY0 = map.getYMin();
		m_freeRes = r;
		m_freeW = int(map.getSizeX());
		m_freeH = int(map.getSizeY());
		m_observed.resize(std::size_t(m_freeW) * std::size_t(m_freeH));
		for (int y = 0; y < m_freeH; ++y)
			for (int x = 0; x < m_freeW; ++x)
			{
				const float p = map.getCell(x, y);
				m_observed[std::size_t(y) * std::size_t(m_freeW) + std::size_t(x)] =
					p > 0.55f ? Observed::Free : p < 0.45f ? Observed::Occupied : Observed::Unknown;
			}
	}
}

std::pair<std::size_t, std::size_t> GlobalLocalizer::inFreeSpace(const std::vector<mrpt::math::TPoint2Df>& points,
																   const TPose2D& pose) const
{
	std::size_t inFree = 0, known = 0;
	const double c = std::cos(pose.phi), s = std::sin(pose.phi);
	for (const auto& p : points)
	{
		const double wx = pose.x + c * p.x - s * p.y, wy = pose.y + s * p.x + c * p.y;
		const int cx = int(std::floor((wx - m_freeX0) / m_freeRes)), cy = int(std::floor((wy - m_freeY0) / m_freeRes));
		if (cx < 0 || cy < 0 || cx >= m_freeW || cy >= m_freeH) continue;
		const Observed o = m_observed[std::size_t(cy) * std::size_t(m_freeW) + std::size_t(cx)];
		if (o == Observed::Unknown) continue;
		++known;
		const double dx = wx - m_shift.x, dy = wy - m_shift.y;	// the distance layer's frame
		const float clearance = m_distance.cellDistance(m_distance.worldToCell(dx), m_distance.worldToCell(dy));
		if (o == Observed::Free && clearance > kFreeSpaceMargin) ++inFree;
	}
	return {inFree, known};
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
		// At the start, or every place has been dropped.
		if (m_rivals.empty() && searchDue(odometry))
		{
			searchAnew(points);
			m_searchedOdometry = odometry;
		}
		if (m_opts.searchAlong) remember(points, odometry);
		if (m_rivals.decide() && (!m_opts.searchAlong || historyInFreeSpace(m_rivals.leader().pose, odometry) <=
															  m_opts.alongMaxInFreeSpace))
			m_state = State::Found;
	}
	if (m_state != State::Searching) return m_state;
	if (m_opts.searchAlong)
	{
		if (views() >= m_opts.maxViews) m_rivals.clear();  // let go; searched again further on
	}
	else if (views() >= m_opts.maxViews || (m_rivals.empty() && m_searches >= m_opts.maxSearches))
		m_state = State::Undecided;
	return m_state;
}

void GlobalLocalizer::remember(const std::vector<mrpt::math::TPoint2Df>& points, const std::optional<TPose2D>& odometry)
{
	if (!odometry) return;
	std::vector<mrpt::math::TPoint2Df> some;
	for (std::size_t k = 0; k < points.size(); k += kHistoryPointStride) some.push_back(points[k]);
	m_history.emplace_back(*odometry, std::move(some));
	if (m_history.size() > kHistoryScans) m_history.pop_front();
}

double GlobalLocalizer::historyInFreeSpace(const TPose2D& pose, const std::optional<TPose2D>& odometry) const
{
	// Each remembered scan placed as the odometry has it relative to the place's pose now; of all their
	// returns that land where the map observed something, the share in its free space (returns off
	// the map say nothing: the robot may have come from ground the map does not hold).
	if (!odometry) return 0;
	std::size_t inFree = 0, known = 0;
	for (const auto& [at, points] : m_history)
	{
		const auto [f, k] = inFreeSpace(points, compose(pose, between(at, *odometry)));
		inFree += f;
		known += k;
	}
	return known ? double(inFree) / double(known) : 0.0;
}

bool GlobalLocalizer::searchDue(const std::optional<TPose2D>& odometry) const
{
	if (!m_opts.searchAlong || m_searches == 0 || !odometry || !m_searchedOdometry) return true;
	const TPose2D d = between(*odometry, *m_searchedOdometry);
	return std::hypot(d.x, d.y) >= m_opts.searchEveryLinear || std::abs(d.phi) >= m_opts.searchEveryAngular;
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
