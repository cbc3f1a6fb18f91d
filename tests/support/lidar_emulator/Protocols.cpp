// The two sensor protocols of pm-lidar-emulator, written from the vendors' protocol descriptions and from what
// MRPT 2.5's CHokuyoURG and CLMS100Eth send and parse (see the comments where a driver's needs shaped a reply).
#include "LidarEmulator.h"

#include <cmath>
#include <cstdio>
#include <deque>

namespace pmslam::testing::emulator
{
void Protocol::garbageReply(std::string& out)
{
	std::uniform_int_distribution<int> length(1, 200), byte(0, 255);
	for (int n = length(m_robot.rng()); n > 0; --n) out += static_cast<char>(byte(m_robot.rng()));
}

namespace
{
using namespace std::chrono_literals;

/** The latest tick start + k * period at or before `now` (k >= 0), or the first one at or after it. */
Clock::time_point tickAtOrBefore(Clock::time_point start, Clock::duration period, Clock::time_point now)
{
	return now <= start ? start : start + ((now - start) / period) * period;
}
Clock::time_point tickAtOrAfter(Clock::time_point start, Clock::duration period, Clock::time_point now)
{
	const auto t = tickAtOrBefore(start, period, now);
	return t < now ? t + period : t;
}

// ------------------------------------------------------------------------------------------------------------
// Hokuyo SCIP 2.0. A reply is the echoed command line, a status line (2 characters and their checksum), data
// lines of at most 64 characters each followed by its checksum, and an empty line. A checksum is the low 6 bits
// of the sum of the line's bytes, plus 0x30.

constexpr int kSteps = 1081, kFrontStep = 540, kStepsPer360 = 1440;
constexpr double kStepAngle = 2 * M_PI / kStepsPer360;
constexpr int kMinRangeMm = 20, kMaxRangeMm = 30000;
constexpr auto kScanPeriod = 25ms;	// 2400 rpm
/** The error code a UTM sends for "no echo": any value below DMIN, which drivers (MRPT's too) take as invalid. */
constexpr unsigned kNoEcho = 1;

char scipSum(std::string_view s)
{
	unsigned sum = 0;
	for (unsigned char c : s) sum += c;
	return static_cast<char>((sum & 0x3F) + 0x30);
}

void statusLine(std::string& out, std::string_view status)
{
	out += status;
	out += scipSum(status);
	out += '\n';
}

void dataLines(std::string& out, std::string_view data)
{
	for (std::size_t i = 0; i < data.size(); i += 64)
	{
		const auto line = data.substr(i, 64);
		out += line;
		out += scipSum(line);
		out += '\n';
	}
}

/** SCIP's character encoding: 6 bits per character, plus 0x30, most significant first. */
void encode(std::string& out, unsigned value, int chars)
{
	for (int k = chars - 1; k >= 0; --k) out += static_cast<char>(((value >> (6 * k)) & 0x3F) + 0x30);
}

/** A VV / PP / II line: "LABEL:value;" and the checksum of "LABEL:value". */
void infoLine(std::string& out, const std::string& labelValue)
{
	out += labelValue;
	out += ';';
	out += scipSum(labelValue);
	out += '\n';
}

bool digits(std::string_view s, int& value)
{
	value = 0;
	for (char c : s)
	{
		if (c < '0' || c > '9') return false;
		value = value * 10 + (c - '0');
	}
	return !s.empty();
}

class Scip2 final : public Protocol
{
   public:
	using Protocol::Protocol;

	void connected() override
	{
		m_in.clear();
		reset();
	}

	void received(std::string_view bytes, Clock::time_point now, std::string& out) override
	{
		m_in.append(bytes);
		// SCIP ends a command with LF or CR; an empty line (the second half of a CR LF) is nothing.
		for (std::size_t end; (end = m_in.find_first_of("\n\r")) != std::string::npos;)
		{
			const std::string cmd = m_in.substr(0, end);
			m_in.erase(0, end + 1);
			if (cmd.empty()) continue;
			if (m_garbage)
				garbageReply(out);
			else
				handle(cmd, now, out);
		}
		if (m_in.size() > 4096) m_in.clear();  // no line end in sight: not SCIP
	}

