/* pmslam — MRPT rawlog reader (see RawlogReader.h). */
#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <pmslam/util/ExceptionText.h>
#include <pmslam/sensor/ScanSlice.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <pmslam/io/ObservationEvents.h>
#include <pmslam/io/RawlogReader.h>

#include "CarmenGeometry.h"
#include "GrowingFileStream.h"
#include "RawlogProbe.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

namespace pmslam
{
namespace
{
/** Uncompressed size of the file: its size, or the gzip ISIZE trailer. */
std::uint64_t contentSize(const std::string& path)
{
	std::error_code ec;
	const std::uint64_t size = std::filesystem::file_size(path, ec);
	if (ec) return 0;
	std::ifstream f(path, std::ios::binary);
	unsigned char magic[2] = {0, 0};
	if (!f.read(reinterpret_cast<char*>(magic), 2) || magic[0] != 0x1f || magic[1] != 0x8b || size < 18) return size;
	unsigned char t[4];
	f.seekg(static_cast<std::streamoff>(size - 4));
	if (!f.read(reinterpret_cast<char*>(t), 4)) return size;
	const std::uint64_t isize = std::uint64_t(t[0]) | (std::uint64_t(t[1]) << 8) | (std::uint64_t(t[2]) << 16) |
								(std::uint64_t(t[3]) << 24);
	// Smaller than the file: > 4 GiB wrapped; implausibly large: not a trailer (damaged copy).
	return (isize >= size && isize <= 50 * size) ? isize : size;
}

}  // namespace

struct RawlogReader::Impl
{
	LogReaderOptions opts;
	std::unique_ptr<RawlogProbe> probe;  // runs ahead: only objects it got through are read here (not when following)
	std::unique_ptr<mrpt::io::CStream> in;
	std::unique_ptr<mrpt::serialization::CArchive> arch;
	std::unique_ptr<ObservationEvents> events;
	std::deque<LogEvent> queue;
	std::size_t objects = 0;
	bool done = false;

	mutable bool estimated = false;
	mutable std::size_t estimate = 0;

	bool safeToRead(std::size_t object) const { return !probe || probe->safeToRead(object); }
};

RawlogReader::RawlogReader(const std::string& path, const LogReaderOptions& opts)
	: LogReader(path), m_impl(std::make_unique<Impl>())
{
	Impl& d = *m_impl;
	d.opts = opts;
	if (opts.follow)
	{
		try
		{
			d.in = std::make_unique<GrowingFileStream>(path, opts.followTimeout, opts.stopRequested);
		}
		catch (const std::exception&)
		{
			throw LogError("pmslam: cannot open rawlog '" + path + "' for reading");
		}
	}
	else
	{
		auto in = std::make_unique<mrpt::io::CFileGZInputStream>();
		bool ok = false;
		try
		{
			ok = in->open(path);
		}
		catch (const std::exception&)
		{
		}
		if (!ok) throw LogError("pmslam: cannot open rawlog '" + path + "' for reading");
		d.in = std::move(in);
		d.probe = std::make_unique<RawlogProbe>(path, opts.rawlogObjectTimeout);
	}
	d.arch = mrpt::serialization::archiveUniquePtrFrom(*d.in);
	d.events = std::make_unique<ObservationEvents>(
		opts, path, [this](const std::string& w) { warn(w); }, m_stats);
}

RawlogReader::~RawlogReader() = default;

std::size_t RawlogReader::estimatedScanCount() const
{
	Impl& d = *m_impl;
	if (d.estimated) return d.estimate;
	d.estimated = true;
	if (d.opts.follow) return 0;  // still being written: unknown
	try
	{
		mrpt::io::CFileGZInputStream in;
		if (!in.open(m_path)) return 0;
		auto arch = mrpt::serialization::archiveFrom(in);
		std::size_t scans = 0;
		bool atEnd = false;
		for (std::size_t k = 0; k < 400 && in.getPosition() < (8u << 20); ++k)
		{
			if (!d.safeToRead(k + 1))
			{
				atEnd = true;
				break;
			}
			mrpt::serialization::CSerializable::Ptr obj;
			try
			{
				obj = arch.ReadObject();
			}
			catch (const std::exception&)
			{
				atEnd = true;
				break;
			}
			if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obj))
				++scans;
			else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
			{
				for (const auto& o : *sf)
					if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o) || (o && isSliceable(*o))) ++scans;
			}
			else if (auto ob = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj); ob && isSliceable(*ob))
				++scans;
		}
		const std::uint64_t consumed = in.getPosition();
		if (atEnd || consumed == 0)
			d.estimate = scans;
		else
		{
			const double total = static_cast<double>(std::max<std::uint64_t>(contentSize(m_path), consumed));
			d.estimate = static_cast<std::size_t>(std::llround(scans * total / static_cast<double>(consumed)));
		}
	}
	catch (const std::exception&)
	{
	}
	return d.estimate;
}

bool RawlogReader::next(LogEvent& ev)
{
	Impl& d = *m_impl;
	while (d.queue.empty())
	{
		if (d.done) return false;

		// Stops reading for good, with the damage warning unless the file just ended (reason empty).
		auto stop = [&](const std::string& reason) {
			d.events->finish(d.queue);
			d.done = true;
			if (!reason.empty())
				warn(m_path + ": damaged after object " + std::to_string(d.objects) + " (" + reason + "), stopping");
		};
		if (!d.safeToRead(d.objects + 1))
		{
			// MRPT would crash, hang, throw or exhaust memory on the next object: stop before it.
			const std::string& why = d.probe->failure();
			stop(d.probe->failedWithException() ? exceptionSummary(why) : why);
			continue;
		}
		const std::uint64_t pos0 = d.in->getPosition();
		mrpt::serialization::CSerializable::Ptr obj;
		std::string failure;
		try
		{
			obj = d.arch->ReadObject();
		}
		catch (const std::exception& e)
		{
			failure = exceptionSummary(e.what());
		}
		catch (...)
		{
			failure = "unknown exception";
		}
		if (!failure.empty())
		{
			std::uint64_t pos1 = pos0;
			try
			{
				pos1 = d.in->getPosition();
			}
			catch (const std::exception&)
			{
			}
			if (d.opts.follow && d.opts.stopRequested && d.opts.stopRequested())
				stop(std::string());  // interrupted while waiting for the writer: not damage
			else if (d.opts.follow && pos1 != pos0 && static_cast<GrowingFileStream&>(*d.in).idle())
			{
				stop(std::string());
				warn(m_path + ": stopped growing inside object " + std::to_string(d.objects + 1) + " (no new byte for " +
					 std::to_string(int(d.opts.followTimeout)) + " s), stopping after object " + std::to_string(d.objects));
			}
			else
				stop(pos1 != pos0 ? failure : std::string());  // no byte of a next object: a clean end
			continue;
		}

		++d.objects;
		m_stats.linesOrObjects = d.objects;
		if (!obj) continue;

		d.events->add(obj, d.objects, d.queue);
	}
	return deliver(d.queue, ev);
}

}  // namespace pmslam
