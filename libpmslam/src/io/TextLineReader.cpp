/* pmslam — a plain or compressed text file read line by line (see TextLineReader.h). */
#include <pmslam/io/TextLineReader.h>

#include <vector>

#include "CompressedInput.h"

namespace pmslam
{
namespace
{
constexpr std::size_t kChunk = 1 << 16;
}

struct TextLineReader::Impl
{
	detail::CompressedInput in;
	std::string buf;
	std::size_t pos = 0;
	bool eof = false;
	std::vector<char> chunk = std::vector<char>(kChunk);
};

TextLineReader::TextLineReader() : m_impl(std::make_unique<Impl>()) {}
TextLineReader::~TextLineReader() = default;

bool TextLineReader::open(const std::string& path)
{
	m_impl = std::make_unique<Impl>();
	return m_impl->in.open(path);
}

bool TextLineReader::getline(std::string& line)
{
	Impl& d = *m_impl;
	for (;;)
	{
		const std::size_t nl = d.buf.find('\n', d.pos);
		if (nl != std::string::npos)
		{
			line.assign(d.buf, d.pos, nl - d.pos);
			d.pos = nl + 1;
			return true;
		}
		if (d.eof)
		{
			if (d.pos >= d.buf.size()) return false;
			line.assign(d.buf, d.pos, std::string::npos);
			d.pos = d.buf.size();
			return true;
		}
		d.buf.erase(0, d.pos);
		d.pos = 0;
		const std::size_t got = d.in.read(d.chunk.data(), d.chunk.size());
		if (got == 0)
			d.eof = true;
		else
			d.buf.append(d.chunk.data(), got);
	}
}

}  // namespace pmslam
