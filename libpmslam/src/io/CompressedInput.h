/* pmslam — a file read as its decompressed bytes, whether plain, gzip or bzip2 (not installed).
 *
 * Carmen logs come compressed: Radish distributes them as .clf.bz2 / .log.bz2,
 * others as .gz. The Carmen reader (through TextLineReader) and the format
 * detection of LogReader::open() read through this class, so a compressed log
 * reads exactly like the plain file. The compression is told by the file's
 * first bytes, not its name: gzip and plain files go through zlib's gzread
 * (which passes plain files through unchanged, as MRPT's CFileGZInputStream
 * does), bzip2 files through libbz2, several concatenated bzip2 streams (as
 * pbzip2 writes them) one after the other.
 *
 * Damage — a file cut short, a corrupt block — is reported by read() throwing
 * once every byte decompressed before it has been returned, so a reader can
 * use what came before and stop there with one warning. bzip2 checks a block
 * (100–900 kB of text) only as a whole, so a truncated .bz2 ends at its last
 * complete block.
 */
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace pmslam::detail
{
enum class Compression
{
	None,
	Gzip,
	Bzip2
};

/** The compression of the file from its first bytes (None for a plain file, or one that cannot be read). */
Compression compressionOf(const std::string& path);

class CompressedInput
{
   public:
	CompressedInput();
	~CompressedInput();
	CompressedInput(const CompressedInput&) = delete;
	CompressedInput& operator=(const CompressedInput&) = delete;

	/** False if the file cannot be opened. */
	bool open(const std::string& path);
	/** Up to `count` decompressed bytes into `buffer`; 0 at the end of the data. Throws std::runtime_error
	 * describing the damage ("bzip2 data ends early (truncated file)") when it reaches it. */
	std::size_t read(char* buffer, std::size_t count);

	struct Source;	// one per compression (CompressedInput.cpp)

   private:
	std::unique_ptr<Source> m_source;
};

}  // namespace pmslam::detail
