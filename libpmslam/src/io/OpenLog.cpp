/* pmslam — LogReader::open(): the log-reader factory and its format detection (see LogReader.h).
 * Its own unit because it creates the readers, which derive from LogReader: LogReader.cpp stays free
 * of them, so the base and its readers do not include each other. */
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/CarmenLogReader.h>
#include <pmslam/io/LogReader.h>
#include <pmslam/util/ExceptionText.h>
#include <pmslam/io/RawlogReader.h>
#include <pmslam/io/SimpleMapLogReader.h>
#include <pmslam/util/TextCase.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <system_error>

#include "CompressedInput.h"
#include "RawlogProbe.h"

namespace pmslam
{
namespace
{
const char* const kExpected = "expected a Carmen log (.clf/.log/.txt) or an MRPT .rawlog";

/** Extension of the file, lower case, ignoring a trailing ".gz" or ".bz2". */
std::string logExtension(const std::string& path)
{
	std::filesystem::path p(path);
	std::string ext = lowerCase(p.extension().string());
	if (ext == ".gz" || ext == ".bz2") ext = lowerCase(p.stem().extension().string());
	return ext;
}

/** Up to maxBytes of the decompressed start of the file (plain, gzip or bzip2); `damage` says why it
 * ends early if the file is damaged there. */
std::string readHead(const std::string& path, std::size_t maxBytes, std::string& damage)
{
	std::string head(maxBytes, '\0');
	std::size_t got = 0;
	try
	{
		detail::CompressedInput in;
		if (in.open(path))
			while (got < maxBytes)
			{
				const std::size_t r = in.read(&head[got], maxBytes - got);
				if (r == 0) break;
				got += r;
			}
	}
	catch (const std::exception& e)
	{
		damage = exceptionSummary(e.what());
	}
	head.resize(got);
	return head;
}

bool isCarmenKeyword(const std::string& w)
{
	static const char* const kw[] = {"PARAM",	   "SYNC",		  "ODOM",		 "FLASER",	   "RLASER",
									 "LASER1",	   "LASER2",	  "LASER3",		 "LASER4",	   "RAWLASER1",
									 "RAWLASER2",  "RAWLASER3",	  "RAWLASER4",	 "ROBOTLASER1", "ROBOTLASER2",
									 "TRUEPOS",	   "NMEAGGA",	  "NMEARMC",	 "SONAR",	   "BUMPER",
									 "SCANMARK",   "POSITIONLASER", "IMU",		 "VECTORMOVE", "ROBOTVELOCITY"};
	for (const char* k : kw)
		if (w == k) return true;
	return false;
}

/** First word of the first non-empty, non-comment line (of a complete line, or
 * of the head if it has no newline at all). */
std::string firstKeyword(const std::string& head)
{
	std::size_t pos = 0;
	while (pos < head.size())
	{
		std::size_t nl = head.find('\n', pos);
		if (nl == std::string::npos) nl = head.size();
		const std::size_t b = head.find_first_not_of(" \t\r", pos);
		if (b != std::string::npos && b < nl && head[b] != '#')
		{
			std::size_t e = b;
			while (e < nl && !std::isspace(static_cast<unsigned char>(head[e]))) ++e;
			return head.substr(b, e - b);
		}
		pos = nl + 1;
	}
	return {};
}

bool looksLikeText(const std::string& head)
{
	if (head.empty()) return false;
	std::size_t odd = 0;
	for (unsigned char c : head)
	{
		if (c == 0) return false;
		if (c < 32 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v') ++odd;
	}
	return odd * 100 <= head.size();  // tolerate a few control characters
}

/** True if the file starts with an MRPT-serialized rawlog object; else the reason. */
bool startsWithRawlogObject(const std::string& path, double objectTimeout, std::string& reason, bool& exceptionText)
{
	// MRPT may crash or hang on a damaged first object: read it here only if a child could.
	RawlogProbe probe(path, objectTimeout);
	if (!probe.safeToRead(1))
	{
		reason = probe.failure().empty() ? "no object" : probe.failure();
		exceptionText = probe.failedWithException();
		return false;
	}
	try
	{
		mrpt::io::CFileGZInputStream in;
		if (!in.open(path))
		{
			reason = "cannot be opened";
			return false;
		}
		auto arch = mrpt::serialization::archiveFrom(in);
		const auto obj = arch.ReadObject();
		if (obj && (std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj) ||
					std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj) ||
					std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)))
			return true;
		reason = std::string("first object is a ") + (obj ? obj->GetRuntimeClass()->className : "null object");
		return false;
	}
	catch (const std::exception& e)
	{
		reason = e.what();
		exceptionText = true;
		return false;
	}
}

}  // namespace

