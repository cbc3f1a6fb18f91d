// PendingObservations: arrival order, drop-oldest against a model, the recording hook, and a slow consumer.
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <gtest/gtest.h>
#include <pmslam/live/PendingObservations.h>

#include <atomic>
#include <deque>
#include <random>
#include <thread>

using mrpt::serialization::CSerializable;

namespace
{
// Each object carries its sequence number in the timestamp, so order and identity can be checked.
CSerializable::Ptr scan(int id)
{
	auto s = mrpt::obs::CObservation2DRangeScan::Create();
	s->timestamp = mrpt::Clock::fromDouble(id);
	return s;
}
CSerializable::Ptr odometry(int id)
{
	auto o = mrpt::obs::CObservationOdometry::Create();
	o->timestamp = mrpt::Clock::fromDouble(id);
	return o;
}
int idOf(const CSerializable::Ptr& p)
{
	return int(std::lround(mrpt::Clock::toDouble(std::dynamic_pointer_cast<mrpt::obs::CObservation>(p)->timestamp)));
}
bool isScan(const CSerializable::Ptr& p) { return bool(std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(p)); }
}  // namespace

TEST(PendingObservations, DropsTheOldestScansAsAModelQueueDoes)
{
	// Random interleavings of pushes (scans, odometry) and pops against a plain model of the rule.
	std::mt19937 rng(7);
	for (int trial = 0; trial < 50; ++trial)
	{
		const std::size_t cap = 1 + rng() % 5;
		pmslam::PendingObservations q(cap);
		std::vector<int> recorded;
		q.onReceived = [&](const CSerializable::Ptr& p) { recorded.push_back(idOf(p)); };
		std::deque<std::pair<int, bool>> model;
		std::size_t dropped = 0, scans = 0;
		std::vector<int> pushed;
		for (int id = 0; id < 300; ++id)
		{
			const int op = int(rng() % 10);
			if (op < 5)
			{
				const bool sc = op < 4;
				q.push(sc ? scan(id) : odometry(id));
				pushed.push_back(id);
				if (sc)
				{
					++scans;
					std::size_t pendingScans = 0;
					for (const auto& e : model) pendingScans += e.second;
					if (pendingScans >= cap)
					{
						for (auto it = model.begin(); it != model.end(); ++it)
							if (it->second)
							{
								model.erase(it);
								break;
							}
						++dropped;
					}
				}
				model.emplace_back(id, sc);
			}
			else
			{
				CSerializable::Ptr got;
				const bool ok = q.pop(got, std::chrono::milliseconds(0));
				ASSERT_EQ(ok, !model.empty());
				if (!ok) continue;
				EXPECT_EQ(idOf(got), model.front().first);
				EXPECT_EQ(isScan(got), model.front().second);
				model.pop_front();
			}
		}
		const auto c = q.counts();
		EXPECT_EQ(c.received, pushed.size());
		EXPECT_EQ(c.scans, scans);
		EXPECT_EQ(c.droppedScans, dropped);
		EXPECT_EQ(c.pending, model.size());
		EXPECT_EQ(recorded, pushed);  // everything received is recorded, dropped or not, in arrival order
	}
}

TEST(PendingObservations, AFastSensorAndASlowConsumerNeverQueueMoreThanTheBound)
{
	pmslam::PendingObservations q(4);
	std::atomic<bool> done{false};
	std::thread sensor([&] {
		for (int id = 0; id < 2000; ++id)
		{
			q.push(scan(id));
			if (id % 50 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
		}
		done = true;
		q.close();
	});
	std::size_t taken = 0, maxPending = 0;
	int last = -1;
	CSerializable::Ptr got;
	while (q.pop(got, std::chrono::milliseconds(500)))
	{
		++taken;
		EXPECT_GT(idOf(got), last);	 // oldest first, never out of order
		last = idOf(got);
		maxPending = std::max(maxPending, q.counts().pending);
		std::this_thread::sleep_for(std::chrono::microseconds(300));  // slower than the sensor
	}
	sensor.join();
	const auto c = q.counts();
	EXPECT_TRUE(done);
	EXPECT_LE(maxPending, 4u);
	EXPECT_GT(c.droppedScans, 0u);
	EXPECT_EQ(taken + c.droppedScans, 2000u);
	EXPECT_EQ(last, 1999);	// the newest scan is never the one dropped
}

TEST(PendingObservations, CloseEndsAWaitingConsumerAndNotesArriveOnce)
{
	pmslam::PendingObservations q(2);
	q.note("sensor [A]: connection lost");
	std::thread closer([&] {
		std::this_thread::sleep_for(std::chrono::milliseconds(50));
		q.close();
	});
	CSerializable::Ptr got;
	const auto t0 = std::chrono::steady_clock::now();
	EXPECT_FALSE(q.pop(got, std::chrono::seconds(10)));
	EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
	closer.join();
	EXPECT_EQ(q.takeNotes(), std::vector<std::string>{"sensor [A]: connection lost"});
	EXPECT_TRUE(q.takeNotes().empty());
}
