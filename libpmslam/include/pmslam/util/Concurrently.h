/* pmslam — independent pieces of work run side by side.
 *
 * The loop-closure back-end's work at a keyframe comes in pieces that do not depend on each
 * other (the local maps of two visits, the two halves of a map patch). Run one after the other
 * they leave the second core idle whenever the front-end waits for the back-end (a log replayed
 * faster than real time); run side by side they finish in about half the time. Each piece writes
 * only its own outputs and reads what no piece writes, so the results do not depend on which
 * finishes first: a run stays repeatable whatever the machine's load.
 */
#pragma once

#include <cstddef>
#include <exception>
#include <future>
#include <vector>

namespace pmslam
{
/** Calls f(0), …, f(n-1): f(0) on the calling thread, the others each on a thread of its own, and
 * returns when every call has returned. The first exception thrown (by index) is rethrown after all
 * have finished. */
template <class F>
void concurrently(std::size_t n, F&& f)
{
	std::vector<std::future<void>> others;
	others.reserve(n > 0 ? n - 1 : 0);
	for (std::size_t i = 1; i < n; ++i) others.push_back(std::async(std::launch::async, [&f, i] { f(i); }));
	std::exception_ptr failure;
	try
	{
		if (n > 0) f(std::size_t(0));
	}
	catch (...)
	{
		failure = std::current_exception();
	}
	for (auto& o : others)
	{
		try
		{
			o.get();
		}
		catch (...)
		{
			if (!failure) failure = std::current_exception();
		}
	}
	if (failure) std::rethrow_exception(failure);
}

}  // namespace pmslam
