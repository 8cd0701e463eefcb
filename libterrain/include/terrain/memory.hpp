#pragma once
// How much memory a run may take (no GDAL here: the renderer uses it too).
#include <string>

namespace terrain {

// Memory this process can take now, in bytes: MemAvailable of /proc/meminfo (what Linux
// can give without swapping), else the physical memory; 0 when neither is known. The
// environment's TERRAIN_MEMORY_MIB caps it: a number of MiB from 1 to kMaxMemoryMib (Error
// otherwise).
inline constexpr double kMaxMemoryMib = 1073741824.0;  // 1 PiB
double available_memory();

// A size for messages: "12 KiB", "3.4 MiB", "1.2 GiB".
std::string bytes_text(double bytes);

// Throws Error "WHAT needs N GiB, more than this machine's memory available now (M GiB);
// ADVICE" when `bytes` exceed available_memory(). Tools call it with every buffer a run
// will hold counted, before they read anything large.
void check_memory(double bytes, const std::string& what, const std::string& advice);

}  // namespace terrain
