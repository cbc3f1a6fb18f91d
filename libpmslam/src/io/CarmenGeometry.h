/* pmslam — the beam geometry of Carmen laser lines, shared by the two readers (not installed).
 *
 * Carmen FLASER/RLASER lines write no field of view: beam i of a line with n
 * readings lies at −90° + i·step in the laser frame (see CarmenLogReader.h for
 * the whole convention). CarmenLogReader applies it to Carmen lines and
 * RawlogReader re-applies it to scans converted by MRPT's Carmen importer;
 * both include this header, so neither reader includes the other.
 */
#pragma once

#include <cstddef>

namespace pmslam::carmen
{
/** Angular step (rad) between consecutive FLASER/RLASER beams for a line
 * with n readings (n >= 2): π/n for even n, π/(n−1) for odd n. */
double flaserBeamStep(std::size_t n);

}  // namespace pmslam::carmen
