// pm-lidar-emulator: a laser scanner on 127.0.0.1 that speaks Hokuyo SCIP 2.0 or SICK LMS1xx CoLa-A, serving
// scans ray-cast in a synthetic world from a robot driving a loop in real time. For testing the real drivers
// (MRPT's CHokuyoURG and CLMS100Eth) and whatever is built on them, without the hardware.
#include "LidarEmulator.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <iostream>

namespace pmslam::testing::emulator
{
Robot::Robot(SyntheticWorld world, LoopPath path, double speed, double noise, std::FILE* truth)
	: m_world(std::move(world)), m_path(std::move(path)), m_speed(speed), m_noise(noise), m_truth(truth)
{
}

void Robot::startServing(Clock::time_point now)
{
	if (!m_start) m_start = now;
}

Scan Robot::scan(Clock::time_point t, int n, double first, double step, double maxRange)
{
	Scan s{t, m_path.at(m_speed * std::chrono::duration<double>(t - *m_start).count()), {}};
	std::normal_distribution<double> noise(0.0, m_noise);
	s.ranges.resize(n);
	for (int i = 0; i < n; ++i)
	{
		const double r = m_world.castRay(s.pose.x, s.pose.y, s.pose.phi + first + i * step);
		s.ranges[i] = r <= maxRange ? r + (m_noise > 0 ? noise(m_rng) : 0.0) : std::nan("");
	}
	return s;
}

void Robot::served(const Scan& s)
{
	if (!m_firstServed) m_firstServed = s.time;
	if (!m_truth) return;
	std::fprintf(m_truth, "%.6f %.6f %.6f %.6f\n", epochSeconds(s.time), s.pose.x, s.pose.y, s.pose.phi);
	std::fflush(m_truth);
}

double Robot::epochSeconds(Clock::time_point t) const
{
	return std::chrono::duration<double>(m_bootEpoch.time_since_epoch()).count() +
		   std::chrono::duration<double>(t - m_boot).count();
}

std::uint64_t Robot::uptimeMicros(Clock::time_point t) const
{
	return std::uint64_t(std::chrono::duration_cast<std::chrono::microseconds>(t - m_boot).count());
}

}  // namespace pmslam::testing::emulator

namespace
{
using namespace pmslam::testing;
using namespace pmslam::testing::emulator;

volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }

constexpr const char* kUsage =
	"usage: pm-lidar-emulator --protocol scip|lms1xx [--port P] [--world room|corridors] [--speed V]\n"
	"                         [--truth FILE] [--duration S] [--disconnect-at S] [--garbage] [--noise SIGMA]\n"
	"                         [--lms-mrpt-order]\n"
	"  --port 0 (default) picks a free port; \"PORT <n>\" is printed once listening on 127.0.0.1.\n"
	"  --truth: one line \"t x y yaw\" per scan served (t: seconds since the Unix epoch).\n"
	"  --duration: exit after S seconds of serving (from the first scan request; 0: never).\n"
	"  --disconnect-at: drop the client S seconds after the first scan served, then accept a new one.\n"
	"  --outage S: with --disconnect-at, for S seconds after the drop every new connection is dropped at once\n"
	"    (a sensor that was unplugged), then served again.\n"
	"  --garbage: answer every request with random bytes.\n"
	"  --lms-mrpt-order: send LMS beams left to right, as MRPT's CLMS100Eth reads them (a real LMS1xx\n"
	"    sends them right to left, so CLMS100Eth mirrors its scans).\n";

struct Options
{
	std::string protocol, world = "corridors", truth;
	int port = 0;
	double speed = 0.5, duration = 0, disconnectAt = -1, noise = 0.005, outage = 0;
	bool garbage = false, lmsMrptOrder = false;
};

[[noreturn]] void usageError(const std::string& message)
{
	std::cerr << "pm-lidar-emulator: " << message << "\n" << kUsage;
	std::exit(2);
}

