/* pmslam — a file read while another program is still writing it (--follow).
 *
 * An MRPT stream over zlib's gzread (plain or gz-compressed files alike):
 * where the bytes asked for are not there yet, Read() waits for the file to
 * grow, polling, instead of reporting the end. It gives up — and returns what
 * it has, which the archive sees as the end of the file — when `idleTimeout`
 * seconds pass without a new byte (0: never) or `stop()` returns true.
 * zlib documents that gzread, after gzclearerr, resumes on a file that is
 * being written, compressed or not.
 */
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <functional>
#include <string>

namespace pmslam
{
class GrowingFileStream : public mrpt::io::CStream
{
   public:
	/** Throws std::runtime_error if the file cannot be opened. */
	GrowingFileStream(const std::string& path, double idleTimeout, std::function<bool()> stop);
	~GrowingFileStream() override;
	GrowingFileStream(const GrowingFileStream&) = delete;
	GrowingFileStream& operator=(const GrowingFileStream&) = delete;

	size_t Read(void* buffer, size_t count) override;
	size_t Write(const void*, size_t) override { return 0; }
	uint64_t Seek(int64_t, mrpt::io::CStream::TSeekOrigin) override { return m_position; }
	uint64_t getTotalBytesCount() const override { return m_position; }
	uint64_t getPosition() const override { return m_position; }
	std::string getStreamDescription() const override { return "followed file " + m_path; }

	/** True once Read() gave up because the file stopped growing (not because of stop()). */
	bool idle() const { return m_idle; }

   private:
	std::string m_path;
	void* m_file = nullptr;	 // gzFile
	double m_idleTimeout;
	std::function<bool()> m_stop;
	uint64_t m_position = 0;
	bool m_idle = false;
};

}  // namespace pmslam