	std::optional<Clock::time_point> nextDue() const override
	{
		std::optional<Clock::time_point> t;
		if (m_stream) t = m_stream->next;
		for (const auto& s : m_singles)
			if (!t || s.next < *t) t = s.next;
		return t;
	}

	void due(Clock::time_point now, std::string& out, bool clientReading) override
	{
		if (m_stream && m_stream->next <= now)
		{
			// Serve the latest scan that is due; one missed while the client lagged is gone, as on the sensor.
			auto& s = *m_stream;
			const auto interval = kScanPeriod * (s.skip + 1);
			const auto t = s.next + ((now - s.next) / interval) * interval;
			s.next = t + interval;
			if (clientReading)
			{
				const bool last = !s.forever && --s.remaining <= 0;
				// The echo counts down the scans still to come.
				std::string echo = s.cmd;
				char left[4];
				std::snprintf(left, sizeof left, "%02d", std::max(s.remaining, 0) % 100);
				if (!s.forever) echo.replace(13, 2, left);
				sendScan(s, echo, "99", t, out);
				if (last) m_stream.reset();
			}
		}
		for (auto it = m_singles.begin(); it != m_singles.end();)
		{
			if (it->next > now)
			{
				++it;
				continue;
			}
			sendScan(*it, it->cmd, "00", it->next, out);
			it = m_singles.erase(it);
		}
	}

   private:
	/** The sensor as powered up: laser off, nothing measured. */
	void reset()
	{
		m_stream.reset();
		m_singles.clear();
		m_laserOn = m_timeAdjust = m_rebootAsked = false;
	}

	/** An MD/MS/ME stream or a GD/GS/GE request. */
	struct Request
	{
		std::string cmd;
		char kind;	// 'D' distances, 'S' distances in 2 characters, 'E' distances and intensities
		int first, last, cluster, skip, remaining;
		bool forever;
		Clock::time_point next;
	};

	void handle(const std::string& cmd, Clock::time_point now, std::string& out)
	{
		// An optional ";tag" after the parameters is echoed back with the command, not parsed.
		const std::string_view c = std::string_view(cmd).substr(0, cmd.find(';'));
		const auto reply = [&](std::string_view status) {
			out += cmd;
			out += '\n';
			statusLine(out, status);
			out += '\n';
		};
		const auto info = [&](std::initializer_list<std::string> lines) {
			out += cmd;
			out += '\n';
			statusLine(out, "00");
			for (const auto& l : lines) infoLine(out, l);
			out += '\n';
		};
		if (c != "RB") m_rebootAsked = false;

		if (c == "SCIP2.0")
			reply("0E");  // already speaking SCIP 2.0; CHokuyoURG wants a 3-character status line here
		else if (c == "VV")
			info({"VEND:Hokuyo Automatic Co.,Ltd.", "PROD:SOKUIKI Sensor TOP-URG UTM-30LX",
				  "FIRM:1.20.01(16/Nov./2009)", "PROT:SCIP 2.0", "SERI:00000001"});
		else if (c == "PP")
			info({"MODL:UTM-30LX", "DMIN:" + std::to_string(kMinRangeMm), "DMAX:" + std::to_string(kMaxRangeMm),
				  "ARES:" + std::to_string(kStepsPer360), "AMIN:0", "AMAX:" + std::to_string(kSteps - 1),
				  "AFRT:" + std::to_string(kFrontStep), "SCAN:2400"});
		else if (c == "II")
		{
			std::string time = "TIME:";
			encode(time, timestamp(now), 4);
			info({"MODL:UTM-30LX", m_laserOn ? "LASR:ON" : "LASR:OFF", "SCSP:Initial(2400[rpm])",
				  "MESM:Measuring by Normal Mode", "SBPS:Ethernet 100 [Mbps]", time, "STAT:Stable 000 no error."});
		}
		else if (c == "BM")
		{
			reply(m_laserOn ? "02" : "00");	 // 02: the laser was already on
			m_laserOn = true;
		}
		else if (c == "QT" || c == "RS" || c == "RT")
		{
			m_stream.reset();
			m_singles.clear();
			m_laserOn = false;
			reply("00");
		}
		else if (c == "RB")
		{
			// A reboot must be asked twice in a row; it then ends everything running.
			const bool reboot = m_rebootAsked;
			reply(reboot ? "00" : "01");
			if (reboot) reset();
			m_rebootAsked = !reboot;
		}
		else if (c == "TM0" || c == "TM2")
		{
			m_timeAdjust = c == "TM0";
			reply("00");
		}
		else if (c == "TM1")
		{
			if (!m_timeAdjust) return reply("01");
			out += cmd;
			out += '\n';
			statusLine(out, "00");
			std::string t;
			encode(t, timestamp(now), 4);
			dataLines(out, t);
			out += '\n';
		}
		else if (c == "HS0" || c == "HS1" || (c.size() == 4 && c.substr(0, 2) == "CR"))
			reply("00");
		else if (c.size() == 8 && c.substr(0, 2) == "SS")
			reply("0F");  // an Ethernet sensor has no bit rate to change
		else if ((c[0] == 'M' || c[0] == 'G') && c.size() >= 2 && (c[1] == 'D' || c[1] == 'S' || c[1] == 'E'))
			measure(cmd, c, now, out);
		else
			reply("0E");  // unknown command
	}

