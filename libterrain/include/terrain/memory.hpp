#pragma once
// How much memory a run may take (no GDAL here: the renderer uses it too).
#include <string>

namespace terrain {

// Memory this process can take now, in bytes: MemAvailable of /proc/meminfo (what Linux
// can give without swapping), else the physical memory; 0 when neither is known.
double available_memory();

// Throws Error "WHAT needs N GiB, more than this machine's memory available now (M GiB);
// ADVICE" when `bytes` exceed available_memory(). Tools call it with every buffer a run
// will hold counted, before they read anything large.
void check_memory(double bytes, const std::string& what, const std::string& advice);

}  // namespace terrain
