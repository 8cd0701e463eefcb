#pragma once
// build-drainage's raster mode tile by tile (tiled_pipeline.cpp): the tiled algorithms of
// tiled.hpp between GDAL windows of the input and the blocks of a .dv version 2.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/tile_comm.hpp"
#include "drainage/tiled.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"

namespace drainage {

// build-drainage --raster / --d8-input with --tile-size: the whole raster mode tile by
// tile, from GDAL windows of the input to a .dv version 2 with one block per tile (so
// that a window of it reads whole tiles). With `fill`, the filled surface is kept in a
// temporary raw array in the run's private scratch folder, and with resolve_flats the
// resolved codes in another (both removed at the end, on an error and on SIGINT/SIGTERM).
// The defaults are DrainageOptions' (pipeline.hpp): flats resolved, no fill. A flat inside a tile
// is resolved with its tile; a flat that crosses tile edges is joined across tiles and resolved in
// a window of its bounding box (so a flat's bounding box must fit in memory). Each flat's
// directions depend on that flat alone, so the result equals resolve_flats on the whole grid.
struct TiledRun {
  std::string dem, d8;  // inputs: a DEM, or D8 codes in `encoding`, not both
  D8Encoding encoding = D8Encoding::Taudem;
  std::size_t tile = 0;  // tile side in samples (>= 1, <= 16384)
  bool fill = false, resolve_flats = true;
  std::string provenance;
  // Where rank 0 writes the .dv: empty for output_path itself, or a staged path of the
  // caller's terrain::OutputSet, so that the .dv lands together with the layers made from
  // it (--rasters, --outlets) and an interrupted run replaces none of them.
  std::string write_to;
};
struct TiledSummary {
  std::size_t rows = 0, cols = 0, tiles = 0, filled = 0;
  double dx = 0, dy = 0;
  NetworkTotals totals;
  std::vector<std::pair<const char*, double>> timings;  // wall seconds per step (rank 0's), for -v
};
// About the peak memory of a tiled run (one process) of `info`'s grid in tiles of `side` on
// `threads` threads: 64 MiB for the process and GDAL's cache, and the larger of the tiles
// in flight (100 bytes per tile point per thread: tiles are worked on all threads) and the
// perimeter graphs (300 bytes per tile-edge cell; they are solved between the passes).
// docs/build-drainage.md has the peaks measured against it.
double tiled_run_bytes(const terrain::DemInfo& info, std::size_t side, int threads);

// The tile side for a raster mode run on `threads` threads within `bytes` of memory: 0
// (untiled) when the whole grid fits at 40 bytes per point, else the largest multiple of
// 256 (256 .. 16384) whose run fits (tiled_run_bytes); when none does, the side whose run
// needs least (check tiled_run_bytes of the result against the budget).
std::size_t tile_size_for_memory(const terrain::DemInfo& info, double bytes, int threads = 1);

// With several ranks (tile_comm.hpp, e.g. under mpirun) every rank calls it with the same
// arguments; the ranks share the tiles, the temporary rasters (raw files next to the
// output, so on a file system every rank sees) and the .dv, which rank 0 writes from the
// blocks the others leave in per-rank temporary files. Every rank returns the summary.
TiledSummary run_tiled_drainage(const TiledRun& run, const std::string& output_path,
                                const terrain::Progress& progress = {},
                                const TileComm& comm = single_process());

}  // namespace drainage
