/* pmslam — trajectory text files (see Trajectory.h). */
#include <pmslam/io/AtomicFile.h>
#include <pmslam/io/Trajectory.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "TextParsing.h"

namespace pmslam
{
void saveTrajectory(const std::string& path, const Trajectory& trajectory, const std::string& headerComment)
{
	for (std::size_t i = 0; i < trajectory.size(); ++i)
	{
		const TimedPose2D& p = trajectory[i];
		if (!std::isfinite(p.timestamp) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.yaw))
			throw std::invalid_argument("saveTrajectory('" + path + "'): pose " + std::to_string(i) +
										" has a non-finite value");
	}
	writeFileAtomically(path, [&](std::ostream& os) {
		if (!headerComment.empty())
		{
			std::istringstream lines(headerComment);
			std::string l;
			while (std::getline(lines, l)) os << "# " << l << '\n';
		}
		os << "# timestamp x y yaw\n";
		char buf[160];
		for (const TimedPose2D& p : trajectory)
		{
			const int n = std::snprintf(buf, sizeof(buf), "%.6f %.6f %.6f %.8f\n", p.timestamp, p.x, p.y, p.yaw);
			os.write(buf, n);
		}
	});
}

Trajectory loadTrajectory(const std::string& path)
{
	std::ifstream in(path);
	if (!in)
	{
		const int err = errno;
		throw std::runtime_error(path + ": cannot open: " + std::strerror(err));
	}
	Trajectory out;
	std::string line;
	std::size_t lineNo = 0;
	while (std::getline(in, line))
	{
		++lineNo;
		if (detail::isCommentOrBlank(line)) continue;
		double v[4];
		if (!detail::parseNumbers(line, v, 4))
			throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": expected 'timestamp x y yaw', got " +
									 detail::quoteForError(line));
		out.push_back(TimedPose2D{v[0], v[1], v[2], v[3]});
	}
	if (in.bad()) throw std::runtime_error(path + ": read error");
	return out;
}

}  // namespace pmslam