	/** MDssssllllccinn / GDssssllllcc (and their S and E variants): start step, last step, cluster size,
	 * scan interval and number of scans (0: until QT). */
	void measure(const std::string& cmd, std::string_view c, Clock::time_point now, std::string& out)
	{
		const bool stream = c[0] == 'M';
		const auto reply = [&](std::string_view status) {
			out += cmd;
			out += '\n';
			statusLine(out, status);
			out += '\n';
		};
		if (c.size() != (stream ? 15u : 12u)) return reply("0C");	 // wrong length
		Request r{cmd, c[1], 0, 0, 0, 0, 0, false, now};
		if (!digits(c.substr(2, 4), r.first) || r.first >= kSteps) return reply("01");
		if (!digits(c.substr(6, 4), r.last) || r.last >= kSteps) return reply("02");
		if (r.first > r.last) return reply("04");
		if (!digits(c.substr(10, 2), r.cluster)) return reply("03");
		r.cluster = std::max(r.cluster, 1);
		if (stream && !digits(c.substr(12, 1), r.skip)) return reply("05");
		if (stream && !digits(c.substr(13, 2), r.remaining)) return reply("06");
		r.forever = stream && r.remaining == 0;
		if (!stream && !m_laserOn) return reply("10");	// a single scan needs BM first

		m_robot.startServing(now);
		r.next = tickAtOrAfter(*m_robot.servingSince(), kScanPeriod, now);
		if (stream)
		{
			m_laserOn = true;  // MD switches the laser on by itself
			reply("00");
			m_stream = r;
		}
		else
			m_singles.push_back(r);
	}

	void sendScan(const Request& r, const std::string& echo, std::string_view status, Clock::time_point t,
				  std::string& out)
	{
		if (!m_cache || m_cache->time != t)
			m_cache = m_robot.scan(t, kSteps, -kFrontStep * kStepAngle, kStepAngle, kMaxRangeMm * 1e-3);
		std::string data;
		data.reserve(6 * kSteps);
		for (int first = r.first; first <= r.last; first += r.cluster)
		{
			// A cluster reports its nearest valid reading, or an error code when it has none.
			unsigned value = kNoEcho;
			for (int s = first; s < std::min(first + r.cluster, r.last + 1); ++s)
			{
				const unsigned v = millimetres(m_cache->ranges[s], r.kind == 'S' ? 4095 : 0x3FFFF);
				if (v >= kMinRangeMm && (value < kMinRangeMm || v < value)) value = v;
			}
			encode(data, value, r.kind == 'S' ? 2 : 3);
			if (r.kind == 'E') encode(data, value >= kMinRangeMm ? 2000 : 0, 3);  // a flat intensity
		}
		out += echo;
		out += '\n';
		statusLine(out, status);
		std::string stamp;
		encode(stamp, timestamp(t), 4);
		dataLines(out, stamp);
		dataLines(out, data);
		out += '\n';
		m_robot.served(*m_cache);
	}

