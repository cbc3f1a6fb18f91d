/* pmslam — compact keyframe store (see KeyframeStore.h). */
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>
#include <pmslam/slam/KeyframeStore.h>
#include <pmslam/io/MapExport.h>

#include <stdexcept>

namespace pmslam
{
bool KeyframeStore::Geometry::sameAs(const mrpt::obs::CObservation2DRangeScan& s) const
{
	return aperture == s.aperture && maxRange == s.maxRange && stdError == s.stdError &&
		   beamAperture == s.beamAperture && deltaPitch == s.deltaPitch && rightToLeft == s.rightToLeft &&
		   sensorPose == s.sensorPose && sensorLabel == s.sensorLabel;
}

void KeyframeStore::add(const mrpt::math::TPose2D& pose, const mrpt::obs::CObservation2DRangeScan& scan)
{
	if (m_geometries.empty() || !m_geometries.back().sameAs(scan))
	{
		Geometry g;
		g.aperture = scan.aperture;
		g.maxRange = scan.maxRange;
		g.stdError = scan.stdError;
		g.beamAperture = scan.beamAperture;
		g.deltaPitch = scan.deltaPitch;
		g.rightToLeft = scan.rightToLeft;
		g.sensorPose = scan.sensorPose;
		g.sensorLabel = scan.sensorLabel;
		m_geometries.push_back(std::move(g));
	}
	Frame f;
	f.pose = pose;
	f.stamp = scan.timestamp;
	f.geometry = static_cast<uint32_t>(m_geometries.size() - 1);
	f.beams = static_cast<uint32_t>(scan.getScanSize());
	f.first = m_ranges.size();
	f.firstIntensity = -1;
	for (std::size_t i = 0; i < f.beams; ++i)
	{
		m_ranges.push_back(scan.getScanRange(i));
		m_valid.push_back(scan.getScanRangeValidity(i) ? 1 : 0);
	}
	if (scan.hasIntensity())
	{
		f.firstIntensity = static_cast<int64_t>(m_intensity.size());
		for (std::size_t i = 0; i < f.beams; ++i) m_intensity.push_back(scan.getScanIntensity(i));
	}
	m_frames.push_back(f);
}

void KeyframeStore::clear()
{
	m_geometries.clear();
	m_frames.clear();
	m_ranges.clear();
	m_valid.clear();
	m_intensity.clear();
}

mrpt::obs::CObservation2DRangeScan::Ptr KeyframeStore::scan(std::size_t i) const
{
	const Frame& f = m_frames.at(i);
	const Geometry& g = m_geometries[f.geometry];
	auto s = mrpt::obs::CObservation2DRangeScan::Create();
	s->aperture = g.aperture;
	s->maxRange = g.maxRange;
	s->stdError = g.stdError;
	s->beamAperture = g.beamAperture;
	s->deltaPitch = g.deltaPitch;
	s->rightToLeft = g.rightToLeft;
	s->sensorPose = g.sensorPose;
	s->sensorLabel = g.sensorLabel;
	s->timestamp = f.stamp;
	s->resizeScan(f.beams);
	for (std::size_t k = 0; k < f.beams; ++k)
	{
		s->setScanRange(k, m_ranges[f.first + k]);
		s->setScanRangeValidity(k, m_valid[f.first + k] != 0);
	}
	if (f.firstIntensity >= 0)
	{
		s->setScanHasIntensity(true);
		for (std::size_t k = 0; k < f.beams; ++k)
			s->setScanIntensity(k, m_intensity[static_cast<std::size_t>(f.firstIntensity) + k]);
	}
	return s;
}

namespace
{
mrpt::poses::CPose3DPDFGaussian::Ptr gaussianAt(const mrpt::math::TPose2D& p)
{
	auto pdf = mrpt::poses::CPose3DPDFGaussian::Create();
	pdf->mean = mrpt::poses::CPose3D(mrpt::poses::CPose2D(p));
	return pdf;
}

mrpt::obs::CSensoryFrame::Ptr frameWith(const mrpt::obs::CObservation2DRangeScan::Ptr& scan)
{
	auto sf = mrpt::obs::CSensoryFrame::Create();
	sf->insert(scan);
	return sf;
}

// Writes a CSimpleMap without building one: MRPT's archive writes the class header
// (name "CSimpleMap", this class's serialisation version) and then calls serializeTo(),
// which is replaced here by the same sequence of (pose PDF, sensory frame) objects that
// CSimpleMap::serializeTo() writes from memory, made one at a time.
class StreamedSimpleMap : public mrpt::maps::CSimpleMap
{
   public:
	StreamedSimpleMap(const mrpt::maps::CSimpleMap& prefix, const KeyframeStore& store)
		: m_prefix(prefix), m_store(store)
	{
	}

   protected:
	void serializeTo(mrpt::serialization::CArchive& out) const override
	{
		out.WriteAs<uint32_t>(m_prefix.size() + m_store.size());
		for (const auto& [pose, sf] : m_prefix)
		{
			if (!pose || !sf) throw std::runtime_error("saveSimpleMapGz: a prefix keyframe is empty");
			out << *pose << *sf;
		}
		for (std::size_t i = 0; i < m_store.size(); ++i)
			out << *gaussianAt(m_store.pose(i)) << *frameWith(m_store.scan(i));
	}

   private:
	const mrpt::maps::CSimpleMap& m_prefix;
	const KeyframeStore& m_store;
};
}  // namespace

mrpt::maps::CSimpleMap KeyframeStore::toSimpleMap(const mrpt::maps::CSimpleMap& prefix) const
{
	mrpt::maps::CSimpleMap out = prefix;
	for (std::size_t i = 0; i < m_frames.size(); ++i) out.insert(gaussianAt(m_frames[i].pose), frameWith(scan(i)));
	return out;
}

void KeyframeStore::saveSimpleMapGz(const std::string& path, const mrpt::maps::CSimpleMap& prefix) const
{
	pmslam::saveSimpleMapGz(StreamedSimpleMap(prefix, *this), path);
}

std::size_t KeyframeStore::memoryBytes() const
{
	std::size_t b = m_frames.capacity() * sizeof(Frame) + m_ranges.size() * sizeof(float) + m_valid.size() +
					m_intensity.size() * sizeof(int32_t);
	for (const auto& g : m_geometries) b += sizeof(Geometry) + g.sensorLabel.capacity();
	return b;
}

}  // namespace pmslam
