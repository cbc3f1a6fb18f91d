// OdometrySelector: [Log] odometrySource applied to a log's events, the same for every program.
#include <gtest/gtest.h>
#include <pmslam/slam/OdometrySelector.h>

using pmslam::LogEvent;
using pmslam::OdometrySelector;
using pmslam::OdometrySource;

namespace
{
LogEvent reading(double x)
{
	LogEvent e;
	e.kind = LogEvent::Kind::Odometry;
	e.odometry = {x, 0, 0};
	return e;
}

LogEvent scan(bool withOdometry, double x = 0)
{
	LogEvent e;
	e.kind = LogEvent::Kind::Scan;
	e.scanHasOdometry = withOdometry;
	e.scanOdometry = {x, 0, 0};
	return e;
}
}  // namespace

TEST(OdometrySelector, AutoPrefersTheScansOwnOdometryElseTheLatestReading)
{
	OdometrySelector s(OdometrySource::Auto);
	EXPECT_FALSE(s.forScan(scan(false)));
	EXPECT_TRUE(s.takeReading(reading(1)));
	EXPECT_TRUE(s.takeReading(reading(2)));
	EXPECT_DOUBLE_EQ(s.forScan(scan(false))->x, 2.0);
	EXPECT_DOUBLE_EQ(s.forScan(scan(true, 7))->x, 7.0);
	EXPECT_DOUBLE_EQ(s.scanOdometry(scan(true, 7))->x, 7.0);
	EXPECT_FALSE(s.scanOdometry(scan(false)));
}

TEST(OdometrySelector, ScanIgnoresTheReadings)
{
	OdometrySelector s(OdometrySource::Scan);
	EXPECT_FALSE(s.takeReading(reading(1)));
	EXPECT_FALSE(s.forScan(scan(false)));
	EXPECT_DOUBLE_EQ(s.forScan(scan(true, 7))->x, 7.0);
}

TEST(OdometrySelector, EventsIgnoresTheOdometryOnTheLaserLine)
{
	OdometrySelector s(OdometrySource::Events);
	EXPECT_FALSE(s.scanOdometry(scan(true, 7)));
	EXPECT_FALSE(s.forScan(scan(true, 7)));
	EXPECT_TRUE(s.takeReading(reading(3)));
	EXPECT_DOUBLE_EQ(s.forScan(scan(true, 7))->x, 3.0);
}

TEST(OdometrySelector, NamesAreTheConfigurationsWords)
{
	EXPECT_EQ(pmslam::odometrySourceFromName("auto"), OdometrySource::Auto);
	EXPECT_EQ(pmslam::odometrySourceFromName("scan"), OdometrySource::Scan);
	EXPECT_EQ(pmslam::odometrySourceFromName("events"), OdometrySource::Events);
	EXPECT_THROW(pmslam::odometrySourceFromName("wheels"), std::invalid_argument);
}
