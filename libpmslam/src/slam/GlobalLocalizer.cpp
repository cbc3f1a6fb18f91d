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

bool near(const TPose2D& a, const TPose2D& b)
{
	return std::hypot(a.x - b.x, a.y - b.y) < 0.3 && std::abs(mrpt::math::wrapToPi(a.phi - b.phi)) < 5 * M_PI / 180;
}

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
}  // namespace

GlobalLocalizer::GlobalLocalizer(const mrpt::maps::COccupancyGridMap2D& map,
								 const PerfectMatchMatcher::TConfigParams& matcher, const ScanPointsOptions& scanOptions,
								 const GlobalLocalizerOptions& options)
	: m_opts(options),
	  m_scanOpts(scanOptions),
	  m_matcher(matcher),
	  m_distance(PerfectMatchMatcher::distanceMapFromGrid(map, matcher.maxDistance, matcher.occupiedThreshold))
{
	const double r = map.getResolution();
	m_shift = {map.getXMin() - std::lround(map.getXMin() / r) * r, map.getYMin() - std::lround(map.getYMin() / r) * r};
	m_pyramid = std::make_unique<LikelihoodPyramid>(
		LikelihoodPyramid::fromGrid(map, matcher.maxDistance, matcher.occupiedThreshold));
}

GlobalLocalizer::State GlobalLocalizer::addScan(const mrpt::obs::CObservation2DRangeScan& scan,
												const std::optional<TPose2D>& odometry)
{
	if (m_state != State::Searching) return m_state;
	const auto points = scanToPoints(scan, m_scanOpts).hits;
	const TPose2D motion = odometry && m_lastOdometry ? between(*odometry, *m_lastOdometry) : TPose2D(0, 0, 0);
	if (m_scans == 0) m_firstOdometry = odometry;
	if (odometry) m_lastOdometry = odometry;
	++m_scans;
	if (points.size() >= 10)
	{
		if (m_hyps.empty())
			searchAnew(points);
		else
			follow(points, motion);
		decide();
	}
	else
		for (auto& h : m_hyps) h.pose = compose(h.pose, motion);
	if (m_state == State::Searching &&
		(views() >= m_opts.maxViews || (m_hyps.empty() && m_searches >= m_opts.maxSearches)))
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
	const auto t0 = std::chrono::steady_clock::now();
	const auto result = BranchAndBoundSearch(*m_pyramid, o).searchGlobal(points);
	m_searchSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
	++m_searches;
	// Carried back to the first scan by the odometry since (no odometry: where the search found it).
	const TPose2D back =
		m_firstOdometry && m_lastOdometry ? between(*m_firstOdometry, *m_lastOdometry) : TPose2D(0, 0, 0);
	for (const auto& c : result.candidates)
	{
		PerfectMatchMatcher::MatchInfo info;
		Hypothesis h;
		h.pose = refine(points, c.pose, info);
		if (info.goodness < m_opts.minGoodness) continue;
		if (std::any_of(m_hyps.begin(), m_hyps.end(), [&](const Hypothesis& o) { return near(o.pose, h.pose); }))
			continue;  // two lattice peaks that PM took to the same pose
		h.first = compose(h.pose, back);
		h.lastView = h.pose;
		h.goodnessSum = h.lastGoodness = info.goodness;
		h.scans = 1;
		m_hyps.push_back(h);
	}
}

void GlobalLocalizer::follow(const std::vector<mrpt::math::TPoint2Df>& points, const TPose2D& motion)
{
	for (auto& h : m_hyps)
	{
		PerfectMatchMatcher::MatchInfo info;
		h.pose = refine(points, compose(h.pose, motion), info);
		h.lastGoodness = info.goodness;
	}
	// A new view for all when the leader (first: sorted by decide()) has moved since its last one.
	const TPose2D moved = between(m_hyps.front().pose, m_hyps.front().lastView);
	if (std::hypot(moved.x, moved.y) >= m_opts.viewLinear || std::abs(moved.phi) >= m_opts.viewAngular)
		for (auto& h : m_hyps)
		{
			h.goodnessSum += h.lastGoodness;
			++h.scans;
			h.lastView = h.pose;
		}
	// A hypothesis whose scans stopped fitting is not where the robot is; nor is the second of two
	// that have come together.
	std::vector<Hypothesis> kept;
	for (const auto& h : m_hyps)
		if (h.mean() >= m_opts.minGoodness && h.lastGoodness >= m_opts.minGoodness - 0.15 &&
			std::none_of(kept.begin(), kept.end(), [&](const Hypothesis& k) { return near(k.pose, h.pose); }))
			kept.push_back(h);
	m_hyps = std::move(kept);
	if (m_hyps.empty()) searchAnew(points);
}

void GlobalLocalizer::decide()
{
	std::sort(m_hyps.begin(), m_hyps.end(), [](const Hypothesis& a, const Hypothesis& b) { return a.mean() > b.mean(); });
	m_runnerUp = m_hyps.size() > 1 ? m_hyps[1].mean() : 0;
	if (m_hyps.empty()) return;
	const double views = double(m_hyps[0].scans);
	if (m_hyps.size() == 1 || m_hyps[0].mean() - m_runnerUp >= m_opts.decideMargin / std::sqrt(views))
		m_state = State::Found;
}

std::optional<GlobalLocalizer::Hypothesis> GlobalLocalizer::best() const
{
	if (m_hyps.empty()) return std::nullopt;
	return m_hyps.front();
}

}  // namespace pmslam
