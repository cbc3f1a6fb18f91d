/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * CarmenLogReader: reads a Carmen text log (plain, gz- or bzip2-compressed:
 * TextLineReader.h) line by line and turns FLASER, RLASER, ROBOTLASER1 and ODOM lines into LogEvent.
 * PARAM, SYNC, comments (#) and unknown keywords are ignored silently.
 *
 * Line layouts (whitespace separated):
 *   FLASER|RLASER n r1..rn  lx ly lth  ox oy oth  ipc_timestamp host logger_timestamp
 *   ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode
 *               n r1..rn  m e1..em  lx ly lth  ox oy oth  tv rv fwd side turn
 *               ipc_timestamp host logger_timestamp
 *   ODOM x y theta tv rv accel ipc_timestamp host logger_timestamp
 * (lx ly lth) is the laser pose and (ox oy oth) the robot odometry, both in
 * the odometry frame; the laser's mounting pose on the robot is their
 * difference expressed in the robot frame, (o)^-1 ⊕ (l).
 *
 * Parsing: the laser lines go through MRPT's importer
 * (mrpt::obs::carmen_log_parse_line) for ranges, sensor offset and odometry;
 * ODOM lines are parsed here (MRPT's importer ignores them). Every line is
 * first validated from its own text; what MRPT 2.5.8 gets wrong is then
 * corrected: the timestamp (MRPT does not keep the ipc_timestamp), the fan
 * geometry (MRPT uses aperture = n × 0.5°, 90° for a 180-beam scan; it also
 * ignores ROBOTLASER1's start_angle) and the no-return threshold.
 *
 * Beam geometry. Carmen FLASER/RLASER write no field of view: beam i lies at
 * −90° + i·step in the laser frame, with step = 180°/n for even n (180 → 1°,
 * 360 → 0.5°, last beam one step short of +90°) and 180°/(n−1) for odd n
 * (181 → 1°, 361 → 0.5°, both ends included). MRPT places beam i at
 * −aperture/2 + i·aperture/(N−1) (rightToLeft = true) around the sensor's
 * x axis, a fan symmetric about that axis. The reader therefore sets
 * aperture = (n−1)·step and rotates sensorPose by the fan's centre,
 * −90° + aperture/2 (−0.5° for n = 180, −0.25° for n = 360, 0 for n = 361),
 * so yaw(sensorPose) + getScanAngle(i) is exactly laser yaw − 90° + i·step.
 * ROBOTLASER1 likewise: beam i at start_angle + i·resolution, aperture =
 * (n−1)·resolution, sensor yaw += start_angle + aperture/2.
 * RLASER is the rear laser: its sensor yaw is the yaw difference of the two
 * pose triples, plus π when the log wrote the same heading for both.
 *
 * No return: readings >= LogReaderOptions::noReturnRange (ROBOTLASER1: or
 * >= the line's max_range, whichever is smaller; that value becomes
 * scan->maxRange) and readings of 0 are invalid, their raw range is kept.
 *
 * Damaged lines (wrong field count, beam count that disagrees with the line,
 * non-numeric or non-finite fields, negative ranges, MRPT importer errors,
 * scans without a valid beam, timestamps going back more than
 * kBackwardsToleranceSec behind the latest accepted one) are skipped with a
 * warning "file:line: reason, skipped" and counted in stats().skipped.
 * Small backward steps are normal in Carmen logs (intel.clf: 631 FLASER lines
 * step back by up to 0.9 s, interleaved ODOM/FLASER lines by up to 0.9 s) and
 * are delivered unchanged, in file order.
 * A compressed file damaged at some point (cut short, a corrupt block) is
 * read up to the damage, then reading stops with one warning
 * "file:line: read error (what), stopping".
 */
#pragma once

#include <pmslam/io/LogReader.h>

#include <cstddef>
#include <memory>
#include <string>

namespace pmslam
{
class CarmenLogReader : public LogReader
{
   public:
	/** Throws LogError if the file cannot be opened. */
	explicit CarmenLogReader(const std::string& path, const LogReaderOptions& opts = {});
	~CarmenLogReader() override;

	bool next(LogEvent& ev) override;
	/** Counts the FLASER/RLASER/ROBOTLASER1 lines (one pass over the file on
	 * the first call, cached). */
	std::size_t estimatedScanCount() const override;

	/** Angular step (rad) between consecutive FLASER/RLASER beams for a line
	 * with n readings (n >= 2): π/n for even n, π/(n−1) for odd n. Forwards to
	 * the geometry both readers share (src/io/CarmenGeometry.h). */
	static double flaserBeamStep(std::size_t n);

	/** Lines stepping back further than this behind the latest accepted
	 * timestamp are skipped. */
	static constexpr double kBackwardsToleranceSec = 2.0;

   private:
	struct Impl;
	std::unique_ptr<Impl> m_impl;
};

}  // namespace pmslam
