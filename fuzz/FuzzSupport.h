// Fuzz support: the readers take a path, so each input is put in an anonymous
// in-memory file (memfd) and handed over as /proc/self/fd/N — no disk traffic,
// no temporary files left behind by a crash.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <pmslam/io/LogReader.h>
#include <pmslam/sensor/ScanPoints.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pmslam::fuzz
{
/** Replaces the content of the process's one in-memory file; returns its path. */
inline std::string memoryFile(const std::uint8_t* data, std::size_t size)
{
	static const int fd = ::memfd_create("pmslam-fuzz", MFD_CLOEXEC);
	if (fd < 0 || ::ftruncate(fd, 0) != 0)
	{
		std::perror("pmslam fuzz: memfd");
		std::abort();
	}
	std::size_t done = 0;
	while (done < size)
	{
		const ssize_t n = ::pwrite(fd, data + done, size - done, static_cast<off_t>(done));
		if (n <= 0)
		{
			std::perror("pmslam fuzz: pwrite");
			std::abort();
		}
		done += static_cast<std::size_t>(n);
	}
	return "/proc/self/fd/" + std::to_string(fd);
}

/** A broken invariant: report it and crash so libFuzzer keeps the input. */
[[noreturn]] inline void fail(const char* what)
{
	std::fprintf(stderr, "pmslam fuzz: invariant broken: %s\n", what);
	std::abort();
}
/** What every event a reader delivers must satisfy, whatever the input: the
 * SLAM loop takes these values as they are. */
inline void checkEvent(const LogEvent& ev)
{
	if (!std::isfinite(ev.timestamp)) fail("non-finite timestamp");
	if (ev.kind == LogEvent::Kind::Odometry)
	{
		if (!std::isfinite(ev.odometry.x) || !std::isfinite(ev.odometry.y) || !std::isfinite(ev.odometry.phi))
			fail("non-finite odometry");
		return;
	}
	if (!ev.scan) fail("scan event without a scan");
	const auto& s = *ev.scan;
	if (s.getScanSize() < 2) fail("scan with fewer than 2 beams");
	if (!std::isfinite(s.aperture)) fail("non-finite aperture");
	const auto& p = s.sensorPose;
	if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()) || !std::isfinite(p.yaw()) ||
		!std::isfinite(p.pitch()) || !std::isfinite(p.roll()))
		fail("non-finite sensor pose");
	if (ev.scanHasOdometry &&
		(!std::isfinite(ev.scanOdometry.x) || !std::isfinite(ev.scanOdometry.y) || !std::isfinite(ev.scanOdometry.phi)))
		fail("non-finite scan odometry");
	// What the map builder does first with every scan.
	ScanPointsOptions o;
	o.noReturnCarveRange = 5.0;
	const ScanPoints pts = scanToPoints(s, o);
	for (const auto& q : pts.hits)
		if (!std::isfinite(q.x) || !std::isfinite(q.y)) fail("non-finite scan point");
	for (const auto& q : pts.freeEnds)
		if (!std::isfinite(q.x) || !std::isfinite(q.y)) fail("non-finite free-space end");
}
}  // namespace pmslam::fuzz
