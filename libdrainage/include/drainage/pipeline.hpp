#pragma once
// Steps 2-6 of build-drainage on a surface grid: (fill), D8, (flats), network.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/drainage_result.hpp"
#include "drainage/flats.hpp"
#include "drainage/network.hpp"
#include "drainage/rasters.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct DrainageOptions {
  bool fill = false;          // Priority-Flood depression filling first (--fill)
  bool resolve_flats = true;  // Barnes flat resolution (off: --keep-flats)
  std::optional<double>
      breach_depth;  // breaching instead of fill, cutting at most this deep (--breach)
  NetworkDetail network = NetworkDetail::Full;  // Lean: enough for a version-2 .dv (network.hpp)
};

// Fill or breach (optional), D8 directions, flat resolution (optional), then the network.
DrainageResult compute_drainage(terrain::Grid surface, const DrainageOptions& options,
                                const terrain::Progress& progress = {});

// The network of given directions on `surface`'s grid (--d8-input): skips D8 and flats.
DrainageResult drainage_from_directions(terrain::Grid surface, D8Codes dirs,
                                        const terrain::Progress& progress = {},
                                        NetworkDetail detail = NetworkDetail::Full);

// compute_drainage, or drainage_from_directions when `in` carries directions (then
// `options` must be the defaults' fill = false).
DrainageResult run_drainage(RasterInput in, const DrainageOptions& options,
                            const terrain::Progress& progress = {});

// Peak memory of an untiled run per grid cell, every buffer counted (input, directions,
// network, the .dv writer's blocks, rasters): measured as build-drainage's peak RSS on
// Logan at 10 m (14.4 M cells) with --fill: 25.7 bytes a cell lean (a version-2 .dv),
// 40.3 with --rasters; rounded up. Tools check it against the memory available before
// they read (terrain::check_memory).
inline double untiled_bytes_per_cell(NetworkDetail detail) {
  return detail == NetworkDetail::Lean ? 28.0 : 44.0;
}

}  // namespace drainage
