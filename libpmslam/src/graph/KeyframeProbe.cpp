/* pmslam — a measurement tap on the loop closure's keyframes (see KeyframeProbe.h). */
#include <pmslam/graph/KeyframeProbe.h>

namespace pmslam
{
namespace
{
KeyframeProbe& probe()
{
	static KeyframeProbe p;
	return p;
}
}  // namespace

void setKeyframeProbe(KeyframeProbe p) { probe() = std::move(p); }
const KeyframeProbe& keyframeProbe() { return probe(); }

}  // namespace pmslam
