// pm-relation-check on a synthetic Carmen log with exact odometry: exact reference relations
// are confirmed by scan matching; references pushed 4 cm along the track are exposed, and the
// push shows up as the component odometry and matching share.
#include <gtest/gtest.h>
#include <mrpt/poses/CPose2D.h>

#include <fstream>
#include <random>
#include <sstream>

#include "RunProgram.h"
#include "SyntheticLogs.h"

namespace
{
using namespace pmslam::testing;
using mrpt::poses::CPose2D;
const std::string kTool = PMSLAM_BINARY_DIR "/bin/pm-relation-check";

// Value of summary line "#   NAME along / across" (along if !across).
double summary(const std::string& out, const std::string& name, bool across = false)
{
	std::istringstream in(out);
	std::string line;
	while (std::getline(in, line))
	{
		const auto p = line.find("#   " + name + " ");
		if (p == std::string::npos) continue;
		std::istringstream f(line.substr(p + 4 + name.size()));
		double along = NAN, cross = NAN;
		std::string slash;
		f >> along >> slash >> cross;
		return across ? cross : along;
	}
	return NAN;
}
}  // namespace

TEST(RelationCheck, ExposesReferenceErrorsThatOdometryAndScansDoNotShare)
{
	ScratchDir dir("relation-check");
	const auto world = furnishedRoom();
	const auto truth = roomPath(120);
	CarmenLogSpec spec;
	const auto log = dir.dir / "room.clf";
	std::ofstream(log) << carmenLog(world, truth, truth, spec);

	std::mt19937 rng(7);
	for (const double push : {0.0, 0.04})
	{
		const auto rel = dir.dir / "room.relations";
		{
			std::ofstream out(rel);
			for (std::size_t k = 0; k + 1 < truth.size(); ++k)
			{
				CPose2D d = CPose2D(truth[k + 1]) - CPose2D(truth[k]);
				// Push the reference along the track by ±push (random sign).
				const double s = (rng() % 2 ? 1.0 : -1.0) * push, len = std::hypot(d.x(), d.y());
				if (len > 0) d = CPose2D(d.x() + s * d.x() / len, d.y() + s * d.y() / len, d.phi());
				out << fmt(spec.t0 + spec.dt * k) << " " << fmt(spec.t0 + spec.dt * (k + 1)) << " " << fmt(d.x()) << " "
					<< fmt(d.y()) << " 0 0 0 " << fmt(d.phi()) << "\n";
			}
		}
		const auto r = run(quote(kTool) + " " + quote(log.string()) + " " + quote(rel.string()));
		ASSERT_EQ(r.exitCode, 0) << r.output;
		const double match = summary(r.output, "match"), shared = summary(r.output, "match-odometry");
		if (push == 0)
		{
			EXPECT_LT(match, 0.01) << r.output;
			EXPECT_LT(std::abs(shared), 0.01) << r.output;
		}
		else
		{
			// Scan matching walks back from the pushed reference, odometry disagrees with it by the
			// push: what they share is the reference's own error.
			EXPECT_GT(match, 0.03) << r.output;
			EXPECT_NEAR(shared, push, 0.01) << r.output;
		}
	}
	EXPECT_EQ(run(quote(kTool) + " only-one-argument").exitCode, 2);
}