double number(const std::string& option, const char* text, double lowest)
{
	char* end = nullptr;
	const double v = std::strtod(text, &end);
	if (end == text || *end != '\0' || !std::isfinite(v) || v < lowest)
		usageError(option + " needs a number" + (lowest == 0 ? " >= 0" : "") + ", not '" + text + "'");
	return v;
}

Options parse(int argc, char** argv)
{
	Options o;
	for (int i = 1; i < argc; ++i)
	{
		const std::string a = argv[i];
		const auto value = [&]() -> const char* {
			if (i + 1 >= argc) usageError(a + " needs a value");
			return argv[++i];
		};
		if (a == "--protocol")
			o.protocol = value();
		else if (a == "--port")
		{
			const double p = number(a, value(), 0);
			if (p > 65535 || p != std::floor(p)) usageError("--port needs a port number");
			o.port = int(p);
		}
		else if (a == "--world")
			o.world = value();
		else if (a == "--speed")
			o.speed = number(a, value(), 0);
		else if (a == "--truth")
			o.truth = value();
		else if (a == "--duration")
			o.duration = number(a, value(), 0);
		else if (a == "--disconnect-at")
			o.disconnectAt = number(a, value(), 0);
		else if (a == "--outage")
			o.outage = number(a, value(), 0);
		else if (a == "--noise")
			o.noise = number(a, value(), 0);
		else if (a == "--garbage")
			o.garbage = true;
		else if (a == "--lms-mrpt-order")
			o.lmsMrptOrder = true;
		else if (a == "--help" || a == "-h")
		{
			std::cout << kUsage;
			std::exit(0);
		}
		else
			usageError("unknown option " + a);
	}
	if (o.protocol != "scip" && o.protocol != "lms1xx") usageError("--protocol must be scip or lms1xx");
	if (o.world != "corridors" && o.world != "room") usageError("--world must be room or corridors");
	return o;
}

[[noreturn]] void fail(const char* what)
{
	std::cerr << "pm-lidar-emulator: " << what << ": " << std::strerror(errno) << "\n";
	std::exit(1);
}

/** Closes the connection with a reset, as a sensor that loses power or reboots would leave it. */
void dropAbruptly(int fd)
{
	const linger l{1, 0};
	::setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof l);
	::close(fd);
}

}  // namespace