	static unsigned millimetres(double r, unsigned largest)
	{
		if (!std::isfinite(r)) return kNoEcho;
		const long mm = std::lround(r * 1000);
		return mm < kMinRangeMm || mm > long(largest) ? kNoEcho : unsigned(mm);
	}

	/** The sensor's clock: milliseconds since it started, 24 bits. */
	unsigned timestamp(Clock::time_point t) const { return unsigned(m_robot.uptimeMicros(t) / 1000) & 0xFFFFFF; }

	std::string m_in;
	std::optional<Request> m_stream;
	std::deque<Request> m_singles;
	std::optional<Scan> m_cache;
	bool m_laserOn = false, m_timeAdjust = false, m_rebootAsked = false;
};

// ------------------------------------------------------------------------------------------------------------
// SICK LMS1xx, CoLa-A: every telegram is <STX> text <ETX>; the text is space-separated tokens, numbers in hex
// unless signed with + or - (decimal). Angles are in 1/10000 degree, 90 degrees straight ahead, -45 degrees
// behind on the right; a scan runs counter-clockwise (right to left) from its start angle.

std::string toHex(unsigned long long v)
{
	char buf[24];
	std::snprintf(buf, sizeof buf, "%llX", v);
	return buf;
}

std::string colaString(const std::string& s) { return toHex(s.size()) + " " + s; }

bool colaNumber(const std::string& token, long long& v)
{
	if (token.empty()) return false;
	char* end = nullptr;
	v = (token[0] == '+' || token[0] == '-') ? std::strtoll(token.c_str(), &end, 10)
											 : std::strtoll(token.c_str(), &end, 16);
	return *end == '\0';
}

class Lms1xx final : public Protocol
{
   public:
	Lms1xx(Robot& robot, bool garbage, bool mrptOrder) : Protocol(robot, garbage), m_mrptOrder(mrptOrder) {}

	void connected() override
	{
		m_in.clear();
		m_streaming = false;
		m_level = 0;
	}

	void received(std::string_view bytes, Clock::time_point now, std::string& out) override
	{
		m_in.append(bytes);
		for (;;)
		{
			const auto stx = m_in.find('\x02');
			if (stx == std::string::npos)
			{
				m_in.clear();  // nothing before a telegram's start means anything
				return;
			}
			const auto etx = m_in.find('\x03', stx);
			if (etx == std::string::npos)
			{
				m_in.erase(0, stx);
				if (m_in.size() > 65536) m_in.clear();
				return;
			}
			const std::string telegram = m_in.substr(stx + 1, etx - stx - 1);
			m_in.erase(0, etx + 1);
			if (m_garbage)
				garbageReply(out);
			else
				handle(telegram, now, out);
		}
	}

	std::optional<Clock::time_point> nextDue() const override
	{
		if (!m_streaming) return std::nullopt;
		return m_nextStream;
	}

	void due(Clock::time_point now, std::string& out, bool clientReading) override
	{
		if (!m_streaming || m_nextStream > now) return;
		const auto t = tickAtOrBefore(*m_robot.servingSince(), period(), now);
		m_nextStream = t + period();
		if (clientReading) sendScan("sSN", t, now, out);
	}

   private:
	struct ScanConfig
	{
		long long frequency = 2500, resolution = 5000, start = -450000, stop = 2250000;	 // 25 Hz, 0.5 degree
	};

