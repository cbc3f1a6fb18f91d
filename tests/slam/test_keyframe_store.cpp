// KeyframeStore: keyframes kept compactly come back as the very scans that went in, and the
// streamed .simplemap.gz is byte for byte what MRPT writes for the same CSimpleMap.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/slam/KeyframeStore.h>

#include <fstream>
#include <iterator>

#include "SyntheticLogs.h"

using mrpt::obs::CObservation2DRangeScan;

namespace
{
CObservation2DRangeScan makeScan(std::size_t beams, double aperture, bool intensities, const std::string& label,
								 mrpt::random::CRandomGenerator& rng, int stamp)
{
	CObservation2DRangeScan s;
	s.aperture = static_cast<float>(aperture);
	s.maxRange = 30.f;
	s.stdError = 0.01f;
	s.rightToLeft = beams % 2 == 0;
	s.sensorPose = mrpt::poses::CPose3D(0.1, -0.05, 0.3, 0.02, 0, 0);
	s.sensorLabel = label;
	s.timestamp = mrpt::Clock::fromDouble(1000.0 + stamp * 0.1);
	s.resizeScan(beams);
	for (std::size_t i = 0; i < beams; ++i)
	{
		s.setScanRange(i, static_cast<float>(rng.drawUniform(0.1, 35.0)));
		s.setScanRangeValidity(i, rng.drawUniform(0.0, 1.0) > 0.2);
	}
	if (intensities)
	{
		s.setScanHasIntensity(true);
		for (std::size_t i = 0; i < beams; ++i) s.setScanIntensity(i, static_cast<int>(rng.drawUniform(0.0, 4000.0)));
	}
	return s;
}

std::string gunzip(const std::string& path)
{
	mrpt::io::CFileGZInputStream in(path);
	std::string bytes;
	char buf[4096];
	for (std::size_t n; (n = in.Read(buf, sizeof buf)) > 0;) bytes.append(buf, n);
	return bytes;
}

// Three sensors' worth of scans (the geometry changes between runs of scans) and random poses.
pmslam::KeyframeStore makeStore(std::vector<CObservation2DRangeScan>& scans, std::vector<mrpt::math::TPose2D>& poses)
{
	mrpt::random::CRandomGenerator rng(7);
	pmslam::KeyframeStore store;
	for (int k = 0; k < 30; ++k)
	{
		const bool second = (k / 10) % 2 == 1;
		scans.push_back(makeScan(second ? 361 : 180, second ? 2 * M_PI : M_PI, second, second ? "LMS" : "FLASER", rng, k));
		poses.emplace_back(rng.drawUniform(-50.0, 50.0), rng.drawUniform(-50.0, 50.0), rng.drawUniform(-3.1, 3.1));
		store.add(poses.back(), scans.back());
	}
	return store;
}
}  // namespace

TEST(KeyframeStore, ScansComeBackExactly)
{
	std::vector<CObservation2DRangeScan> scans;
	std::vector<mrpt::math::TPose2D> poses;
	const pmslam::KeyframeStore store = makeStore(scans, poses);
	ASSERT_EQ(store.size(), scans.size());
	for (std::size_t i = 0; i < scans.size(); ++i)
	{
		const auto back = store.scan(i);
		const auto& in = scans[i];
		EXPECT_EQ(store.pose(i).x, poses[i].x);
		EXPECT_EQ(store.pose(i).phi, poses[i].phi);
		ASSERT_EQ(back->getScanSize(), in.getScanSize());
		EXPECT_EQ(back->aperture, in.aperture);
		EXPECT_EQ(back->rightToLeft, in.rightToLeft);
		EXPECT_EQ(back->maxRange, in.maxRange);
		EXPECT_EQ(back->stdError, in.stdError);
		EXPECT_EQ(back->sensorPose, in.sensorPose);
		EXPECT_EQ(back->sensorLabel, in.sensorLabel);
		EXPECT_EQ(back->timestamp, in.timestamp);
		EXPECT_EQ(back->hasIntensity(), in.hasIntensity());
		for (std::size_t b = 0; b < in.getScanSize(); ++b)
		{
			ASSERT_EQ(back->getScanRange(b), in.getScanRange(b)) << "scan " << i << " beam " << b;
			ASSERT_EQ(back->getScanRangeValidity(b), in.getScanRangeValidity(b));
			if (in.hasIntensity()) { ASSERT_EQ(back->getScanIntensity(b), in.getScanIntensity(b)); }
		}
	}
	// Compact: well under the ~3.8 KB per 180-beam keyframe of a CSimpleMap.
	EXPECT_LT(store.memoryBytes(), scans.size() * 2600);
}

TEST(KeyframeStore, StreamedSimpleMapIsWhatMrptWrites)
{
	std::vector<CObservation2DRangeScan> scans;
	std::vector<mrpt::math::TPose2D> poses;
	const pmslam::KeyframeStore store = makeStore(scans, poses);

	// A prefix (an initial map given to the builder) goes first, as it was.
	mrpt::maps::CSimpleMap prefix;
	{
		auto sf = mrpt::obs::CSensoryFrame::Create();
		sf->insert(CObservation2DRangeScan::Create(scans.front()));
		auto pdf = mrpt::poses::CPose3DPDFGaussian::Create();
		pdf->mean = mrpt::poses::CPose3D(1, 2, 0, 0.5, 0, 0);
		prefix.insert(pdf, sf);
	}
	pmslam::testing::ScratchDir dir("keyframe-store");
	const std::string streamed = dir.path("streamed.simplemap.gz"), reference = dir.path("reference.simplemap.gz");
	store.saveSimpleMapGz(streamed, prefix);
	{
		mrpt::io::CFileGZOutputStream f(reference);
		mrpt::serialization::archiveFrom(f) << store.toSimpleMap(prefix);
	}
	const std::string a = gunzip(streamed), b = gunzip(reference);
	ASSERT_GT(a.size(), 30 * 180 * 4u);
	EXPECT_TRUE(a == b) << "streamed " << a.size() << " bytes, MRPT " << b.size() << " bytes";

	// And MRPT reads it back as the same keyframes.
	mrpt::maps::CSimpleMap reloaded;
	{
		mrpt::io::CFileGZInputStream f(streamed);
		mrpt::serialization::archiveFrom(f) >> reloaded;
	}
	ASSERT_EQ(reloaded.size(), scans.size() + 1);
	for (std::size_t i = 0; i < scans.size(); ++i)
	{
		const auto& [pdf, sf] = reloaded.get(i + 1);
		const auto mean = mrpt::poses::CPose2D(pdf->getMeanVal());
		EXPECT_NEAR(mean.x(), poses[i].x, 1e-12);
		EXPECT_NEAR(mean.phi(), poses[i].phi, 1e-12);
		const auto obs = sf->getObservationByClass<CObservation2DRangeScan>();
		ASSERT_TRUE(obs);
		EXPECT_EQ(obs->getScanSize(), scans[i].getScanSize());
		EXPECT_EQ(obs->getScanRange(17), scans[i].getScanRange(17));
	}
	// No temporary file is left behind.
	std::size_t files = 0;
	for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.dir)) ++files;
	EXPECT_EQ(files, 2u);
}

TEST(KeyframeStore, FailedSaveLeavesNoFile)
{
	std::vector<CObservation2DRangeScan> scans;
	std::vector<mrpt::math::TPose2D> poses;
	const pmslam::KeyframeStore store = makeStore(scans, poses);
	EXPECT_THROW(store.saveSimpleMapGz("/nonexistent-dir/x.simplemap.gz"), std::runtime_error);
}
