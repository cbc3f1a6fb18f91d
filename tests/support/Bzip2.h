// Test support: text compressed with bzip2 by libbz2 itself (as bzip2 and Radish's .clf.bz2 files are), and
// files cut short. Tests including this link BZip2::BZip2 (tests/CMakeLists.txt).
#pragma once

#include <bzlib.h>

#include <stdexcept>
#include <string>

namespace pmslam::testing
{
/** `text` as one bzip2 stream; blockSize100k 1..9 (1: a block per 100 kB of text, so a few hundred kB make
 * several blocks). */
inline std::string bzip2(const std::string& text, int blockSize100k = 9)
{
	std::string out(text.size() + text.size() / 100 + 600, '\0');
	unsigned int n = static_cast<unsigned int>(out.size());
	const int rc = BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(text.data()),
											static_cast<unsigned int>(text.size()), blockSize100k, 0, 0);
	if (rc != BZ_OK) throw std::runtime_error("BZ2_bzBuffToBuffCompress failed: " + std::to_string(rc));
	out.resize(n);
	return out;
}

}  // namespace pmslam::testing
