/* pmslam — the frames the front-end worked in (see FrameHistory.h). */
#include <pmslam/slam/FrameHistory.h>

namespace pmslam
{
void FrameHistory::correct(const mrpt::poses::CPose2D& correction)
{
	m_frame = correction + m_frame;
	m_frames.push_back(m_frame);
}

mrpt::math::TPose2D FrameHistory::toFirst(const mrpt::math::TPose2D& pose) const
{
	return (-m_frame + mrpt::poses::CPose2D(pose)).asTPose();
}

mrpt::math::TPose2D FrameHistory::toScanFrame(std::size_t scan, const mrpt::math::TPose2D& pose) const
{
	if (scan >= m_scanFrame.size()) return pose;
	return (m_frames[m_scanFrame[scan]] + mrpt::poses::CPose2D(pose)).asTPose();
}

void FrameHistory::addKeyframe(const mrpt::math::TPose2D& pose)
{
	m_nodeInFirstFrame.push_back(toFirst(pose));
	for (const std::size_t s : m_pendingAnchors)
		if (s < m_scanAnchor.size()) m_scanAnchor[s] = static_cast<uint32_t>(m_nodeInFirstFrame.size() - 1);
	m_pendingAnchors.clear();
}

void FrameHistory::addScan(std::size_t keyframes)
{
	m_scanFrame.push_back(static_cast<uint32_t>(m_frames.size() - 1));
	m_scanAnchor.push_back(keyframes ? static_cast<uint32_t>(keyframes - 1) : UINT32_MAX);
}

std::vector<mrpt::math::TPose2D> FrameHistory::corrected(const std::vector<mrpt::math::TPose2D>& online,
														 const LoopClosure& loops) const
{
	std::vector<mrpt::math::TPose2D> out = online;
	for (std::size_t i = 0; i < out.size() && i < m_scanAnchor.size(); ++i)
	{
		const uint32_t n = m_scanAnchor[i];
		if (n == UINT32_MAX || n >= m_nodeInFirstFrame.size()) continue;
		// In the first frame the scan sits at a fixed offset from its keyframe; the keyframe
		// goes where the graph has it, and the scan with it.
		const mrpt::poses::CPose2D inFirst = -m_frames[m_scanFrame[i]] + mrpt::poses::CPose2D(online[i]);
		const mrpt::poses::CPose2D offset = inFirst - mrpt::poses::CPose2D(m_nodeInFirstFrame[n]);
		out[i] = (mrpt::poses::CPose2D(loops.nodePose(n)) + offset).asTPose();
	}
	return out;
}

}  // namespace pmslam
