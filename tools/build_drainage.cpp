// build-drainage: the drainage vertex database (.dv) of a mesh's PN surface or of a raster.
#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>

#include "common.hpp"
#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/job.hpp"
#include "drainage/rasters.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#ifdef TERRAIN_HAVE_MPI
#include "mpi_comm.hpp"
#endif

namespace tt = terrain::tools;

namespace {

// Tiles of a run under several MPI ranks that gives neither --tile-size nor --memory.
constexpr std::size_t kMpiDefaultTile = 1024;

// The options as CLI11 fills them.
struct Options {
  std::vector<std::string> positional;
  std::string raster, d8_input, rasters_dir, surface_out, encoding = "taudem", outlets, watersheds;
  double snap_distance = 0, spacing = 10.0, memory_mib = 0;
  bool keep_flats = false, fill = false, keep_pits = false;
  int threads = 0;
  std::uint32_t dv_version = drainage::kDvVersion;
  std::size_t tile_size = 0;
  std::optional<double> breach;
};

void add_options(CLI::App& app, Options& o) {
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
  app.add_option(
         "--tile-size", o.tile_size,
         "Raster mode tile by tile, for rasters larger than memory: tiles of N x N samples read\n"
         "through GDAL windows, results identical to the untiled run (docs/build-drainage.md).\n"
         "Under mpirun the ranks share the tiles (default 1024 there)")
      ->check(CLI::Range(1, 16384));
  app.add_option(
         "--memory", o.memory_mib,
         "Raster mode within about this much memory (MiB): untiled when the grid fits (40 bytes "
         "per\n"
         "point), else tiled with the largest tiles that fit (100 bytes per tile point per thread, "
         "or\n"
         "300 per tile-edge cell for the perimeter graphs, + 64 MiB; docs/build-drainage.md)")
      ->check(CLI::Range(64.0, 1e9))
      ->excludes("--tile-size");
  app.add_option("--threads", o.threads,
                 "Threads (default: all cores); the output does not depend on it")
      ->check(CLI::Range(1, tt::kMaxThreads));
}

// The job the options ask for: the inputs, the outputs (the watersheds' names defaulted), the
// drainage rules. Throws for options that do not go together.
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

// Every output differs from every input and can be written; a bad outlet file fails at once.
void check_outputs(const drainage::DrainageJob& job, const tt::Verbosity& verb) {
  std::vector<std::string> outputs = {job.output, job.surface, job.watersheds, job.watershed_tif};
  if (!job.rasters_dir.empty())
    for (const char* name : drainage::kDrainageRasterNames)
      outputs.push_back((std::filesystem::path(job.rasters_dir) / name).string());
  tt::check_distinct_paths({job.mesh, job.raster, job.d8_input, job.outlets}, outputs);
  tt::warn_stale_temporaries(verb, outputs);
  for (const std::string& out : {job.output, job.surface, job.watersheds, job.watershed_tif})
    if (!out.empty()) terrain::check_output_path(out);
  if (!job.outlets.empty()) (void)drainage::read_outlet_points(job.outlets, "");
  if (!job.rasters_dir.empty() && !std::filesystem::is_directory(job.rasters_dir))
    throw terrain::Error("--rasters: directory '" + job.rasters_dir + "' does not exist");
}

// The tiles of the run: --tile-size, or the largest that fit --memory, or the MPI default
// under several ranks; 0 for an untiled run. Throws for options a tiled run does not take.
std::size_t tile_size_of(const drainage::DrainageJob& job, const Options& o,
                         const drainage::TileComm& comm, const tt::Verbosity& verb) {
  std::size_t tile = o.tile_size;
  if (o.memory_mib > 0) {
    if (!job.raster_mode())
      throw terrain::Error("--memory applies to --raster and --d8-input runs");
    const terrain::DemInfo info =
        terrain::read_dem_info(job.raster.empty() ? job.d8_input : job.raster);
    tile =
        drainage::tile_size_for_memory(info, o.memory_mib * 1024.0 * 1024.0, omp_get_max_threads());
    if (tile > 0) {
      const double need = drainage::tiled_run_bytes(info, tile, omp_get_max_threads()) / 1048576.0;
      tt::step(verb, fmt::format("--memory {:.0f} MiB: tiles of {} x {} (about {:.0f} MiB)",
                                 o.memory_mib, tile, tile, need));
      if (need > o.memory_mib)
        tt::warn(
            verb,
            fmt::format(
                "--memory {:.0f} MiB is too little for this grid's perimeter graphs: expect about "
                "{:.0f} MiB (tiles of {}; fewer --threads need less)",
                o.memory_mib, need, tile));
    }
  }
  if (comm.size() > 1) {
    if (!job.raster_mode())
      throw terrain::Error(
          "mesh mode runs on one process: start it without mpirun, or use --raster");
    if (tile == 0) tile = kMpiDefaultTile;
  }
  if (tile == 0) return 0;
  if (!job.raster_mode())
    throw terrain::Error("--tile-size applies to --raster and --d8-input runs");
  if (!job.surface.empty())
    throw terrain::Error(
        "--surface is not written in tiled runs (yet): --rasters DIR writes surface.tif");
  if (job.dv_version != 2) throw terrain::Error("tiled runs write .dv version 2");
  if (job.breach)
    throw terrain::Error("--breach runs untiled only (use --fill in tiled and MPI runs)");
  return tile;
}

int build_drainage(int argc, char** argv, const drainage::TileComm& comm) {
  CLI::App app{
      "Build the drainage vertex database (.dv): sample the PN surface of a mesh on a fine grid,\n"
      "D8 steepest descent, flats, pits/ridges/channels/junctions, basins, flow accumulation\n"
      "normalized per basin, Strahler order and branches.",
      "build-drainage"};
  app.footer(
      "Examples:\n"
      "  build-drainage out/msh_50m.ply out/msh.dv --spacing 10 --rasters out/msh_rasters\n"
      "  build-drainage out/logan_100m.ply out/logan_pits.dv --spacing 30 --keep-pits\n"
      "  build-drainage --raster data/logan_utm12n_100m.tif logan.dv --fill\n"
      "  build-drainage --raster dem.tif --d8-input dirs.tif --d8-encoding taudem acc.dv\n"
      "  build-drainage --raster big.vrt big.dv --fill --memory 4096\n"
      "  mpirun -np 8 build-drainage --raster big.vrt big.dv --fill --tile-size 4096\n"
      "  build-drainage --raster dem.tif dem.dv --fill --outlets gauges.gpkg --snap-distance "
      "100\n\n"
      "Conditioning: mesh mode breaches depressions by default (--breach 10: basins are the\n"
      "surface's real drainage basins); --keep-pits keeps every pit a basin, --fill fills.\n"
      "Raster mode conditions nothing by default (TauDEM's rules: --fill is its pitremove).\n\n"
      "Output: stdout gets 'key: value' lines (points, pits, basins, classes, branches); see\n"
      "docs/build-drainage.md for the rules and docs/dv-format.md for the file.");
  app.set_version_flag("--version", tt::version());
  Options o;
  tt::Verbosity verb;
  add_options(app, o);
  tt::add_verbosity_flags(app, verb);

  return tt::run_main(app, argc, argv, [&]() {
    if (!comm.root()) verb.quiet = true, verb.verbose = false;  // rank 0 speaks for the job
    drainage::DrainageJob job = job_of(app, o);
    job.provenance = tt::provenance(argc, argv);
    check_outputs(job, verb);
    if (o.threads > 0) omp_set_num_threads(o.threads);
    job.tile_size = tile_size_of(job, o, comm, verb);
    const auto progress = [&](const std::string& label) {
      return tt::terminal_progress(verb, label);
    };
    const auto t0 = std::chrono::steady_clock::now();
    const drainage::RunSummary s = job.tile_size > 0 ? drainage::run_tiled_job(job, progress, comm)
                                                     : drainage::run_untiled_job(job, progress);
    for (const auto& [name, secs] : s.timings)
      tt::step(verb, fmt::format("{}: {:.3f} s", name, secs));
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    tt::step(verb, fmt::format(
                       "{} run ({} tiles, {} process(es)): {:.2f} s, peak RSS {:.0f} MiB (rank 0)",
                       job.tile_size > 0 ? "tiled" : "untiled", s.tiles, comm.size(), secs,
                       tt::peak_rss_mib()));
    for (const std::string& w : s.warnings) tt::warn(verb, w);
    if (s.pn_fallbacks > 0)
      tt::warn(verb, fmt::format("{} samples used the flat triangle (PN patch folds over)",
                                 s.pn_fallbacks));
    if (comm.root()) std::cout << drainage::summary_text(job, s);
    return 0;
  });
}

}  // namespace

int main(int argc, char** argv) {
#ifdef TERRAIN_HAVE_MPI
  std::optional<tt::MpiSession> mpi;
  if (tt::mpi_launcher_size() > 0) mpi.emplace(argc, argv);
  const int code = build_drainage(argc, argv, mpi ? *mpi : drainage::single_process());
  if (code != 0 && mpi && mpi->size() > 1)
    mpi->abort(code);  // the other ranks may wait for this one
  return code;
#else
  if (tt::mpi_launcher_size() > 1) {
    std::cerr << "build-drainage: error: started by an MPI launcher on " << tt::mpi_launcher_size()
              << " ranks, but built without MPI (install libopenmpi-dev and rebuild)\n";
    return 1;
  }
  return build_drainage(argc, argv, drainage::single_process());
#endif
}