	void handle(const std::string& telegram, Clock::time_point now, std::string& out)
	{
		std::vector<std::string> tok;
		for (std::size_t i = 0; i < telegram.size();)
		{
			const auto end = std::min(telegram.find(' ', i), telegram.size());
			if (end > i) tok.push_back(telegram.substr(i, end - i));
			i = end + 1;
		}
		const auto reply = [&out](const std::string& text) {
			out += '\x02';
			out += text;
			out += '\x03';
		};
		if (tok.size() < 2) return reply("sFA C");	// not a CoLa command
		const std::string &type = tok[0], &name = tok[1];

		if (type == "sMN" && name == "SetAccessMode")
		{
			// The client levels' fixed passwords (hashes): maintenance, authorised client, service.
			const bool ok = tok.size() == 4 && ((tok[2] == "02" && tok[3] == "B21ACE26") ||
												(tok[2] == "03" && tok[3] == "F4724744") ||
												(tok[2] == "04" && tok[3] == "81BE23AA"));
			if (ok) m_level = std::stoi(tok[2]);
			reply(std::string("sAN SetAccessMode ") + (ok ? "1" : "0"));
		}
		else if (type == "sMN" && name == "mLMPsetscancfg")
			setScanConfig(tok, reply);
		else if (type == "sWN" && (name == "LMDscandatacfg" || name == "LMPoutputRange"))
			reply(m_level ? "sWA " + name : "sFA A");  // accepted, though only DIST1 is ever sent
		else if (type == "sMN" && (name == "LMCstartmeas" || name == "LMCstopmeas"))
		{
			m_measuring = name == "LMCstartmeas";
			reply("sAN " + name + " 0");
		}
		else if (type == "sMN" && name == "Run")
		{
			// Leaving the configuration level makes a new scan configuration effective.
			if (m_pending) m_config = *m_pending;
			m_pending.reset();
			m_level = 0;
			reply("sAN Run 1");
		}
		else if (type == "sMN" && name == "mEEwriteall")
			reply("sAN mEEwriteall 1");
		else if (type == "sRN" && name == "STlms")
			// 7: ready for measurement. Kept short: CLMS100Eth reads at most 100 bytes per reply and looks
			// for the status at byte 11.
			reply(std::string("sRA STlms ") + (m_measuring ? "7" : "6") + " 0 8 00:00:00 8 01.01.2024 0 0 0");
		else if (type == "sRN" && name == "LMPscancfg")
			reply("sRA LMPscancfg " + toHex(m_config.frequency) + " 1 " + toHex(m_config.resolution) + " " +
				  angle(m_config.start) + " " + angle(m_config.stop));
		else if (type == "sRN" && name == "LMPoutputRange")
			reply("sRA LMPoutputRange 1 " + toHex(m_config.resolution) + " " + angle(m_config.start) + " " +
				  angle(m_config.stop));
		else if (type == "sRN" && name == "DeviceIdent")
			reply("sRA DeviceIdent " + colaString("LMS1xx_Emulator") + " " + colaString("V1.00"));
		else if (type == "sRN" && name == "SerialNumber")
			reply("sRA SerialNumber " + colaString("00000001"));
		else if (type == "sRN" && name == "FirmwareVersion")
			reply("sRA FirmwareVersion " + colaString("V1.00"));
		else if (type == "sRN" && name == "LMDscandata")
		{
			// A poll: the last scan completed (CLMS100Eth asks this way, once per doProcess()).
			m_robot.startServing(now);
			sendScan("sRA", tickAtOrBefore(*m_robot.servingSince(), period(), now), now, out);
		}
		else if (type == "sEN" && name == "LMDscandata" && tok.size() == 3 && (tok[2] == "0" || tok[2] == "1"))
		{
			m_streaming = tok[2] == "1";
			reply("sEA LMDscandata " + tok[2]);
			if (m_streaming)
			{
				m_robot.startServing(now);
				m_nextStream = tickAtOrAfter(*m_robot.servingSince(), period(), now);
			}
		}
		else
			reply(type == "sMN" ? "sFA 2" : "sFA 3");  // unknown method / unknown variable
	}

