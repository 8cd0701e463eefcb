#pragma once
// build-drainage's run, as named steps over the library (the tool parses its options into
// a DrainageJob and prints the report): the input (a mesh's PN surface sampled, or a
// raster), the drainage (untiled: pipeline.hpp; tiled and MPI: tiled_pipeline.hpp), and
// the outputs that land together (the .dv, --surface, --rasters, the watersheds at
// --outlets). One summary, with the same keys, for untiled and tiled runs.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/tile_comm.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct DrainageJob {
  std::string mesh;              // mesh mode: the mesh whose PN surface is sampled
  double spacing = 10.0;         // mesh mode: the sampling spacing in metres
  std::string raster, d8_input;  // raster mode: a DEM, or D8 codes in `encoding`
  D8Encoding encoding = D8Encoding::Taudem;
  std::string output;                              // the .dv
  std::string surface;                             // --surface GeoTIFF ("" none)
  std::string rasters_dir;                         // --rasters ("" none)
  std::string outlets, watersheds, watershed_tif;  // --outlets ("" none) and where they go
  double snap_distance = 0;
  bool fill = false, keep_flats = false;
  std::optional<double>
      breach;  // build-drainage sets kMeshBreachDepth in mesh mode unless told otherwise
  std::uint32_t dv_version = 2;
  std::size_t tile_size = 0;  // > 0: tiled (raster mode only)
  std::string provenance;
  bool raster_mode() const { return !raster.empty() || !d8_input.empty(); }
};

// Mesh mode's default conditioning: depressions breached at most this deep (metres), the
// rest filled, so that basins are the surface's real drainage basins and the creases form
// a network; --keep-pits keeps every pit a basin (the paper's rule). Raster mode conditions
// nothing unless told (TauDEM's rules).
inline constexpr double kMeshBreachDepth = 10.0;

// What a run reports (build-drainage's stdout: summary_text), untiled or tiled alike.
struct RunSummary {
  std::size_t rows = 0, cols = 0, tiles = 1;
  double dx = 0, dy = 0;
  std::size_t points = 0, basins = 0, pits = 0, ridges = 0, channels = 0, junctions = 0,
              branches = 0;
  std::optional<std::pair<std::size_t, std::size_t>>
      flats;  // resolved, undrainable (untiled runs count them)
  std::size_t filled = 0;
  std::optional<std::pair<std::size_t, double>> carved;  // --breach: cells cut, deepest cut
  std::size_t pn_fallbacks = 0;                          // mesh mode: samples on the flat triangle
  std::vector<Watershed> watersheds;
  std::vector<std::pair<std::string, double>> timings;  // seconds per step, for -v
  std::vector<std::string> warnings;                    // for the tool to print
};

// A progress callback for a step named `label` (the tool's terminal progress).
using ProgressFor = std::function<terrain::Progress(const std::string& label)>;

// The untiled run: input, drainage, outputs (all land, or none). Throws terrain::Error.
RunSummary run_untiled_job(const DrainageJob& job, const ProgressFor& progress);

// The tiled run on the ranks of `comm` (raster mode): the .dv staged, then --rasters and the
// watersheds from it, all landing together; the classes counted from the finished file.
// Every rank calls it; rank 0 writes.
RunSummary run_tiled_job(const DrainageJob& job, const ProgressFor& progress, const TileComm& comm);

// "key: value" lines: output, grid, spacing, tiles, points, basins, pits, ridges, channels,
// junctions, branches, flats, filled, carved (with --breach), and the watersheds.
std::string summary_text(const DrainageJob& job, const RunSummary& s);

}  // namespace drainage
