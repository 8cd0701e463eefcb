#pragma once
// Steps 2-6 of build-drainage on a surface grid: (fill), D8, (flats), network.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/flats.hpp"
#include "drainage/network.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct DrainageOptions {
  bool fill = false;                   // Priority-Flood depression filling first (--fill)
  bool resolve_flats = true;           // Barnes flat resolution (off: --keep-flats)
  std::optional<double> breach_depth;  // breaching instead of fill, cutting at most this deep (--breach)
  NetworkDetail network = NetworkDetail::Full;  // Lean: enough for a version-2 .dv (network.hpp)
};

struct DrainageResult {
  terrain::Grid surface;               // the surface used (filled when fill)
  D8Codes dirs;                        // D8 codes (d8.hpp)
  Network net;
  FlatStats flats;
  std::size_t filled = 0;              // samples raised by filling (or by breaching, where too deep)
  std::size_t carved = 0;              // samples lowered by breaching
  double max_carve = 0;                // the deepest of those lowerings, metres
  std::uint32_t dv_flags = 0;          // DvFlags describing how it was made
  std::vector<std::pair<const char*, double>> timings;  // wall seconds per step, for -v
};

// Fill or breach (optional), D8 directions, flat resolution (optional), then the network.
DrainageResult compute_drainage(terrain::Grid surface, const DrainageOptions& options,
                                const terrain::Progress& progress = {});

// The network of given directions on `surface`'s grid (--d8-input): skips D8 and flats.
DrainageResult drainage_from_directions(terrain::Grid surface, D8Codes dirs, const terrain::Progress& progress = {},
                                        NetworkDetail detail = NetworkDetail::Full);

// The inputs of raster mode (build-drainage --raster DEM and/or --d8-input DIRS).
struct RasterInput {
  terrain::Grid surface;          // the DEM; with directions only, their grid with z = 0 (NaN at no-data)
  std::optional<D8Codes> dirs;    // given directions (--d8-input), masked by the DEM's no-data
  std::uint32_t dv_flags = 0;     // kDvHasElevations when a DEM was given
};

// Reads a DEM (any GDAL raster, projected or geographic: D8 then uses per-row metric cell
// sizes), directions in `encoding`, or both. Errors (terrain::Error): neither given, a DEM
// with no valid sample, a direction raster on a different grid than the DEM.
RasterInput read_raster_input(const std::string& dem_path, const std::string& d8_path, D8Encoding encoding);

// compute_drainage, or drainage_from_directions when `in` carries directions (then
// `options` must be the defaults' fill = false).
DrainageResult run_drainage(RasterInput in, const DrainageOptions& options, const terrain::Progress& progress = {});

// Peak memory of an untiled run per grid cell, every buffer counted (input, directions,
// network, the .dv writer's blocks, rasters): measured as build-drainage's peak RSS on
// Logan at 10 m (14.4 M cells) with --fill: 25.7 bytes a cell lean (a version-2 .dv),
// 40.3 with --rasters; rounded up. Tools check it against the memory available before
// they read (terrain::check_memory).
inline double untiled_bytes_per_cell(NetworkDetail detail) { return detail == NetworkDetail::Lean ? 28.0 : 44.0; }

// Throws terrain::Error naming both files when `a` and `b` differ in size, origin or step.
void check_same_grid(const terrain::Grid& a, const terrain::Grid& b, const std::string& a_name,
                     const std::string& b_name);

}  // namespace drainage
