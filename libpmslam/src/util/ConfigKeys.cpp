/* pmslam — configuration as data (see ConfigKeys.h). */
#include <pmslam/util/ConfigKeys.h>
#include <pmslam/util/TextCase.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>

namespace pmslam::config
{
namespace
{
std::string trim(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r\n");
	if (b == std::string::npos) return "";
	return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

/** Shortest text that reads back as exactly `v`: plain decimals for everyday magnitudes, else "%g". */
std::string shortest(double v)
{
	char buf[64];
	if (v == 0 || (std::abs(v) >= 1e-5 && std::abs(v) < 1e15))
		for (int decimals = 0; decimals <= 20; ++decimals)
		{
			std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
			if (std::strtod(buf, nullptr) == v) return buf;
		}
	for (int digits = 1; digits <= 17; ++digits)
	{
		std::snprintf(buf, sizeof buf, "%.*g", digits, v);
		if (std::strtod(buf, nullptr) == v) break;
	}
	return buf;
}

bool isNumber(const std::string& v)
{
	if (v.empty()) return false;
	char* end = nullptr;
	const double d = std::strtod(v.c_str(), &end);
	return end != v.c_str() && *end == '\0' && std::isfinite(d);
}

// Counts are plain digits: MRPT's read_int would read "1e3" as 1 and "-5" as a huge unsigned.
bool isCount(const std::string& v)
{
	return !v.empty() && v.size() <= 9 && v.find_first_not_of("0123456789") == std::string::npos;
}

int boolValue(const std::string& v)	 // 1, 0, or -1 for neither
{
	const std::string l = lowerCase(v);
	if (l == "true" || l == "1" || l == "yes") return 1;
	if (l == "false" || l == "0" || l == "no") return 0;
	return -1;
}
}  // namespace

std::string Range::text() const
{
	const bool hasLo = std::isfinite(lo), hasHi = std::isfinite(hi);
	if (hasLo && hasHi)
	{
		if (loOpen || hiOpen)
			return std::string(loOpen ? "(" : "[") + shortest(lo) + ", " + shortest(hi) + (hiOpen ? ")" : "]");
		return shortest(lo) + ".." + shortest(hi);
	}
	if (hasLo) return std::string(loOpen ? "> " : ">= ") + shortest(lo);
	if (hasHi) return std::string(hiOpen ? "< " : "<= ") + shortest(hi);
	return "any";
}

std::string formatValue(Kind kind, double v)
{
	switch (kind)
	{
		case Kind::Bool: return v != 0 ? "true" : "false";
		case Kind::Integer: return shortest(std::round(v));
		default: return shortest(v);
	}
}

std::string checkValue(Kind kind, const Range& range, const std::string& unit, const std::vector<std::string>& words,
					   const std::string& text)
{
	const std::string bounds = range.text();
	const std::string inRange = std::string(bounds[0] == '>' || bounds[0] == '<' ? "a value " : "a value in ") + bounds +
								(unit.empty() ? "" : " " + unit);
	switch (kind)
	{
		case Kind::Number:
			if (!isNumber(text)) return "a number";
			return range.contains(std::strtod(text.c_str(), nullptr)) ? "" : inRange;
		case Kind::Integer:
			if (!isCount(text)) return "a whole number >= 0";
			return range.contains(std::strtod(text.c_str(), nullptr)) ? "" : inRange;
		case Kind::Bool: return boolValue(text) >= 0 ? "" : "true or false";
		case Kind::Word:
			if (std::find(words.begin(), words.end(), text) != words.end()) return "";
			{
				std::string all = "one of ";
				for (std::size_t i = 0; i < words.size(); ++i) all += (i ? ", " : "") + words[i];
				return all;
			}
	}
	return "?";
}

double parseValue(Kind kind, const std::string& text)
{
	if (kind == Kind::Bool) return boolValue(text);
	return std::strtod(text.c_str(), nullptr);
}

bool findValue(const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& name,
			   const std::vector<std::string>& aliases, std::string& text)
{
	if (c.keyExists(section, name))
	{
		text = trim(c.read_string(section, name, ""));
		return true;
	}
	for (const auto& a : aliases)
		if (c.keyExists(section, a))
		{
			text = trim(c.read_string(section, a, ""));
			return true;
		}
	return false;
}

}  // namespace pmslam::config
