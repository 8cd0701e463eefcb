#pragma once
// Steps 2-6 of build-drainage on a surface grid: (fill), D8, (flats), network.
#include <cstdint>
#include <utility>
#include <vector>

#include "drainage/flats.hpp"
#include "drainage/network.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct DrainageOptions {
  bool fill = false;           // Priority-Flood depression filling first (--fill)
  bool resolve_flats = true;   // Barnes flat resolution (off: --keep-flats)
};

struct DrainageResult {
  terrain::Grid surface;               // the surface used (filled when fill)
  D8Codes dirs;                        // D8 codes (d8.hpp)
  Network net;
  FlatStats flats;
  std::size_t filled = 0;              // samples raised by filling
  std::uint32_t dv_flags = 0;          // DvFlags describing how it was made
  std::vector<std::pair<const char*, double>> timings;  // wall seconds per step, for -v
};

// Fill (optional), D8 directions, flat resolution (optional), then the network.
DrainageResult compute_drainage(terrain::Grid surface, const DrainageOptions& options,
                                const terrain::Progress& progress = {});

// The network of given directions on `surface`'s grid (--d8-input): skips D8 and flats.
DrainageResult drainage_from_directions(terrain::Grid surface, D8Codes dirs,
                                        const terrain::Progress& progress = {});

}  // namespace drainage
