/* pmslam — giving back the library pages only start-up needed.
 *
 * Debian's MRPT 2.5 libraries pull in ~170 shared libraries (OpenCV, GDAL, assimp, …)
 * and are linked with BIND_NOW: before main() the dynamic linker reads the symbol and
 * relocation tables of all of them, and their static constructors run. About 50 MB of
 * file pages end up in the resident set that the mapping never reads again. They are
 * clean copies of the files (the kernel could drop them under pressure anyway), but
 * they count in the process's RSS, which is what a user's `top`, a container limit or
 * a robot's watchdog looks at.
 */
#pragma once

namespace pmslam
{
/** Unmaps from this process's resident set the pages of read-only file mappings that
 * hold no private (written) page: the code and tables of the shared libraries and of
 * the program. They stay in the page cache, and whatever code runs later is faulted
 * back in from there (a minor fault per page, once). Writable mappings and every
 * page the loader relocated are left alone. Returns the MiB released (0 where
 * /proc/self/smaps is unavailable). Call it once start-up is over, before the work. */
double releaseStartupLibraryPages();

}  // namespace pmslam