std::unique_ptr<LogReader> LogReader::open(const std::string& path, const LogReaderOptions& opts)
{
	namespace fs = std::filesystem;
	if (opts.follow)
	{
		const std::string ext = logExtension(path);
		if (ext == ".clf" || ext == ".log" || ext == ".txt")
			throw LogError("pmslam: '" + path + "' is named as a Carmen log: --follow reads MRPT rawlogs (as rawlog-grabber "
						   "writes them)");
		if (lowerCase(std::filesystem::path(path).extension().string()) == ".bz2")
			throw LogError("pmslam: '" + path + "' is named as a bzip2 file: --follow reads MRPT rawlogs (as rawlog-grabber "
						   "writes them: plain or gz)");
	}
	const std::string expected = opts.follow ? "expected an MRPT .rawlog to follow" : kExpected;
	// A simple map (or an output folder holding one) replays its keyframes (merging sessions).
	if (!opts.follow && SimpleMapLogReader::accepts(path)) return std::make_unique<SimpleMapLogReader>(path);
	std::error_code ec;
	const auto st = fs::status(path, ec);
	if (!path.empty() && ec && st.type() == fs::file_type::none)  // e.g. a folder on the way is not searchable
		throw LogError("pmslam: cannot access log file '" + path + "' (" + ec.message() + "), " + expected);
	if (path.empty() || !fs::exists(st)) throw LogError("pmslam: log file '" + path + "' does not exist (" + expected + ")");
	if (fs::is_directory(st)) throw LogError("pmslam: '" + path + "' is a directory, " + expected);
	if (!fs::is_regular_file(st)) throw LogError("pmslam: '" + path + "' is not a regular file, " + expected);
	// Still being written: it may be empty yet, and only a rawlog can be followed (RawlogReader.h).
	if (opts.follow) return std::make_unique<RawlogReader>(path, opts);
	const auto size = fs::file_size(path, ec);
	if (ec) throw LogError("pmslam: cannot read log file '" + path + "' (" + ec.message() + "), " + kExpected);
	if (size == 0) throw LogError("pmslam: log file '" + path + "' is empty, " + kExpected);
	{
		errno = 0;
		std::ifstream probe(path, std::ios::binary);
		char c;
		if (!probe || !probe.get(c))
		{
			const int err = errno;
			throw LogError("pmslam: cannot read log file '" + path + "'" +
						   (err != 0 ? " (" + std::string(std::strerror(err)) + ")" : std::string()) + ", " + kExpected);
		}
	}

	std::string damage;
	const std::string head = readHead(path, 1 << 16, damage);
	if (head.empty())
		throw LogError("pmslam: log file '" + path + "' has no content" + (damage.empty() ? "" : " (" + damage + ")") +
					   ", " + kExpected);
	const bool text = looksLikeText(head);
	const std::string ext = logExtension(path);
	// MRPT reads rawlogs plain or gz only, and the rawlog reader reads them through MRPT (RawlogReader.h).
	if (detail::compressionOf(path) == detail::Compression::Bzip2 && (!text || ext == ".rawlog"))
		throw LogError("pmslam: '" + path + "' is bzip2-compressed but not a Carmen log: expected a Carmen log, or an " +
					   "MRPT .rawlog plain or gz-compressed (MRPT reads no bzip2: bunzip2 the rawlog, or recompress it with gzip)");

	// 1. Content: a Carmen keyword opening the first non-comment line.
	if (text && isCarmenKeyword(firstKeyword(head))) return std::make_unique<CarmenLogReader>(path, opts);
	// 2. Content: an MRPT-serialized object (rawlog of either format, plain or gz).
	std::string why;
	if (!text || ext == ".rawlog")
	{
		bool exceptionText = false;
		if (startsWithRawlogObject(path, opts.rawlogObjectTimeout, why, exceptionText)) return std::make_unique<RawlogReader>(path, opts);
		if (exceptionText) why = "first object unreadable: " + exceptionSummary(why);
		if (ext == ".rawlog") throw LogError("pmslam: '" + path + "' is not a readable MRPT rawlog (" + why + ")");
	}
	// 3. Extension: a text file named like a Carmen log.
	if (text && (ext == ".clf" || ext == ".log" || ext == ".txt")) return std::make_unique<CarmenLogReader>(path, opts);
	throw LogError("pmslam: unknown log format for '" + path + "': " + kExpected +
				   " (Carmen: first non-comment line starting with FLASER/ODOM/PARAM/...)");
}

}  // namespace pmslam
