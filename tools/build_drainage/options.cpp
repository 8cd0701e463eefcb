#include "build_drainage/options.hpp"

#include <fmt/format.h>

#include "common.hpp"
#include "drainage/d8.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "terrain/error.hpp"

namespace terrain::tools::build_drainage {

namespace tt = terrain::tools;

// The inputs and how the surface is conditioned.
static void add_input_options(CLI::App& app, Options& o) {
  app.add_option("MESH_OR_OUTPUT", o.positional,
                 "MESH.ply OUTPUT.dv, or only OUTPUT.dv with --raster / --d8-input")
      ->required()
      ->expected(1, 2);
  app.add_option(
         "--spacing", o.spacing,
         "Mesh mode: spacing in metres of the grid on which the PN surface is sampled (not the\n"
         "mesh's own spacing; finer than it, typically 1/5). Not with --raster: a raster is used\n"
         "on its own grid")
      ->check(tt::kPositive)
      ->capture_default_str();
  app.add_option("--raster", o.raster, "Raster mode: run on this DEM's own grid (no PN surface)");
  app.add_option("--d8-input", o.d8_input,
                 "Accumulate these D8 directions instead of computing them");
  app.add_option("--d8-encoding", o.encoding,
                 "Encoding of --d8-input and of the d8 raster of --rasters")
      ->check(CLI::IsMember({"taudem", "esri"}))
      ->capture_default_str();
  app.add_flag("--keep-flats", o.keep_flats,
               "Keep flat areas as one-point pits (the paper's literal behaviour)");
  auto* fill_flag =
      app.add_flag("--fill", o.fill, "Fill depressions first (Priority-Flood; TauDEM's pitremove)");
  auto* breach =
      app.add_option(
             "--breach", o.breach,
             "Breach depressions first: cut a channel through each one's rim, at most DEPTH\n"
             "metres deep, and fill what remains below that (Lindsay 2016). Mesh mode's default\n"
             "is --breach " +
                 fmt::format("{:g}", drainage::kMeshBreachDepth) +
                 "; raster mode conditions nothing unless told. Untiled runs")
          ->check(tt::kNonNegative)
          ->type_name("DEPTH")
          ->excludes(fill_flag);
  app.add_flag("--keep-pits", o.keep_pits,
               "Mesh mode: condition nothing, every pit is a basin (the paper's rule)")
      ->excludes(fill_flag, breach);
}

// What is written besides the .dv: rasters, watersheds, the surface, the .dv's version.
static void add_output_options(CLI::App& app, Options& o) {
  app.add_option("--rasters", o.rasters_dir,
                 "Also write GeoTIFFs of every layer into this directory");
  app.add_option("--outlets", o.outlets,
                 "Watersheds at these points (any OGR point layer: GeoPackage, shapefile, GeoJSON, "
                 "CSV with x/y\n"
                 "columns; transformed to the grid's CRS): each cell goes to its nearest outlet "
                 "downstream, so\n"
                 "nested outlets give nested watersheds (TauDEM's gagewatershed)");
  app.add_option(
         "--snap-distance", o.snap_distance,
         "Move each outlet to the cell of highest accumulation within this many metres (TauDEM's\n"
         "moveoutletstostreams); 0: the cell holding the point")
      ->check(tt::kNonNegative)
      ->capture_default_str();
  app.add_option(
      "--watersheds", o.watersheds,
      "With --outlets: the GeoPackage to write (layers outlets and watersheds) and, beside it "
      "with\n"
      "the extension .tif, the watershed raster (UInt32 outlet index). Default: OUTPUT's name\n"
      "without .dv, then _watersheds.gpkg");
  app.add_option("--surface", o.surface_out, "Also write the sampled surface as a GeoTIFF");
  app.add_option("--dv-version", o.dv_version,
                 "Format version of OUTPUT.dv: 2 (compact, compressed blocks) or 1 (32 bytes per "
                 "point, for readers "
                 "older than 2026-11)")
      ->check(CLI::IsMember({1, 2}))
      ->capture_default_str();
}

// How the run is shared out: tiles, memory, threads.
static void add_run_options(CLI::App& app, Options& o) {
  tt::add_tile_size_option(
      app, o.tile_size,
      "Raster mode tile by tile, for rasters larger than memory: tiles of N x N samples read\n"
      "through GDAL windows, results identical to the untiled run (docs/build-drainage.md).\n"
      "Under mpirun the ranks share the tiles (default 1024 there)",
      decltype(o.tile_size)(16384));
  tt::add_memory_option(app, o.memory_mib,
                        "Raster mode within about this much memory (MiB): untiled when the grid "
                        "fits (40 bytes per\npoint), else tiled with the largest tiles that fit "
                        "(100 bytes per tile point per thread, or\n300 per tile-edge cell for "
                        "the perimeter graphs, + 64 MiB; docs/build-drainage.md)",
                        64.0)
      ->excludes("--tile-size");
  app.add_option("--threads", o.threads,
                 "Threads (default: all cores); the output does not depend on it")
      ->check(CLI::Range(1, tt::kMaxThreads));
}

void add_options(CLI::App& app, Options& o) {
  add_input_options(app, o);
  add_output_options(app, o);
  add_run_options(app, o);
}

drainage::DrainageJob job_of(const CLI::App& app, Options& o) {
  drainage::DrainageJob job;
  job.raster = o.raster, job.d8_input = o.d8_input;
  const bool raster_mode = job.raster_mode();
  if (raster_mode && o.positional.size() != 1)
    throw terrain::Error("with --raster or --d8-input give only OUTPUT.dv (no mesh)");
  if (!raster_mode && o.positional.size() != 2)
    throw terrain::Error("give MESH.ply and OUTPUT.dv (or use --raster)");
  if (raster_mode && app.get_option("--spacing")->count() > 0)
    throw terrain::Error(
        "--spacing applies to mesh mode only: --raster runs on the raster's own grid (resample it "
        "first, e.g. with gdalwarp -tr)");
  job.output = o.positional.back();
  if (!job.output.ends_with(".dv"))
    throw terrain::Error("OUTPUT must be a .dv file: '" + job.output + "'");
  if (!o.d8_input.empty() && (o.fill || o.breach || o.keep_flats))
    throw terrain::Error(
        "--fill, --breach and --keep-flats do not apply to --d8-input (directions are given)");
  if (raster_mode && o.keep_pits)
    throw terrain::Error(
        "--keep-pits applies to mesh mode: raster mode keeps every pit unless --fill or --breach");
  if (!raster_mode && !o.fill && !o.breach && !o.keep_pits) o.breach = drainage::kMeshBreachDepth;
  if (o.outlets.empty() &&
      (!o.watersheds.empty() || app.get_option("--snap-distance")->count() > 0))
    throw terrain::Error("--watersheds and --snap-distance go with --outlets POINTS");
  if (!o.outlets.empty()) {
    if (o.watersheds.empty())
      o.watersheds = job.output.substr(0, job.output.size() - 3) + "_watersheds.gpkg";
    if (!o.watersheds.ends_with(".gpkg"))
      throw terrain::Error("--watersheds must name a .gpkg file: '" + o.watersheds + "'");
    job.watershed_tif = o.watersheds.substr(0, o.watersheds.size() - 5) + ".tif";
  }
  job.mesh = raster_mode ? "" : o.positional[0];
  job.spacing = o.spacing, job.encoding = drainage::parse_d8_encoding(o.encoding);
  job.surface = o.surface_out, job.rasters_dir = o.rasters_dir;
  job.outlets = o.outlets, job.watersheds = o.watersheds, job.snap_distance = o.snap_distance;
  job.fill = o.fill, job.keep_flats = o.keep_flats, job.breach = o.breach,
  job.dv_version = o.dv_version;
  return job;
}

}  // namespace terrain::tools::build_drainage
