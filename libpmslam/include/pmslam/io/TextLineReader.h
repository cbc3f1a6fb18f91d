/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * TextLineReader: a text file read line by line, plain or compressed with
 * gzip (.gz) or bzip2 (.bz2; Radish distributes its Carmen logs as .clf.bz2),
 * the compression told by the file's first bytes. The Carmen reader reads
 * through it, and so does pm-fault-inject, so both take what the other takes.
 *
 * Lines end at '\n' (a '\r' before it is kept: callers treat it as blank); the
 * last line needs no '\n'. A damaged compressed file (cut short, a corrupt
 * block) gives every complete line before the damage, then getline() throws
 * std::runtime_error describing it; the incomplete line at the damage is
 * dropped.
 */
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace pmslam
{
class TextLineReader
{
   public:
	TextLineReader();
	~TextLineReader();
	TextLineReader(const TextLineReader&) = delete;
	TextLineReader& operator=(const TextLineReader&) = delete;

	/** False if the file cannot be opened. */
	bool open(const std::string& path);
	/** The next line, without its '\n'; false at the end of the file. Throws std::runtime_error at damage. */
	bool getline(std::string& line);

   private:
	struct Impl;
	std::unique_ptr<Impl> m_impl;
};

}  // namespace pmslam
