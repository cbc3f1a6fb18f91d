/* pmslam — configuration as data: one descriptor per INI key.
 *
 * Each options struct (the matcher's, the grid's, the builder's, loop closure's, the log reader's)
 * lists its keys once: name, unit, allowed range, level (basic: what a user sets for a robot;
 * expert: an algorithm constant), a one-line doc, and where the value goes. The struct's own
 * default member values are the defaults. Loading, dumping, range checks, the key list, the
 * committed config/default.ini and docs/configuration.md all come from these lists (SlamConfig.h
 * composes them into the INI sections; pm-slam-config prints them), so a key is written once.
 */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/bits_math.h>

#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace pmslam::config
{
enum class Kind
{
	Number,	  ///< a real number (strtod syntax)
	Integer,  ///< a count: plain digits
	Bool,	  ///< true/false, 1/0, yes/no
	Word	  ///< one of Key::words
};

enum class Level
{
	Basic,	///< set per robot or per log: in config/default.ini
	Expert	///< an algorithm constant: documented, accepted anywhere, not in default.ini
};

/** Allowed values of a Number or Integer key, in the key's own unit. */
struct Range
{
	double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
	bool loOpen = false, hiOpen = false;
	bool contains(double v) const
	{
		return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
	}
	/** "0..1", "> 0", ">= 0", "(0.5, 1)". */
	std::string text() const;
};
inline Range closed(double lo, double hi) { return {lo, hi, false, false}; }
inline Range open(double lo, double hi) { return {lo, hi, true, true}; }
inline Range atLeast(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
inline Range above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, false}; }

template <class Options>
struct Key
{
	std::string name;
	Kind kind = Kind::Number;
	Level level = Level::Expert;
	std::string unit;  ///< of the value as written ("m", "deg", "s", ""), stored in SI (rad for deg)
	Range range;	   ///< Number and Integer
	std::string doc;   ///< one line: what it does, and what 0 means where 0 switches it off
	std::vector<std::string> words;	 ///< Word: the values it takes
	std::vector<std::string> aliases;  ///< older names still read (with a note)
	/** Number, Integer, Bool (1/0): the value in the key's own unit. */
	std::function<double(const Options&)> get;
	std::function<void(Options&, double)> set;
	/** Word. */
	std::function<std::string(const Options&)> getWord;
	std::function<void(Options&, const std::string&)> setWord;
};

// ---- Describing keys. `field` is a generic lambda returning a reference to the member, e.g.
// [](auto& o) -> auto& { return o.sigma; }, so one accessor serves reading and writing.

template <class O, class F>
Key<O> number(std::string name, std::string unit, Range r, Level level, std::string doc, F field)
{
	Key<O> k{std::move(name), Kind::Number, level, std::move(unit), r, std::move(doc), {}, {}, {}, {}, {}, {}};
	k.get = [field](const O& o) { return static_cast<double>(field(o)); };
	k.set = [field](O& o, double v) { field(o) = v; };
	return k;
}

/** An angle written in degrees and kept in radians. */
template <class O, class F>
Key<O> degrees(std::string name, Range r, Level level, std::string doc, F field)
{
	Key<O> k{std::move(name), Kind::Number, level, "deg", r, std::move(doc), {}, {}, {}, {}, {}, {}};
	k.get = [field](const O& o) { return mrpt::RAD2DEG(static_cast<double>(field(o))); };
	k.set = [field](O& o, double v) { field(o) = mrpt::DEG2RAD(v); };
	return k;
}

template <class O, class F>
Key<O> count(std::string name, std::string unit, Range r, Level level, std::string doc, F field)
{
	Key<O> k{std::move(name), Kind::Integer, level, std::move(unit), r, std::move(doc), {}, {}, {}, {}, {}, {}};
	k.get = [field](const O& o) { return static_cast<double>(field(o)); };
	k.set = [field](O& o, double v) { field(o) = static_cast<std::remove_reference_t<decltype(field(o))>>(v); };
	return k;
}

template <class O, class F>
Key<O> flag(std::string name, Level level, std::string doc, F field)
{
	Key<O> k{std::move(name), Kind::Bool, level, "", {}, std::move(doc), {}, {}, {}, {}, {}, {}};
	k.get = [field](const O& o) { return field(o) ? 1.0 : 0.0; };
	k.set = [field](O& o, double v) { field(o) = v != 0; };
	return k;
}