	/** sMN mLMPsetscancfg frequency segments resolution start stop. An LMS1xx scans at 25 Hz with 0.25 or
	 * 0.5 degree, or at 50 Hz with 0.5 degree; the new configuration applies after "sMN Run". */
	template <class Reply>
	void setScanConfig(const std::vector<std::string>& tok, const Reply& reply)
	{
		ScanConfig c;
		long long segments = 0;
		int status = 0;
		if (!m_level)
			return reply("sFA 1");	// access denied
		else if (tok.size() != 7 || !colaNumber(tok[2], c.frequency) || !colaNumber(tok[3], segments) ||
				 !colaNumber(tok[4], c.resolution) || !colaNumber(tok[5], c.start) || !colaNumber(tok[6], c.stop))
			return reply("sFA 5");	// invalid data
		const bool freqOk = c.frequency == 2500 || c.frequency == 5000;
		const bool resOk = c.resolution == 5000 || (c.resolution == 2500 && c.frequency == 2500);
		if (!freqOk || !resOk)
			status = !freqOk && !resOk ? 3 : !freqOk ? 1 : 2;
		else if (segments != 1)
			status = 5;
		else if (c.start < -450000 || c.stop > 2250000 || c.start >= c.stop)
			status = 4;
		if (status == 0) m_pending = c;
		const ScanConfig& shown = status == 0 ? c : m_config;
		reply("sAN mLMPsetscancfg " + std::to_string(status) + " " + toHex(shown.frequency) + " 1 " +
			  toHex(shown.resolution) + " " + angle(shown.start) + " " + angle(shown.stop));
	}

	static std::string angle(long long a) { return toHex(static_cast<std::uint32_t>(a)); }

	Clock::duration period() const
	{
		return std::chrono::duration_cast<Clock::duration>(std::chrono::microseconds(100'000'000 / m_config.frequency));
	}

	void sendScan(const char* type, Clock::time_point t, Clock::time_point now, std::string& out)
	{
		const ScanConfig& c = m_config;
		const int n = int((c.stop - c.start) / c.resolution) + 1;
		const double step = c.resolution * 1e-4 * M_PI / 180, first = (c.start * 1e-4 - 90) * M_PI / 180;
		if (!m_cache || m_cache->time != t || m_cache->ranges.size() != std::size_t(n))
			m_cache = m_robot.scan(t, n, first, step, 20.0);
		const auto tick = (t - *m_robot.servingSince()) / period();
		const long long measuring = c.frequency / 100 * (3600000 / c.resolution) / 100;	 // 100 Hz units
		std::string s = std::string("\x02") + type + " LMDscandata 1 1 1A2B3C 0 0 " + toHex(++m_telegrams) + " " +
						toHex(static_cast<unsigned long long>(tick)) + " " +
						toHex(static_cast<std::uint32_t>(m_robot.uptimeMicros(t))) + " " +
						toHex(static_cast<std::uint32_t>(m_robot.uptimeMicros(now))) + " 0 0 0 0 0 " +
						toHex(c.frequency) + " " + toHex(measuring) + " 0 1 DIST1 3F800000 00000000 " +
						angle(c.start) + " " + toHex(c.resolution) + " " + toHex(n);
		for (int i = 0; i < n; ++i)
		{
			// No echo (or beyond 20 m) is 0, as the sensor sends it.
			const double r = m_cache->ranges[m_mrptOrder ? n - 1 - i : i];
			s += ' ';
			s += toHex(std::isfinite(r) ? static_cast<unsigned long long>(std::max(0L, std::lround(r * 1000))) : 0);
		}
		// No 8-bit channel, position, name, comment, time or event block.
		s += " 0 0 0 0 0 0\x03";
		out += s;
		m_robot.served(*m_cache);
	}

	const bool m_mrptOrder;
	std::string m_in;
	ScanConfig m_config;
	std::optional<ScanConfig> m_pending;
	std::optional<Scan> m_cache;
	bool m_streaming = false, m_measuring = true;
	int m_level = 0;
	Clock::time_point m_nextStream;
	unsigned long long m_telegrams = 0;
};

}  // namespace

std::unique_ptr<Protocol> makeScip2(Robot& robot, bool garbage) { return std::make_unique<Scip2>(robot, garbage); }

std::unique_ptr<Protocol> makeLms1xx(Robot& robot, bool garbage, bool mrptOrder)
{
	return std::make_unique<Lms1xx>(robot, garbage, mrptOrder);
}

}  // namespace pmslam::testing::emulator
