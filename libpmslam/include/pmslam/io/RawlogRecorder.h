/* pmslam — Perfect Match 2D laser SLAM on MRPT.
 *
 * RawlogRecorder (--record): every object a live run received, written as
 * rawlog-grabber writes them — a gz-compressed, observation-only .rawlog, one
 * serialised object after another — so MRPT's tools and pm-slam-app read it
 * back. The file grows as FILE.part and is renamed to FILE by close(): a
 * reader never takes a half-written recording for a whole one, and after a
 * crash FILE.part holds everything up to it (readable up to the damage).
 */
#pragma once

#include <mrpt/serialization/CSerializable.h>

#include <cstddef>
#include <memory>
#include <string>

namespace pmslam
{
class RawlogRecorder
{
   public:
	/** Throws std::runtime_error naming the file if it cannot be created. */
	explicit RawlogRecorder(const std::string& path);
	~RawlogRecorder();	///< closes (renames) if close() was not called
	RawlogRecorder(const RawlogRecorder&) = delete;
	RawlogRecorder& operator=(const RawlogRecorder&) = delete;

	void write(const mrpt::serialization::CSerializable& obj);
	/** Finishes the file and renames FILE.part to FILE; throws on failure. */
	void close();
	/** Gives up: closes and deletes FILE.part (a run that never started). */
	void abandon();
	std::size_t objects() const { return m_objects; }
	const std::string& path() const { return m_path; }

   private:
	bool finishStream();  ///< closes the stream; false if it was closed already
	struct Impl;
	std::unique_ptr<Impl> m_impl;
	std::string m_path;
	std::size_t m_objects = 0;
};

}  // namespace pmslam
