/* pmslam — reading a file that is still being written (see GrowingFileStream.h). */
#include "GrowingFileStream.h"

#include <zlib.h>

#include <chrono>
#include <stdexcept>
#include <thread>

namespace pmslam
{
GrowingFileStream::GrowingFileStream(const std::string& path, double idleTimeout, std::function<bool()> stop)
	: m_path(path), m_idleTimeout(idleTimeout), m_stop(std::move(stop))
{
	m_file = gzopen(path.c_str(), "rb");
	if (!m_file) throw std::runtime_error("cannot open '" + path + "' for reading");
}

GrowingFileStream::~GrowingFileStream()
{
	if (m_file) gzclose(static_cast<gzFile>(m_file));
}

size_t GrowingFileStream::Read(void* buffer, size_t count)
{
	using Clock = std::chrono::steady_clock;
	auto* out = static_cast<unsigned char*>(buffer);
	auto* f = static_cast<gzFile>(m_file);
	size_t got = 0;
	auto lastByte = Clock::now();
	while (got < count)
	{
		const int r = gzread(f, out + got, static_cast<unsigned>(count - got));
		if (r > 0)
		{
			got += static_cast<size_t>(r);
			m_position += static_cast<uint64_t>(r);
			lastByte = Clock::now();
			continue;
		}
		int err = Z_OK;
		gzerror(f, &err);
		if (r < 0 || (err != Z_OK && err != Z_BUF_ERROR)) break;	// damage, not an unfinished file
		if (m_stop && m_stop()) break;
		if (m_idleTimeout > 0 && std::chrono::duration<double>(Clock::now() - lastByte).count() > m_idleTimeout)
		{
			m_idle = true;
			break;
		}
		gzclearerr(f);
		std::this_thread::sleep_for(std::chrono::milliseconds(20));
	}
	return got;
}

}  // namespace pmslam
