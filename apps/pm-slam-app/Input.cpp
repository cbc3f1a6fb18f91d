/* pm-slam-app — where the scans come from (see Input.h). */
#include "Input.h"

#include <pmslam/live/LiveReader.h>

#include <stdexcept>

#include "StopSignal.h"

#include "../common/Message.h"

namespace pmslam_app
{
Input::Input() = default;
Input::~Input() = default;

void Input::open(const Options& options, const pmslam::LogReaderOptions& readerOptions)
{
	if (options.isLive())
		openLive(options, readerOptions);
	else if (!options.follow.empty())
	{
		pmslam::LogReaderOptions opts = readerOptions;
		opts.follow = true;
		opts.followTimeout = options.followTimeout;
		opts.stopRequested = [] { return stopRequested(); };
		m_reader = pmslam::LogReader::open(options.follow, opts);
	}
	else
		m_reader = pmslam::LogReader::open(options.log, readerOptions);
}

void Input::openLive(const Options& options, const pmslam::LogReaderOptions& readerOptions)
{
	m_pending = std::make_unique<pmslam::PendingObservations>(options.maxPending);
	if (!options.record.empty()) startRecording(options.record);
	try
	{
		m_sensors = std::make_unique<LiveSensors>(options.live, *m_pending, options.connectTimeout, 2.0);
	}
	catch (const std::exception&)
	{
		if (m_recorder) m_recorder->abandon();
		throw;
	}
	// A live reader sees Ctrl-C itself: it stops the sensors, then hands over what they had delivered.
	m_reader = std::make_unique<pmslam::LiveReader>(
		options.live, *m_pending, [] { return stopRequested(); }, [this] { m_sensors->stop(); }, readerOptions);
}

void Input::startRecording(const std::string& path)
{
	try
	{
		m_recorder = std::make_unique<pmslam::RawlogRecorder>(path);
	}
	catch (const std::exception& e)
	{
		throw std::runtime_error("--record " + path + ": " + withoutLibraryPrefix(e.what()));
	}
	m_recordPath = path;
	m_pending->onReceived = [this, path](const mrpt::serialization::CSerializable::Ptr& obj) {
		if (m_recordFailed) return;
		try
		{
			m_recorder->write(*obj);
		}
		catch (const std::exception& e)
		{  // the SLAM goes on; the recording stops, loudly
			m_recordFailed = true;
			m_pending->note("--record " + path + ": writing failed (" + withoutLibraryPrefix(e.what()) + "): the recording stops here");
		}
	};
}

std::size_t Input::finish()
{
	const std::size_t stuck = m_sensors ? m_sensors->stop() : 0;
	if (stuck)
		say("warning: " + std::to_string(stuck) + " sensor thread(s) did not return from their driver within 3 s of the stop");
	if (m_recorder)
	{
		try
		{
			m_recorder->close();
		}
		catch (const std::exception& e)
		{
			say("--record " + m_recordPath + ": " + withoutLibraryPrefix(e.what()));
			m_recordFailed = true;
		}
	}
	return stuck;
}

}  // namespace pmslam_app
