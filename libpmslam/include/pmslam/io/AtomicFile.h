/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * AtomicFile: write a file so that readers see either the old content or the
 * complete new content, never a truncated mix, and check output directories
 * before a long run rather than after it.
 *
 * writeFileAtomically() streams into "PATH.tmp.<pid>" in the same directory,
 * flushes, checks every write, fsync()s the data, then rename()s the temporary
 * over PATH (atomic on POSIX file systems) and fsync()s the directory. When the
 * target already exists its permission bits are kept. A target that is a device or a pipe
 * (/dev/null, /dev/stdout, a FIFO) is written in place, never replaced.
 */
#pragma once

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace pmslam
{
/** Write `path` atomically with the content `writer` puts into the stream.
 * On an I/O failure the temporary file is removed and std::runtime_error is
 * thrown, naming the path and the OS error; the old file (if any) is untouched.
 * If `writer` itself throws, the temporary file is removed and the writer's
 * exception propagates unchanged (the old file is untouched too). */
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer);

/** Create `dir` (with its parents) if missing and check that a file can be
 * written in it and that its file system has at least `bytesNeeded` free.
 * Throws std::runtime_error with a one-line message otherwise.
 * An empty string means the current directory. */
void checkDirectoryWritable(const std::string& dir, std::uint64_t bytesNeeded = 0);

}  // namespace pmslam
