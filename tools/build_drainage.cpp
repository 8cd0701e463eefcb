// build-drainage: the drainage vertex database (.dv) of a mesh's PN surface or of a raster.
#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>

#include "build_drainage/options.hpp"
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
using terrain::tools::build_drainage::Options;

namespace {

// Tiles of a run under several MPI ranks that gives neither --tile-size nor --memory.
constexpr std::size_t kMpiDefaultTile = 1024;

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
  terrain::tools::build_drainage::add_options(app, o);
  tt::add_verbosity_flags(app, verb);

  return tt::run_main(app, argc, argv, [&]() {
    if (!comm.root()) verb.quiet = true, verb.verbose = false;  // rank 0 speaks for the job
    drainage::DrainageJob job = terrain::tools::build_drainage::job_of(app, o);
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