/** A word key over an enum: `toText` and `fromText` convert; `words` lists what it takes. */
template <class O, class F, class ToText, class FromText>
Key<O> word(std::string name, std::vector<std::string> words, Level level, std::string doc, F field, ToText toText,
			FromText fromText)
{
	Key<O> k{std::move(name), Kind::Word, level, "", {}, std::move(doc), std::move(words), {}, {}, {}, {}, {}};
	k.getWord = [field, toText](const O& o) { return std::string(toText(field(o))); };
	k.setWord = [field, fromText](O& o, const std::string& v) { field(o) = fromText(v); };
	return k;
}

template <class O>
Key<O> withAliases(Key<O> k, std::vector<std::string> aliases)
{
	k.aliases = std::move(aliases);
	return k;
}

/** The keys of an inner struct as keys of the outer one (`part` returns the member: a generic lambda). */
template <class Outer, class Inner, class Part>
std::vector<Key<Outer>> lift(const std::vector<Key<Inner>>& keys, Part part)
{
	std::vector<Key<Outer>> out;
	for (const auto& k : keys)
	{
		Key<Outer> o{k.name, k.kind, k.level, k.unit, k.range, k.doc, k.words, k.aliases, {}, {}, {}, {}};
		if (k.get) o.get = [g = k.get, part](const Outer& x) { return g(part(x)); };
		if (k.set) o.set = [s = k.set, part](Outer& x, double v) { s(part(x), v); };
		if (k.getWord) o.getWord = [g = k.getWord, part](const Outer& x) { return g(part(x)); };
		if (k.setWord) o.setWord = [s = k.setWord, part](Outer& x, const std::string& v) { s(part(x), v); };
		out.push_back(std::move(o));
	}
	return out;
}

// ---- Using them.

/** The text of `v` as a key of kind `kind` would take it: shortest round trip, no exponent for
 * everyday numbers ("0.055", "2", "1e-06"). */
std::string formatValue(Kind kind, double v);

/** Checks `text` against the key's kind (and range, words); returns "" when valid, else what was
 * expected ("a number", "a value in 0..1 m", "one of RPROP, GaussNewton"). */
std::string checkValue(Kind kind, const Range& range, const std::string& unit, const std::vector<std::string>& words,
					   const std::string& text);
double parseValue(Kind kind, const std::string& text);	// valid text only

/** The key's value in `o`, as INI text. */
template <class O>
std::string valueText(const Key<O>& k, const O& o)
{
	return k.kind == Kind::Word ? k.getWord(o) : formatValue(k.kind, k.get(o));
}

/** The value of key `name` (or an alias) in `section`, if given ("" and false otherwise). */
bool findValue(const mrpt::config::CConfigFileBase& c, const std::string& section, const std::string& name,
			   const std::vector<std::string>& aliases, std::string& text);

/** Reads every key of `keys` present in `section` into `o`, checked; an absent key keeps the
 * struct's value (read back through its unit, as MRPT's read_double(default) does). Throws
 * std::invalid_argument "[section] key = 'text': expected ...". */
template <class O>
void load(const std::vector<Key<O>>& keys, O& o, const mrpt::config::CConfigFileBase& c, const std::string& section)
{
	for (const auto& k : keys)
	{
		std::string text;
		const bool given = findValue(c, section, k.name, k.aliases, text);
		if (given)
			if (const auto wrong = checkValue(k.kind, k.range, k.unit, k.words, text); !wrong.empty())
				throw std::invalid_argument("[" + section + "] " + k.name + " = '" + text + "': expected " + wrong);
		if (k.kind == Kind::Word)
		{
			if (given) k.setWord(o, text);
		}
		else
			k.set(o, given ? parseValue(k.kind, text) : k.get(o));
	}
}

/** "name = value" per key, one a line. */
template <class O>
void dump(const std::vector<Key<O>>& keys, const O& o, std::ostream& out)
{
	for (const auto& k : keys) out << k.name << " = " << valueText(k, o) << "\n";
}

}  // namespace pmslam::config
