#pragma once
// dem2mesh's options (CLI11) and what they ask for: the grid request and the grid itself,
// from a raster or from scattered points.
#include <CLI/CLI.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "terrain/fit_normals.hpp"
#include "terrain/grid.hpp"
#include "terrain/prepare_grid.hpp"
#include "terrain/scattered.hpp"

namespace terrain::tools::mesh {

// The options as CLI11 fills them, and the options whose presence matters.
struct Options {
  std::string input, output, resample = "bilinear", weighting = "uniform", grid_out;
  std::optional<double> nodata;  // --nodata
  std::string interpolation = "natural", src_crs, utm_zone, dequantize = "auto",
              input_kind = "auto";
  double max_edge = 0.0, spacing = 0.0;
  terrain::GridRequest req;
  std::array<double, 4> bbox{};
  std::array<double, 2> center{}, size{};
  bool fit = false, pyramid = false;
  std::size_t tile_size = 0;  // --tile-size: rows a band (0: the whole grid at once)
  double memory_mib = 0;      // --memory
  terrain::NormalFitOptions fit_opt;
  CLI::Option *spacing_opt = nullptr, *bbox_opt = nullptr, *center_opt = nullptr,
              *interp_opt = nullptr, *max_edge_opt = nullptr;
};

// INPUT, OUTPUT and the grid: spacing, crop, zone, kernel, no-data, integer heights, normals.
void add_grid_options(CLI::App& app, Options& o);
// Scattered points' interpolation and CRS, what INPUT holds, and the normals' fit.
void add_input_options(CLI::App& app, Options& o);
// The crop and grid request of the options.
terrain::GridRequest request_of(const Options& o);
// The grid the options ask for: a raster resampled, or scattered points interpolated;
// `source_dem` / `source_points` receive the source samples for --fit-normals, `points`
// whether INPUT was read as points, `filled` which samples --fill-nodata filled.
terrain::Grid grid_of(const Options& o, const terrain::GridRequest& req, const Verbosity& verb,
                      terrain::Grid& source_dem, terrain::SourceSamples& source_points,
                      bool& points, std::vector<std::uint8_t>& filled);

}  // namespace terrain::tools::mesh
