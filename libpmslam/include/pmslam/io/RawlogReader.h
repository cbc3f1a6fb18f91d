/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * RawlogReader: reads an MRPT .rawlog (plain or gz-compressed; both formats)
 * object by object and turns it into LogEvent:
 *  - action–observation format: each CActionCollection's best
 *    CActionRobotMovement2D increment is composed onto an accumulated
 *    odometry pose (starting at the origin), emitted as an Odometry event
 *    stamped with the action's timestamp (or, if it has none, with the first
 *    observation of the following CSensoryFrame); every
 *    CObservation2DRangeScan of a CSensoryFrame becomes a Scan event. If a
 *    frame with scans comes before any action, an Odometry event at the origin
 *    is emitted first, so every scan has an odometry pose.
 *  - observation-only format: CObservationOdometry → Odometry event (its
 *    odometry pose), CObservation2DRangeScan → Scan event.
 * Other object and observation types are ignored.
 *
 * Objects are read one at a time with CArchive::ReadObject() rather than
 * CRawlog::getActionObservationPairOrObservation(): that function returns
 * false both at the end of the file and at damage (printing the exception to
 * std::cerr), and drops a CSensoryFrame that is not preceded by an action (the
 * first frame of MRPT's own sample 2006-01ENE-21-SENA rawlog). Here the end is
 * "clean" when no byte could be read for the next object; anything else
 * (truncated object, garbage, unknown class) stops reading with exactly one
 * warning "file: damaged after object N (reason), stopping", and everything
 * before it has been delivered. (zlib ignores bytes appended after a complete
 * gzip stream, so garbage after a gz-compressed rawlog goes unnoticed.)
 *
 * MRPT's deserialisers can also crash or spin on damaged bytes (seen: a null
 * dereference and an endless odometry-sampling loop in
 * CActionRobotMovement2D::serializeFrom). So a child process reads the file
 * first, a little ahead (see src/io/RawlogProbe.h), and this reader stops, with
 * the same one warning, before the first object the child did not get through
 * ("MRPT crashed reading it (signal 11, ...)", "did not finish reading it
 * within 10 s", or the exception). The child is limited to 4 GiB more address
 * space than the process had, so a damaged length cannot exhaust memory.
 *
 * MRPT's Carmen importer defects (see CarmenLogReader.h) are inherited by
 * rawlogs made with carmen2rawlog: scans labelled FLASER/RLASER with
 * aperture = N × 0.5°. Such scans get the Carmen fan geometry and the
 * no-return threshold (LogReaderOptions::noReturnRange) re-applied, announced
 * by one warning per file. Their timestamps were synthesised by the
 * conversion and cannot be recovered.
 */
#pragma once

#include <pmslam/io/LogReader.h>

#include <cstddef>
#include <memory>
#include <string>

namespace pmslam
{
class RawlogReader : public LogReader
{
   public:
	/** Throws LogError if the file cannot be opened. */
	explicit RawlogReader(const std::string& path, const LogReaderOptions& opts = {});
	~RawlogReader() override;

	bool next(LogEvent& ev) override;
	/** Scans per byte over the first objects (read once, on the first call)
	 * times the file's (uncompressed) size; exact for small files. */
	std::size_t estimatedScanCount() const override;

   private:
	struct Impl;
	std::unique_ptr<Impl> m_impl;
};

}  // namespace pmslam
