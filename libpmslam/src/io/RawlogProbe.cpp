/* pmslam — rawlog probe in a child process (see RawlogProbe.h). */
#include "RawlogProbe.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>

#if defined(__SANITIZE_ADDRESS__)
#define PMSLAM_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PMSLAM_ASAN 1
#endif
#endif

namespace pmslam
{
namespace
{
// Child → parent messages: one kObject per object read, then kEnd (clean end of file)
// or kThrew followed by the exception's text and a NUL.
constexpr char kObject = '.', kEnd = 'E', kThrew = 'X';

#ifndef PMSLAM_ASAN
/** Room a damaged length may claim in the child before it gets std::bad_alloc, on top of
 * what the process had mapped already. (Sanitizers reserve terabytes of address space for
 * their shadow memory, so there the fuzz targets' own allocation limits hold instead.) */
constexpr std::uint64_t kChildHeadroom = std::uint64_t(4) << 30;
#endif

void writeAll(int fd, const char* p, std::size_t n)
{
	while (n > 0)
	{
		const ssize_t w = ::write(fd, p, n);
		if (w < 0 && errno == EINTR) continue;
		if (w <= 0) ::_exit(3);	 // the parent is gone
		p += w;
		n -= std::size_t(w);
	}
}

[[noreturn]] void runChild(const std::string& path, int fd)
{
	// Die of the signal itself, quietly (no sanitizer or fuzzer report, no core), if the
	// parent dies first too; Ctrl-C is the parent's to handle.
	for (int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(s, SIG_DFL);
	std::signal(SIGINT, SIG_IGN);
	::prctl(PR_SET_PDEATHSIG, SIGKILL);
	const rlimit noCore{0, 0};
	::setrlimit(RLIMIT_CORE, &noCore);
	if (const int null = ::open("/dev/null", O_WRONLY); null >= 0)
	{
		::dup2(null, STDOUT_FILENO);
		::dup2(null, STDERR_FILENO);
	}
#ifndef PMSLAM_ASAN
	if (FILE* f = std::fopen("/proc/self/statm", "r"))
	{
		unsigned long long pages = 0;
		if (std::fscanf(f, "%llu", &pages) == 1)
		{
			const rlim_t cap = rlim_t(pages * std::uint64_t(::sysconf(_SC_PAGESIZE)) + kChildHeadroom);
			const rlimit as{cap, cap};
			::setrlimit(RLIMIT_AS, &as);
		}
		std::fclose(f);
	}
#endif
	try
	{
		mrpt::io::CFileGZInputStream in;
		if (!in.open(path)) throw std::runtime_error("cannot open the file");
		auto arch = mrpt::serialization::archiveFrom(in);
		for (;;)
		{
			const std::uint64_t pos0 = in.getPosition();
			try
			{
				(void)arch.ReadObject();
			}
			catch (...)
			{
				// Not a single byte of a next object: the file ends cleanly here.
				if (in.getPosition() == pos0)
				{
					writeAll(fd, &kEnd, 1);
					::_exit(0);
				}
				throw;
			}
			writeAll(fd, &kObject, 1);
		}
	}
	catch (const std::exception& e)
	{
		std::string msg(1, kThrew);
		msg += e.what();
		msg.push_back('\0');
		writeAll(fd, msg.data(), msg.size());
	}
	catch (...)
	{
		static const char msg[] = "Xunknown exception";
		writeAll(fd, msg, sizeof(msg));	 // with its NUL
	}
	::_exit(0);	 // no atexit handlers, no leak check of a process that is thrown away
}

std::string describeStatus(int status)
{
	if (WIFSIGNALED(status))
	{
		const int s = WTERMSIG(status);
		return "MRPT crashed reading it (signal " + std::to_string(s) + ", " + ::strsignal(s) + ")";
	}
	if (WIFEXITED(status)) return "the reading process stopped with status " + std::to_string(WEXITSTATUS(status));
	return "the reading process stopped";
}
}  // namespace

RawlogProbe::RawlogProbe(const std::string& path, double objectTimeoutSeconds) : m_timeout(objectTimeoutSeconds)
{
	int fds[2];
	if (::pipe2(fds, O_CLOEXEC) != 0) return;
	std::fflush(nullptr);  // buffered output must not be written twice
	const pid_t pid = ::fork();
	if (pid < 0)
	{
		::close(fds[0]);
		::close(fds[1]);
		return;
	}
	if (pid == 0)
	{
		::close(fds[0]);
		runChild(path, fds[1]);
	}
	::close(fds[1]);
	m_pid = pid;
	m_fd = fds[0];
}

RawlogProbe::~RawlogProbe() { stopChild(); }

void RawlogProbe::stopChild()
{
	if (m_fd >= 0) ::close(m_fd);
	m_fd = -1;
	if (m_pid > 0)
	{
		::kill(m_pid, SIGKILL);
		int status;
		while (::waitpid(m_pid, &status, 0) < 0 && errno == EINTR)
		{
		}
	}
	m_pid = -1;
}

bool RawlogProbe::safeToRead(std::size_t n)
{
	if (m_pid < 0 && !m_ended) return true;	 // no probe (fork failed)
	using Clock = std::chrono::steady_clock;
	auto lastProgress = Clock::now();
	while (m_done < n && !m_ended)
	{
		const std::size_t before = m_done;
		const double waited = std::chrono::duration<double>(Clock::now() - lastProgress).count();
		const int left = static_cast<int>(std::max(0.0, m_timeout - waited) * 1000.0);
		readFromChild(left);
		if (m_done != before) lastProgress = Clock::now();
		else if (!m_ended && std::chrono::duration<double>(Clock::now() - lastProgress).count() >= m_timeout)
			childStopped(true);
	}
	if (m_done >= n) return true;
	// The child ended before object n: cleanly (reading n meets the end of the file), or not.
	return m_failure.empty() && !m_exception && n == m_done + 1;
}

void RawlogProbe::readFromChild(int timeoutMs)
{
	pollfd p{m_fd, POLLIN, 0};
	const int ready = ::poll(&p, 1, timeoutMs);
	if (ready <= 0) return;	 // timeout, or EINTR: the caller decides
	char buf[4096];
	const ssize_t got = ::read(m_fd, buf, sizeof(buf));
	if (got < 0) return;
	if (got == 0)
	{
		childStopped(false);  // died without a last word
		return;
	}
	m_buffer.append(buf, std::size_t(got));
	std::size_t i = 0;
	for (; i < m_buffer.size(); ++i)
	{
		const char c = m_buffer[i];
		if (c == kObject)
			++m_done;
		else if (c == kEnd)
		{
			m_ended = true;
			stopChild();
			return;
		}
		else if (c == kThrew)
		{
			const auto nul = m_buffer.find('\0', i + 1);
			if (nul == std::string::npos) break;  // the rest is still coming
			m_failure = m_buffer.substr(i + 1, nul - i - 1);
			if (m_failure.empty()) m_failure = "exception";
			m_exception = true;
			m_ended = true;
			stopChild();
			return;
		}
	}
	m_buffer.erase(0, i);
}

void RawlogProbe::childStopped(bool hung)
{
	m_ended = true;
	if (hung)
	{
		char b[96];
		std::snprintf(b, sizeof(b), "MRPT did not finish reading it within %.3g s", m_timeout);
		m_failure = b;
		stopChild();
		return;
	}
	int status = 0;
	pid_t r;
	while ((r = ::waitpid(m_pid, &status, 0)) < 0 && errno == EINTR)
	{
	}
	m_failure = r == m_pid ? describeStatus(status) : "the reading process stopped";
	m_pid = -1;
	stopChild();
}

}  // namespace pmslam
