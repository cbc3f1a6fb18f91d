/* pmslam — the frames the front-end worked in, across loop-closure corrections.
 *
 * Each new map from the loop-closure back-end comes with a rigid correction that
 * moves every pose the front-end holds: the front-end's frame is the product of the
 * corrections so far. The reported trajectory's smoother works in the first frame,
 * where poses are continuous across corrections; the final trajectory moves each
 * scan with the keyframe it was tracked from. So this part records, per scan, the
 * frame it was tracked in and its latest keyframe, and per keyframe its pose in the
 * first frame.
 */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
#include <pmslam/graph/LoopClosure.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pmslam
{
class FrameHistory
{
   public:
	/** The map moved by `correction`: the front-end's frame with it. */
	void correct(const mrpt::poses::CPose2D& correction);
	/** `pose` (the current frame) in the first frame. */
	mrpt::math::TPose2D toFirst(const mrpt::math::TPose2D& pose) const;
	/** `pose` of scan `scan` (the first frame) in the frame the scan was tracked in. */
	mrpt::math::TPose2D toScanFrame(std::size_t scan, const mrpt::math::TPose2D& pose) const;

	/** A keyframe at `pose` (current frame) was handed to the back-end. */
	void addKeyframe(const mrpt::math::TPose2D& pose);
	/** The next scan was tracked in the current frame; `keyframes` handed to the back-end so far. */
	void addScan(std::size_t keyframes);
	/** Scan `scan` moves with the next keyframe instead of its latest: a scan placed afterwards by
	 * what that keyframe's scan measured (a lost stretch revised, D57). */
	void anchorToNextKeyframe(std::size_t scan) { m_pendingAnchors.push_back(scan); }

	/** `online` (each scan's pose as reported, scan order) with each scan moved with its keyframe
	 * to where `loops`' graph has it. */
	std::vector<mrpt::math::TPose2D> corrected(const std::vector<mrpt::math::TPose2D>& online,
											   const LoopClosure& loops) const;

   private:
	mrpt::poses::CPose2D m_frame;  // the product of the corrections so far
	std::vector<mrpt::poses::CPose2D> m_frames{mrpt::poses::CPose2D()};	 // every m_frame so far, first = identity
	std::vector<uint32_t> m_scanFrame, m_scanAnchor;  // per scan: index into m_frames, latest keyframe
	std::vector<mrpt::math::TPose2D> m_nodeInFirstFrame;  // per keyframe
	std::vector<std::size_t> m_pendingAnchors;	// scans to anchor to the next keyframe
};

}  // namespace pmslam