int main(int argc, char** argv)
{
	const Options opt = parse(argc, argv);

	std::FILE* truth = nullptr;
	if (!opt.truth.empty() && !(truth = std::fopen(opt.truth.c_str(), "w"))) fail(opt.truth.c_str());
	Robot robot(opt.world == "room" ? furnishedRoom() : corridorsWorld(), LoopPath::forWorld(opt.world, opt.speed),
				opt.speed, opt.noise, truth);
	const auto protocol =
		opt.protocol == "scip" ? makeScip2(robot, opt.garbage) : makeLms1xx(robot, opt.garbage, opt.lmsMrptOrder);

	// SIGINT / SIGTERM are blocked except while waiting in ppoll(), so a stop request is never missed.
	struct sigaction sa{};
	sa.sa_handler = onSignal;
	sigaction(SIGINT, &sa, nullptr);
	sigaction(SIGTERM, &sa, nullptr);
	std::signal(SIGPIPE, SIG_IGN);
	sigset_t blocked, waitMask;
	sigemptyset(&blocked);
	sigaddset(&blocked, SIGINT);
	sigaddset(&blocked, SIGTERM);
	sigprocmask(SIG_BLOCK, &blocked, &waitMask);
	sigdelset(&waitMask, SIGINT);
	sigdelset(&waitMask, SIGTERM);

	const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (listener < 0) fail("socket");
	const int yes = 1;
	::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
	sockaddr_in addr{};
	addr.sin_family = AF_INET;
	addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	addr.sin_port = htons(static_cast<std::uint16_t>(opt.port));
	if (::bind(listener, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) fail("bind");
	if (::listen(listener, 4) < 0) fail("listen");
	socklen_t len = sizeof addr;
	::getsockname(listener, reinterpret_cast<sockaddr*>(&addr), &len);
	std::printf("PORT %u\n", unsigned(ntohs(addr.sin_port)));
	std::fflush(stdout);

	int client = -1;
	std::string out;  // bytes not yet taken by the client
	constexpr std::size_t kBacklog = 256 * 1024;  // past this the client is not reading: skip scans
	bool disconnectPending = opt.disconnectAt >= 0;
	std::optional<Clock::time_point> outageUntil;  // --outage: connections refused until then
	const auto seconds = [](double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
	const auto closeClient = [&](bool abrupt) {
		if (client < 0) return;
		abrupt ? dropAbruptly(client) : void(::close(client));
		client = -1;
		out.clear();
	};

	while (!g_stop)
	{
		const auto now = Clock::now();
		const auto since = robot.servingSince();
		if (since && opt.duration > 0 && now >= *since + seconds(opt.duration)) break;
		const auto first = robot.firstScanServed();
		if (disconnectPending && first && now >= *first + seconds(opt.disconnectAt))
		{
			closeClient(true);
			disconnectPending = false;
			outageUntil = now + seconds(opt.outage);
		}

		std::optional<Clock::time_point> wake;
		const auto earliest = [&wake](Clock::time_point t) {
			if (!wake || t < *wake) wake = t;
		};
		if (client >= 0)
			if (const auto t = protocol->nextDue()) earliest(*t);
		if (since && opt.duration > 0) earliest(*since + seconds(opt.duration));
		if (disconnectPending && first) earliest(*first + seconds(opt.disconnectAt));

		pollfd fds[2] = {{listener, POLLIN, 0}, {client, short(POLLIN | (out.empty() ? 0 : POLLOUT)), 0}};
		timespec timeout{};
		if (wake)
		{
			const auto ns = std::max<long long>(0, std::chrono::nanoseconds(*wake - now).count());
			timeout = {time_t(ns / 1'000'000'000), long(ns % 1'000'000'000)};
		}
		const int n = ::ppoll(fds, client >= 0 ? 2 : 1, wake ? &timeout : nullptr, &waitMask);
		if (n < 0 && errno != EINTR) fail("ppoll");

		if (n > 0 && (fds[0].revents & POLLIN))
		{
			// One client at a time, as on the sensors; a newcomer takes over (a driver that reconnects
			// may not have closed its old socket).
			const int fd = ::accept4(listener, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
			if (fd >= 0 && outageUntil && Clock::now() < *outageUntil)
				dropAbruptly(fd);
			else if (fd >= 0)
			{
				closeClient(false);
				client = fd;
				::setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
				protocol->connected();
				// --garbage never serves a scan: its --duration counts from the first connection instead.
				if (opt.garbage) robot.startServing(Clock::now());
			}
		}
		else if (n > 0 && client >= 0 && (fds[1].revents & (POLLIN | POLLHUP | POLLERR)))
		{
			char buf[8192];
			const ssize_t got = ::recv(client, buf, sizeof buf, 0);
			if (got > 0)
				protocol->received(std::string_view(buf, std::size_t(got)), Clock::now(), out);
			else if (got == 0 || (errno != EAGAIN && errno != EINTR))
				closeClient(false);
		}

		if (client >= 0)
		{
			const auto t = protocol->nextDue();
			if (t && *t <= Clock::now()) protocol->due(Clock::now(), out, out.size() < kBacklog);
		}
		while (client >= 0 && !out.empty())
		{
			const ssize_t sent = ::send(client, out.data(), out.size(), MSG_NOSIGNAL);
			if (sent > 0)
				out.erase(0, std::size_t(sent));
			else if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
				break;
			else if (sent < 0 && errno != EINTR)
				closeClient(false);
		}
	}
	closeClient(false);
	::close(listener);
	if (truth) std::fclose(truth);
	return 0;
}
