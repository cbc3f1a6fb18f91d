/* pmslam — a plain, gzip or bzip2 file read as its decompressed bytes (see CompressedInput.h). */
#include "CompressedInput.h"

#include <bzlib.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

namespace pmslam::detail
{
struct CompressedInput::Source
{
	virtual ~Source() = default;
	virtual std::size_t read(char* buffer, std::size_t count) = 0;
};

namespace
{
/** zlib and libbz2 take the output room as an unsigned int. */
constexpr std::size_t kMaxStep = std::size_t(1) << 30;

/** Plain or gzip: zlib passes a file that is not gzip through unchanged. */
class GzipSource : public CompressedInput::Source
{
   public:
	GzipSource(gzFile file, std::string path) : m_file(file), m_path(std::move(path)) {}
	~GzipSource() override { gzclose(m_file); }

	std::size_t read(char* buffer, std::size_t count) override
	{
		const int got = gzread(m_file, buffer, static_cast<unsigned>(std::min(count, kMaxStep)));
		if (got > 0) return static_cast<std::size_t>(got);
		int err = Z_OK;
		const std::string message = gzerror(m_file, &err);
		if (got == 0 && (err == Z_OK || err == Z_STREAM_END)) return 0;
		if (err == Z_BUF_ERROR) throw std::runtime_error("gzip: data ends early (truncated file)");
		throw std::runtime_error("gzip: " + withoutPath(message));
	}

   private:
	/** zlib's messages start with "PATH: "; the reader's warning names the file already. */
	std::string withoutPath(const std::string& message) const
	{
		const std::string prefix = m_path + ": ";
		return message.compare(0, prefix.size(), prefix) == 0 ? message.substr(prefix.size()) : message;
	}

	gzFile m_file;
	std::string m_path;
};

/** bzip2 through libbz2's stream interface, which (unlike BZ2_bzRead) goes on into a next stream. */
class Bzip2Source : public CompressedInput::Source
{
   public:
	explicit Bzip2Source(std::FILE* file) : m_file(file), m_in(std::size_t(1) << 16) { startStream(); }
	~Bzip2Source() override
	{
		if (m_streamOpen) BZ2_bzDecompressEnd(&m_bz);
		std::fclose(m_file);
	}

	std::size_t read(char* buffer, std::size_t count) override
	{
		std::size_t got = 0;
		while (got < count && !m_end && m_damage.empty()) got += decompress(buffer + got, count - got);
		// The bytes before the damage first; the damage on the call that has nothing else to return.
		if (got == 0 && !m_damage.empty()) throw std::runtime_error(m_damage);
		return got;
	}

   private:
	/** One decompression step into `out`; the bytes it produced. Sets m_end or m_damage when it meets them. */
	std::size_t decompress(char* out, std::size_t room)
	{
		if (m_bz.avail_in == 0) refill();
		room = std::min(room, kMaxStep);
		m_bz.next_out = out;
		m_bz.avail_out = static_cast<unsigned>(room);
		const int rc = BZ2_bzDecompress(&m_bz);
		const std::size_t produced = room - m_bz.avail_out;
		if (rc == BZ_STREAM_END)
			nextStream();
		else if (rc == BZ_DATA_ERROR_MAGIC && m_streams > 1)
			m_end = true;  // bytes after the last stream that are not one: ignored, as bzip2 does
		else if (rc != BZ_OK)
			m_damage = describe(rc);
		else if (produced == 0 && m_bz.avail_in == 0 && m_inputEnded && m_damage.empty())
			m_damage = "bzip2: data ends early (truncated file)";
		return produced;
	}

	void refill()
	{
		if (m_inputEnded) return;
		errno = 0;
		const std::size_t n = std::fread(m_in.data(), 1, m_in.size(), m_file);
		if (n == 0)
		{
			m_inputEnded = true;
			if (std::ferror(m_file))
				m_damage = std::string("bzip2: cannot read the file (") + std::strerror(errno ? errno : EIO) + ")";
		}
		m_bz.next_in = m_in.data();
		m_bz.avail_in = static_cast<unsigned>(n);
	}

	void startStream()
	{
		char* const nextIn = m_bz.next_in;
		const unsigned availIn = m_bz.avail_in;
		m_bz.bzalloc = nullptr;
		m_bz.bzfree = nullptr;
		m_bz.opaque = nullptr;
		const int rc = BZ2_bzDecompressInit(&m_bz, 0, 0);
		m_bz.next_in = nextIn;
		m_bz.avail_in = availIn;
		if (rc != BZ_OK)
		{
			m_damage = describe(rc);
			return;
		}
		m_streamOpen = true;
		++m_streams;
	}

	/** After a stream's end: the next one if more bytes follow (pbzip2, or files concatenated). */
	void nextStream()
	{
		BZ2_bzDecompressEnd(&m_bz);
		m_streamOpen = false;
		if (m_bz.avail_in == 0) refill();
		if (m_bz.avail_in == 0)
			m_end = true;
		else
			startStream();
	}

	static std::string describe(int rc)
	{
		switch (rc)
		{
			case BZ_DATA_ERROR: return "bzip2: damaged data (a block fails its check)";
			case BZ_DATA_ERROR_MAGIC: return "bzip2: not bzip2 data";
			case BZ_MEM_ERROR: return "bzip2: out of memory";
			default: return "bzip2: error " + std::to_string(rc);
		}
	}

	std::FILE* m_file;
	std::vector<char> m_in;
	bz_stream m_bz{};
	bool m_streamOpen = false, m_inputEnded = false, m_end = false;
	int m_streams = 0;
	std::string m_damage;
};

}  // namespace

Compression compressionOf(const std::string& path)
{
	std::ifstream in(path, std::ios::binary);
	unsigned char b[10] = {};
	in.read(reinterpret_cast<char*>(b), sizeof(b));
	const std::size_t n = static_cast<std::size_t>(in.gcount());
	if (n >= 2 && b[0] == 0x1f && b[1] == 0x8b) return Compression::Gzip;
	// "BZh", the block size '1'..'9', then the magic of a first block (π) or of the end of an empty stream (√π).
	static const unsigned char block[6] = {0x31, 0x41, 0x59, 0x26, 0x53, 0x59};
	static const unsigned char end[6] = {0x17, 0x72, 0x45, 0x38, 0x50, 0x90};
	if (n == 10 && b[0] == 'B' && b[1] == 'Z' && b[2] == 'h' && b[3] >= '1' && b[3] <= '9' &&
		(std::memcmp(b + 4, block, 6) == 0 || std::memcmp(b + 4, end, 6) == 0))
		return Compression::Bzip2;
	return Compression::None;
}

CompressedInput::CompressedInput() = default;
CompressedInput::~CompressedInput() = default;

bool CompressedInput::open(const std::string& path)
{
	m_source.reset();
	if (compressionOf(path) == Compression::Bzip2)
	{
		std::FILE* f = std::fopen(path.c_str(), "rb");
		if (!f) return false;
		m_source = std::make_unique<Bzip2Source>(f);
		return true;
	}
	gzFile g = gzopen(path.c_str(), "rb");
	if (!g) return false;
	m_source = std::make_unique<GzipSource>(g, path);
	return true;
}

std::size_t CompressedInput::read(char* buffer, std::size_t count)
{
	if (!m_source) throw std::runtime_error("no file open");
	return m_source->read(buffer, count);
}

}  // namespace pmslam::detail
