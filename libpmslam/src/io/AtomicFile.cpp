/* pmslam — crash-safe file writing (see AtomicFile.h). */
#include <pmslam/io/AtomicFile.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <streambuf>
#include <system_error>
#include <vector>

namespace pmslam
{
namespace
{
std::string osError(int err) { return std::strerror(err); }

/** Minimal output stream buffer over a POSIX file descriptor that remembers
 * the first errno seen, so the caller can report the real OS error. */
class FdStreamBuf : public std::streambuf
{
   public:
	explicit FdStreamBuf(int fd) : m_fd(fd), m_buf(1 << 16)
	{
		setp(m_buf.data(), m_buf.data() + m_buf.size());
	}
	int error() const { return m_errno; }

   protected:
	int_type overflow(int_type ch) override
	{
		if (!flushBuffer()) return traits_type::eof();
		if (!traits_type::eq_int_type(ch, traits_type::eof()))
		{
			*pptr() = traits_type::to_char_type(ch);
			pbump(1);
		}
		return traits_type::not_eof(ch);
	}
	int sync() override { return flushBuffer() ? 0 : -1; }

   private:
	bool flushBuffer()
	{
		if (m_errno != 0) return false;
		const char* p = pbase();
		std::size_t left = static_cast<std::size_t>(pptr() - pbase());
		while (left > 0)
		{
			const ssize_t n = ::write(m_fd, p, left);
			if (n < 0)
			{
				if (errno == EINTR) continue;
				m_errno = errno;
				return false;
			}
			p += n;
			left -= static_cast<std::size_t>(n);
		}
		setp(m_buf.data(), m_buf.data() + m_buf.size());
		return true;
	}

	int m_fd;
	std::vector<char> m_buf;
	int m_errno = 0;
};

/** Directory part of `path` ("." when there is none). */
std::string parentDirectory(const std::string& path)
{
	const std::filesystem::path parent = std::filesystem::path(path).parent_path();
	return parent.empty() ? std::string(".") : parent.string();
}

/** Best effort: make the rename durable. Failures are ignored (some file systems refuse). */
void syncDirectory(const std::string& dir)
{
	const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (fd < 0) return;
	(void)::fsync(fd);
	::close(fd);
}
/** Runs `writer` on a stream into `fd`; returns the first write error (0: none). If `writer`
 * throws, closes `fd`, runs `cleanup` and rethrows. */
int streamInto(int fd, const std::function<void(std::ostream&)>& writer, const std::function<void()>& cleanup)
{
	FdStreamBuf buf(fd);
	std::ostream os(&buf);
	try
	{
		writer(os);
	}
	catch (...)
	{
		::close(fd);
		cleanup();
		throw;
	}
	os.flush();
	return os ? 0 : (buf.error() != 0 ? buf.error() : EIO);
}
}  // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& writer)
{
	if (path.empty()) throw std::runtime_error("cannot write file: empty path");
	// A device or a pipe (/dev/null, /dev/stdout, a FIFO) is written in place: there is no old
	// content to keep, and a rename would replace the device with a plain file.
	struct stat target;
	if (::stat(path.c_str(), &target) == 0 && !S_ISREG(target.st_mode) && !S_ISDIR(target.st_mode))
	{
		const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
		if (fd < 0)
		{
			const int err = errno;
			throw std::runtime_error("cannot write '" + path + "': " + osError(err));
		}
		int err = streamInto(fd, writer, [] {});
		if (::close(fd) != 0 && err == 0) err = errno;
		if (err != 0) throw std::runtime_error("cannot write '" + path + "': write failed: " + osError(err));
		return;
	}
	const std::string tmp = path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
	auto fail = [&](const std::string& what, int err) -> void {
		::unlink(tmp.c_str());
		throw std::runtime_error("cannot write '" + path + "': " + what + ": " + osError(err));
	};

	const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	if (fd < 0)
	{
		const int err = errno;
		throw std::runtime_error("cannot write '" + path + "': cannot create temporary file '" + tmp +
								 "': " + osError(err));
	}
	// Keep the permission bits of the file being replaced.
	struct stat st;
	if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) (void)::fchmod(fd, st.st_mode & 07777);

	int err = streamInto(fd, writer, [&] { ::unlink(tmp.c_str()); });
	std::string stage = err != 0 ? "write failed" : "";
	if (err == 0 && ::fsync(fd) != 0 && errno != EINVAL && errno != EROFS)
	{
		err = errno;
		stage = "fsync failed";
	}
	if (::close(fd) != 0 && err == 0)
	{
		err = errno;
		stage = "close failed";
	}
	if (err != 0) fail(stage, err);
	if (::rename(tmp.c_str(), path.c_str()) != 0) fail("cannot rename '" + tmp + "' over it", errno);
	syncDirectory(parentDirectory(path));
}

void checkDirectoryWritable(const std::string& dirIn, std::uint64_t bytesNeeded)
{
	const std::string dir = dirIn.empty() ? std::string(".") : dirIn;
	std::error_code ec;
	bool created = false;
	if (!std::filesystem::exists(dir, ec))
	{
		std::filesystem::create_directories(dir, ec);
		if (ec) throw std::runtime_error("cannot create directory '" + dir + "': " + ec.message());
		created = true;
	}
	if (!std::filesystem::is_directory(dir, ec))
		throw std::runtime_error("output directory '" + dir + "' exists but is not a directory");

	const std::string probe =
		(std::filesystem::path(dir) / (".pmslam-write-probe." + std::to_string(static_cast<long>(::getpid()))))
			.string();
	const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
	if (fd < 0)
	{
		const int e = errno;
		throw std::runtime_error("directory '" + dir + "' is not writable: " + osError(e));
	}
	const char byte = '\n';
	ssize_t n;
	do n = ::write(fd, &byte, 1);
	while (n < 0 && errno == EINTR);
	const int writeErr = n == 1 ? 0 : (n < 0 ? errno : EIO);
	const int closeErr = ::close(fd) == 0 ? 0 : errno;
	::unlink(probe.c_str());
	if (writeErr != 0 || closeErr != 0)
		throw std::runtime_error("directory '" + dir +
								 "' is not writable: " + osError(writeErr != 0 ? writeErr : closeErr));
	struct statvfs fs;
	if (bytesNeeded > 0 && ::statvfs(dir.c_str(), &fs) == 0)
	{
		const std::uint64_t avail = std::uint64_t(fs.f_bavail) * fs.f_frsize;
		auto kb = [](std::uint64_t b) { return std::to_string((b + 1023) / 1024) + " KB"; };
		if (avail < bytesNeeded)
		{
			if (created) std::filesystem::remove(dir, ec);	// leave nothing behind for a refused run
			throw std::runtime_error("not enough free space in '" + dir + "': " + kb(avail) + " free, at least " +
									 kb(bytesNeeded) + " needed for the outputs");
		}
	}
}

}  // namespace pmslam
