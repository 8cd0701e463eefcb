#pragma once
// What a drainage run on one grid makes (pipeline.hpp computes it; rasters.hpp writes it).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/flats.hpp"
#include "drainage/network.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct DrainageResult {
  terrain::Grid surface;  // the surface used (filled when fill)
  D8Codes dirs;           // D8 codes (d8.hpp)
  Network net;
  FlatStats flats;
  std::size_t filled = 0;      // samples raised by filling (or by breaching, where too deep)
  std::size_t carved = 0;      // samples lowered by breaching
  double max_carve = 0;        // the deepest of those lowerings, metres
  std::uint32_t dv_flags = 0;  // DvFlags describing how it was made
  std::vector<std::pair<const char*, double>> timings;  // wall seconds per step, for -v
};

}  // namespace drainage
