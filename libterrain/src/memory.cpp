#include "terrain/memory.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "terrain/error.hpp"

namespace terrain {

namespace {

// Physical memory of this machine in bytes (0 when unknown).
double physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 0.0;
}

}  // namespace

double available_memory() {
  double available = physical_memory();
  if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
    char line[256];
    double kib = -1.0;
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "MemAvailable: %lf kB", &kib) == 1) break;
    std::fclose(f);
    if (kib >= 0.0) available = kib * 1024.0;
  }
  // A container's or batch job's limit (cgroup v2): its room left, when smaller.
  double max = 0.0, current = 0.0;
  if (std::FILE* f = std::fopen("/sys/fs/cgroup/memory.max", "r")) {
    if (std::fscanf(f, "%lf", &max) != 1) max = 0.0;  // "max": no limit
    std::fclose(f);
  }
  if (std::FILE* f = std::fopen("/sys/fs/cgroup/memory.current", "r")) {
    if (std::fscanf(f, "%lf", &current) != 1) current = 0.0;
    std::fclose(f);
  }
  if (max > 0.0 && max - current < available) available = std::max(0.0, max - current);
  // TERRAIN_MEMORY_MIB caps it (a share of a machine others use too; tests).
  if (const char* cap = std::getenv("TERRAIN_MEMORY_MIB")) {
    char* end = nullptr;
    const double mib = std::strtod(cap, &end);
    if (end == cap || *end != '\0' || !(mib >= 1.0 && mib <= kMaxMemoryMib))
      throw Error(fmt::format("TERRAIN_MEMORY_MIB='{}' is not a number of MiB from 1 to {:.0f}",
                              cap, kMaxMemoryMib));
    available = std::min(available > 0.0 ? available : mib * 1048576.0, mib * 1048576.0);
  }
  return available;
}

std::string bytes_text(double bytes) {
  if (bytes >= 1073741824.0) return fmt::format("{:.1f} GiB", bytes / 1073741824.0);
  if (bytes >= 1048576.0) return fmt::format("{:.1f} MiB", bytes / 1048576.0);
  return fmt::format("{:.0f} KiB", std::ceil(bytes / 1024.0));
}

void check_memory(double bytes, const std::string& what, const std::string& advice) {
  const double available = available_memory();
  if (available > 0 && bytes > available)
    throw Error(fmt::format("{} needs {}, more than this machine's memory available now ({}); {}",
                            what, bytes_text(bytes), bytes_text(available), advice));
}

}  // namespace terrain
