/* pmslam — reads a rawlog once in a child process, ahead of the real reader.
 *
 * MRPT's deserialisers trust the bytes of a rawlog: on damaged input some of them
 * dereference null pointers (CActionRobotMovement2D::serializeFrom) or spin for minutes
 * (its odometry sampling on a damaged particle count). An exception can be caught; a
 * crash or a hang cannot. So a forked child reads the same file object by object with
 * the same MRPT code and reports each object it finished through a pipe. The real reader
 * asks safeToRead(n) before reading object n: objects the child got through are safe (MRPT
 * deserialisation is deterministic), and the first one it did not is where the damage is —
 * the child crashed on it, threw, ran out of memory, or took longer than the time limit.
 * The child runs ahead on the other core, so the reader waits only when it catches up.
 *
 * Without fork() (it failed) every object counts as safe, as without the probe.
 */
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>

namespace pmslam
{
class RawlogProbe
{
   public:
	/** Starts the child on `path`. `objectTimeoutSeconds`: longest the child may spend on
	 * one object before it counts as hung (MRPT reads a sane object in microseconds). */
	RawlogProbe(const std::string& path, double objectTimeoutSeconds);
	~RawlogProbe();	 // stops the child
	RawlogProbe(const RawlogProbe&) = delete;
	RawlogProbe& operator=(const RawlogProbe&) = delete;

	/** Blocks until the child has read object `n` (1-based) or stopped before it.
	 * True: reading object n with MRPT returns (an object, or the exception of a clean
	 * end of file); false: it would not, see failure(). */
	bool safeToRead(std::size_t n);

	/** After safeToRead() returned false: why object n cannot be read, one line
	 * ("MRPT crashed reading it (signal 11, Segmentation fault)", the exception's
	 * text, ...). Empty when the file simply ends there. */
	const std::string& failure() const { return m_failure; }
	/** After safeToRead() returned false: true if the failure is an exception text. */
	bool failedWithException() const { return m_exception; }

   private:
	void readFromChild(int timeoutMs);
	void childStopped(bool hung);
	void stopChild();

	pid_t m_pid = -1;
	int m_fd = -1;	// read end of the pipe
	std::size_t m_done = 0;	 // objects the child finished
	bool m_ended = false;  // the child reported its end, or died, or hung
	bool m_exception = false;
	std::string m_failure;
	std::string m_buffer;  // a partial message from the child
	double m_timeout;
};

}  // namespace pmslam
