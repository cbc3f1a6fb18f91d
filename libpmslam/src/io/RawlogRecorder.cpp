/* pmslam — recording a live run in rawlog-grabber's format (see RawlogRecorder.h). */
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/io/RawlogRecorder.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace pmslam
{
struct RawlogRecorder::Impl
{
	mrpt::io::CFileGZOutputStream out;
	std::unique_ptr<mrpt::serialization::CArchive> arch;
	bool open = false;
};

RawlogRecorder::RawlogRecorder(const std::string& path) : m_impl(std::make_unique<Impl>()), m_path(path)
{
	bool ok = false;
	try
	{
		// Level 1, as rawlog-grabber's default (rawlog_GZ_compress_level): fast enough for any sensor.
		ok = m_impl->out.open(path + ".part", 1);
	}
	catch (const std::exception&)
	{
	}
	if (!ok) throw std::runtime_error("cannot create '" + path + ".part' (is the folder there and writable?)");
	m_impl->arch = mrpt::serialization::archiveUniquePtrFrom(m_impl->out);
	m_impl->open = true;
}

RawlogRecorder::~RawlogRecorder()
{
	try
	{
		close();
	}
	catch (const std::exception&)
	{
	}
}

void RawlogRecorder::write(const mrpt::serialization::CSerializable& obj)
{
	if (!m_impl->open) return;
	*m_impl->arch << obj;
	++m_objects;
}

bool RawlogRecorder::finishStream()
{
	if (!m_impl->open) return false;
	m_impl->open = false;
	m_impl->arch.reset();
	m_impl->out.close();
	return true;
}

void RawlogRecorder::close()
{
	if (!finishStream()) return;
	std::error_code ec;
	std::filesystem::rename(m_path + ".part", m_path, ec);
	if (ec) throw std::runtime_error("cannot rename '" + m_path + ".part' to '" + m_path + "': " + ec.message());
}

void RawlogRecorder::abandon()
{
	if (!finishStream()) return;
	std::error_code ec;
	std::filesystem::remove(m_path + ".part", ec);
}

}  // namespace pmslam
