// build-drainage: the drainage vertex database (.dv) of a mesh's PN surface or of a raster.
#include <fmt/format.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

#include "common.hpp"
#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/pipeline.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/rasters.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/memory.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/pn_surface.hpp"
#ifdef TERRAIN_HAVE_MPI
#include "mpi_comm.hpp"
#endif

namespace tt = terrain::tools;

namespace {

// Tiles of a run under several MPI ranks that gives neither --tile-size nor --memory.
constexpr std::size_t kMpiDefaultTile = 1024;

int build_drainage(int argc, char** argv, const drainage::TileComm& comm) {
  CLI::App app{"Build the drainage vertex database (.dv): sample the PN surface of a mesh on a fine grid,\n"
               "D8 steepest descent, flats, pits/ridges/channels/junctions, basins, flow accumulation\n"
               "normalized per basin, Strahler order and branches.",
               "build-drainage"};
  app.footer(
      "Examples:\n"
      "  build-drainage out/msh_50m.ply out/msh.dv --spacing 10 --rasters out/msh_rasters\n"
      "  build-drainage out/logan_100m.ply out/logan_breached.dv --spacing 30 --breach 10\n"
      "  build-drainage --raster data/logan_utm12n_100m.tif logan.dv --fill\n"
      "  build-drainage --raster dem.tif --d8-input dirs.tif --d8-encoding taudem acc.dv\n"
      "  build-drainage --raster big.vrt big.dv --fill --memory 4096\n"
      "  mpirun -np 8 build-drainage --raster big.vrt big.dv --fill --tile-size 4096\n"
      "  build-drainage --raster dem.tif dem.dv --fill --outlets gauges.gpkg --snap-distance 100\n\n"
      "Output: stdout gets 'key: value' lines (points, pits, basins, classes, branches); see\n"
      "docs/build-drainage.md for the rules and docs/dv-format.md for the file.");
  app.set_version_flag("--version", tt::version());

  std::vector<std::string> positional;
  std::string raster, d8_input, rasters_dir, surface_out, encoding = "taudem", outlets, watersheds;
  double snap_distance = 0;
  double spacing = 10.0;
  bool keep_flats = false, fill = false;
  int threads = 0;
  std::uint32_t dv_version = drainage::kDvVersion;
  std::size_t tile_size = 0;
  double memory_mib = 0;
  std::optional<double> breach;
  tt::Verbosity verb;
  app.add_option("MESH_OR_OUTPUT", positional, "MESH.ply OUTPUT.dv, or only OUTPUT.dv with --raster / --d8-input")
      ->required()
      ->expected(1, 2);
  app.add_option("--spacing", spacing,
                 "Mesh mode: spacing in metres of the grid on which the PN surface is sampled (not the\n"
                 "mesh's own spacing; finer than it, typically 1/5). Not with --raster: a raster is used\n"
                 "on its own grid")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--raster", raster, "Raster mode: run on this DEM's own grid (no PN surface)");
  app.add_option("--d8-input", d8_input, "Accumulate these D8 directions instead of computing them");
  app.add_option("--d8-encoding", encoding, "Encoding of --d8-input and of the d8 raster of --rasters")
      ->check(CLI::IsMember({"taudem", "esri"}))
      ->capture_default_str();
  app.add_flag("--keep-flats", keep_flats, "Keep flat areas as one-point pits (the paper's literal behaviour)");
  auto* fill_flag =
      app.add_flag("--fill", fill, "Fill depressions first (Priority-Flood); off by default: every pit is a basin");
  app.add_option("--breach", breach,
                 "Breach depressions first instead: cut a channel through each one's rim, at most DEPTH\n"
                 "metres deep, and fill what remains below that (Lindsay 2016). Keeps rivers running\n"
                 "through small pits of the surface instead of across flat filled reaches. Untiled runs")
      ->check(CLI::NonNegativeNumber)
      ->type_name("DEPTH")
      ->excludes(fill_flag);
  app.add_option("--rasters", rasters_dir, "Also write GeoTIFFs of every layer into this directory");
  app.add_option("--outlets", outlets,
                 "Watersheds at these points (any OGR point layer: GeoPackage, shapefile, GeoJSON, CSV with x/y\n"
                 "columns; transformed to the grid's CRS): each cell goes to its nearest outlet downstream, so\n"
                 "nested outlets give nested watersheds (TauDEM's gagewatershed)");
  app.add_option("--snap-distance", snap_distance,
                 "Move each outlet to the cell of highest accumulation within this many metres (TauDEM's\n"
                 "moveoutletstostreams); 0: the cell holding the point")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--watersheds", watersheds,
                 "With --outlets: the GeoPackage to write (layers outlets and watersheds) and, beside it with\n"
                 "the extension .tif, the watershed raster (UInt32 outlet index). Default: OUTPUT's name\n"
                 "without .dv, then _watersheds.gpkg");
  app.add_option("--surface", surface_out, "Also write the sampled surface as a GeoTIFF");
  app.add_option("--dv-version", dv_version,
                 "Format version of OUTPUT.dv: 2 (compact, compressed blocks) or 1 (32 bytes per point, for readers "
                 "older than 2026-11)")
      ->check(CLI::IsMember({1, 2}))
      ->capture_default_str();
  app.add_option("--tile-size", tile_size,
                 "Raster mode tile by tile, for rasters larger than memory: tiles of N x N samples read\n"
                 "through GDAL windows, results identical to the untiled run (docs/build-drainage.md).\n"
                 "Under mpirun the ranks share the tiles (default 1024 there)")
      ->check(CLI::Range(1, 16384));
  app.add_option("--memory", memory_mib,
                 "Raster mode within about this much memory (MiB): untiled when the grid fits (40 bytes per\n"
                 "point), else tiled with the largest tiles that fit (100 bytes per tile point per thread, or\n"
                 "430 per tile-edge cell for the perimeter graphs, + 64 MiB; docs/build-drainage.md)")
      ->check(CLI::Range(64.0, 1e9))
      ->excludes("--tile-size");
  app.add_option("--threads", threads, "Threads (default: all cores); the output does not depend on it")
      ->check(CLI::Range(1, tt::kMaxThreads));
  tt::add_verbosity_flags(app, verb);

  return tt::run_main(app, argc, argv, [&]() {
    using clock = std::chrono::steady_clock;
    if (!comm.root()) verb.quiet = true, verb.verbose = false;  // rank 0 speaks for the job
    const bool raster_mode = !raster.empty() || !d8_input.empty();
    if (raster_mode && positional.size() != 1)
      throw terrain::Error("with --raster or --d8-input give only OUTPUT.dv (no mesh)");
    if (!raster_mode && positional.size() != 2) throw terrain::Error("give MESH.ply and OUTPUT.dv (or use --raster)");
    if (raster_mode && app.get_option("--spacing")->count() > 0)
      throw terrain::Error("--spacing applies to mesh mode only: --raster runs on the raster's own grid (resample it "
                           "first, e.g. with gdalwarp -tr)");
    const std::string output = positional.back();
    if (!output.ends_with(".dv")) throw terrain::Error("OUTPUT must be a .dv file: '" + output + "'");
    if (!d8_input.empty() && (fill || breach || keep_flats))
      throw terrain::Error("--fill, --breach and --keep-flats do not apply to --d8-input (directions are given)");
    std::vector<std::string> output_paths = {output, surface_out};
    if (!rasters_dir.empty())
      for (const char* name : drainage::kDrainageRasterNames)
        output_paths.push_back((std::filesystem::path(rasters_dir) / name).string());
    if (outlets.empty() && (!watersheds.empty() || app.get_option("--snap-distance")->count() > 0))
      throw terrain::Error("--watersheds and --snap-distance go with --outlets POINTS");
    std::string watershed_tif;
    if (!outlets.empty()) {
      if (watersheds.empty()) watersheds = output.substr(0, output.size() - 3) + "_watersheds.gpkg";
      if (!watersheds.ends_with(".gpkg")) throw terrain::Error("--watersheds must name a .gpkg file: '" + watersheds + "'");
      watershed_tif = watersheds.substr(0, watersheds.size() - 5) + ".tif";
      output_paths.push_back(watersheds), output_paths.push_back(watershed_tif);
    }
    tt::check_distinct_paths({raster_mode ? "" : positional[0], raster, d8_input, outlets}, output_paths);
    tt::warn_stale_temporaries(verb, output_paths);
    terrain::check_output_path(output);
    if (!surface_out.empty()) terrain::check_output_path(surface_out);
    if (!outlets.empty()) {  // before the run: a bad outlet file fails at once
      (void)drainage::read_outlet_points(outlets, "");
      terrain::check_output_path(watersheds);
      terrain::check_output_path(watershed_tif);
    }
    // Watersheds at the outlets from the .dv at `dv` (staged paths of `outputs`), reported.
    auto write_watersheds = [&](const std::string& dv, terrain::OutputSet& outputs, const std::string& prov) {
      const auto t = clock::now();
      const std::vector<drainage::Watershed> ws = drainage::write_watersheds(
          dv, drainage::read_outlet_points(outlets, drainage::read_dv_header(dv).crs_wkt), snap_distance,
          outputs.stage(watersheds), outputs.stage(watershed_tif), prov, tt::terminal_progress(verb, "watersheds"));
      tt::step(verb, fmt::format("watersheds of {} outlets: {:.2f} s", ws.size(),
                                 std::chrono::duration<double>(clock::now() - t).count()));
      return ws;
    };
    auto report_watersheds = [&](const std::vector<drainage::Watershed>& ws) {
      if (outlets.empty()) return;
      std::cout << "watersheds: " << watersheds << "\nwatershed_raster: " << watershed_tif << "\n";
      for (std::size_t k = 0; k < ws.size(); ++k)
        std::cout << fmt::format("outlet_{}: row {}, column {}, moved {:.2f} m, accumulated {}, cells {}, drains into {}\n",
                                 k, ws[k].row, ws[k].col, ws[k].moved, ws[k].accumulated, ws[k].cells,
                                 ws[k].downstream < 0 ? std::string("none") : std::to_string(ws[k].downstream));
    };
    if (!rasters_dir.empty() && !std::filesystem::is_directory(rasters_dir))
      throw terrain::Error("--rasters: directory '" + rasters_dir + "' does not exist");
    if (threads > 0) omp_set_num_threads(threads);
    if (memory_mib > 0) {
      if (!raster_mode) throw terrain::Error("--memory applies to --raster and --d8-input runs");
      const terrain::DemInfo info = terrain::read_dem_info(raster.empty() ? d8_input : raster);
      tile_size = drainage::tile_size_for_memory(info, memory_mib * 1024.0 * 1024.0, omp_get_max_threads());
      if (tile_size > 0) {
        const double need = drainage::tiled_run_bytes(info, tile_size, omp_get_max_threads()) / 1048576.0;
        tt::step(verb, fmt::format("--memory {:.0f} MiB: tiles of {} x {} (about {:.0f} MiB)", memory_mib, tile_size,
                                   tile_size, need));
        if (need > memory_mib)
          tt::warn(verb, fmt::format("--memory {:.0f} MiB is too little for this grid's perimeter graphs: expect about "
                                     "{:.0f} MiB (tiles of {}; fewer --threads need less)",
                                     memory_mib, need, tile_size));
      }
    }
    if (comm.size() > 1) {
      if (!raster_mode) throw terrain::Error("mesh mode runs on one process: start it without mpirun, or use --raster");
      if (tile_size == 0) tile_size = kMpiDefaultTile;
    }
    if (tile_size > 0) {
      if (!raster_mode) throw terrain::Error("--tile-size applies to --raster and --d8-input runs");
      if (!surface_out.empty())
        throw terrain::Error("--surface is not written in tiled runs (yet): --rasters DIR writes surface.tif");
      if (dv_version != 2) throw terrain::Error("tiled runs write .dv version 2");
      if (breach) throw terrain::Error("--breach runs untiled only (use --fill in tiled and MPI runs)");
      using clock = std::chrono::steady_clock;
      const auto t0 = clock::now();
      drainage::TiledRun run;
      run.dem = raster, run.d8 = d8_input, run.encoding = drainage::parse_d8_encoding(encoding);
      run.tile = tile_size, run.fill = fill, run.resolve_flats = !keep_flats;
      run.provenance = tt::provenance(argc, argv);
      // The .dv is staged and lands with the layers made from it (or none lands).
      terrain::OutputSet outputs;
      if (comm.root()) run.write_to = outputs.stage(output);
      drainage::TiledSummary r;
      outputs.write([&] { r = drainage::run_tiled_drainage(run, output, tt::terminal_progress(verb, "tiles"), comm); });
      for (const auto& [name, secs] : r.timings) tt::step(verb, fmt::format("  {}: {:.3f} s", name, secs));
      tt::step(verb, fmt::format("tiled run ({} tiles, {} process{}): {:.2f} s, peak RSS {:.0f} MiB (rank 0)", r.tiles,
                                 comm.size(), comm.size() > 1 ? "es" : "",
                                 std::chrono::duration<double>(clock::now() - t0).count(), tt::peak_rss_mib()));
      if (!comm.root()) return 0;
      std::vector<drainage::Watershed> ws;
      const auto t1 = clock::now();
      outputs.write([&] {
        if (!rasters_dir.empty())
          drainage::export_dv_rasters(
              run.write_to, [&](const std::string& name) { return outputs.stage(std::filesystem::path(rasters_dir) / name); },
              run.encoding, run.provenance);
        if (!outlets.empty()) ws = write_watersheds(run.write_to, outputs, run.provenance);
      });
      outputs.commit();
      if (!rasters_dir.empty() || !outlets.empty())
        tt::step(verb, fmt::format("layers from {}: {:.2f} s", output, std::chrono::duration<double>(clock::now() - t1).count()));
      std::cout << "output: " << output << "\n"
                << "grid: " << r.cols << " x " << r.rows << " (columns x rows)\n"
                << fmt::format("spacing: {} {}\n", r.dx, r.dy) << "tiles: " << r.tiles << "\n"
                << "points: " << r.totals.points << "\n"
                << "basins: " << r.totals.pits.size() << "\n"
                << "branches: " << r.totals.branches << "\n"
                << "filled: " << r.filled << "\n";
      report_watersheds(ws);
      return 0;
    }
    const drainage::D8Encoding enc = drainage::parse_d8_encoding(encoding);
    const std::string prov = tt::provenance(argc, argv);
    // A version-2 .dv stores neither normalized flow nor branches: list them only for
    // version 1 and --rasters.
    const auto detail = dv_version == 1 || !rasters_dir.empty() ? drainage::NetworkDetail::Full : drainage::NetworkDetail::Lean;
    const double per_cell = drainage::untiled_bytes_per_cell(detail);
    if (raster_mode) {  // refused before reading anything when the whole grid does not fit
      const terrain::DemInfo info = terrain::read_dem_info(raster.empty() ? d8_input : raster);
      terrain::check_memory(double(info.rows) * double(info.cols) * per_cell,
                            fmt::format("an untiled run of {} x {} cells", info.cols, info.rows),
                            "run it tiled, which holds a tile at a time: --memory MiB (tiles sized to it) or "
                            "--tile-size 4096");
    }

    auto t0 = clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(clock::now() - t0).count(); };
    drainage::RasterInput input;  // mesh mode fills only .surface
    std::uint32_t flags = 0;
    if (!raster_mode) {
      const terrain::GridMesh mesh = terrain::read_mesh_ply(positional[0]);
      tt::step(verb, fmt::format("read mesh {} x {}: {:.2f} s", mesh.topo.cols, mesh.topo.rows, seconds()));
      const auto [nx, ny] = terrain::sampled_size(mesh, spacing);
      const double cells = double(nx) * double(ny);
      terrain::check_memory(cells * per_cell, fmt::format("sampling the mesh at {:g} m ({:.0f} points)", spacing, cells),
                            "give a coarser --spacing");
      t0 = clock::now();
      terrain::SampledSurface s = terrain::sample_pn_surface(mesh, spacing, tt::terminal_progress(verb, "sample"));
      const double dt = seconds();
      tt::step(verb, fmt::format("sampled {} points: {:.2f} s ({:.1f} M points/s), peak RSS so far {:.0f} MiB",
                                 s.grid.size(), dt, double(s.grid.size()) / dt * 1e-6, tt::peak_rss_mib()));
      if (s.fallbacks > 0)
        tt::warn(verb, fmt::format("{} samples used the flat triangle (PN patch folds over)", s.fallbacks));
      input.surface = std::move(s.grid);
      flags |= drainage::kDvFromPnSurface;
    } else {
      input = drainage::read_raster_input(raster, d8_input, enc);
      tt::step(verb, fmt::format("read {} x {}: {:.2f} s", input.surface.cols, input.surface.rows, seconds()));
    }
    // Every output lands together at the end, or none does.
    terrain::OutputSet outputs;
    if (!surface_out.empty())
      outputs.write([&] { terrain::write_geotiff(input.surface, outputs.stage(surface_out), prov); });

    t0 = clock::now();
    drainage::DrainageResult result = drainage::run_drainage(std::move(input), {fill, !keep_flats, breach, detail},
                                                             tt::terminal_progress(verb, "drainage"));
    flags |= result.dv_flags;
    for (const auto& [name, secs] : result.timings) tt::step(verb, fmt::format("  {}: {:.3f} s", name, secs));
    tt::step(verb, fmt::format("drainage (steps 2-6): {:.2f} s, peak RSS so far {:.0f} MiB", seconds(), tt::peak_rss_mib()));

    t0 = clock::now();
    drainage::DvHeader header = drainage::make_dv_header(result.surface, result.net, flags, prov);
    header.version = dv_version;
    std::vector<drainage::Watershed> ws;
    outputs.write([&] {
      const std::string staged_dv = outputs.stage(output);
      drainage::write_dv(staged_dv, header, result.surface, result.dirs, result.net);
      tt::step(verb, fmt::format("write {}: {:.2f} s", output, seconds()));
      if (!rasters_dir.empty())
        drainage::write_drainage_rasters(
            [&](const std::string& name) { return outputs.stage(std::filesystem::path(rasters_dir) / name); }, result,
            enc, prov);
      if (!outlets.empty()) ws = write_watersheds(staged_dv, outputs, prov);
    });
    outputs.commit();

    const drainage::Network& net = result.net;
    std::size_t counts[4] = {0, 0, 0, 0};
    for (std::uint8_t c : net.point_class)
      if (c < 4) ++counts[c];
    std::cout << "output: " << output << "\n"
              << "grid: " << result.surface.cols << " x " << result.surface.rows << " (columns x rows)\n"
              << fmt::format("spacing: {} {}\n", result.surface.geo.dx, result.surface.geo.dy)
              << "points: " << net.points << "\n"
              << "basins: " << net.pits.size() << "\n"
              << "pits: " << counts[3] << "\n"
              << "ridges: " << counts[0] << "\n"
              << "channels: " << counts[1] << "\n"
              << "junctions: " << counts[2] << "\n"
              << "branches: " << net.branch_count << "\n"
              << "flats: " << result.flats.flats << " (" << result.flats.undrainable << " undrainable)\n"
              << "filled: " << result.filled << "\n";
    if (breach) std::cout << fmt::format("carved: {} (deepest {:.2f} m)\n", result.carved, result.max_carve);
    report_watersheds(ws);
    return 0;
  });
}

}  // namespace

int main(int argc, char** argv) {
#ifdef TERRAIN_HAVE_MPI
  std::optional<tt::MpiSession> mpi;
  if (tt::mpi_launcher_size() > 0) mpi.emplace(argc, argv);
  const int code = build_drainage(argc, argv, mpi ? *mpi : drainage::single_process());
  if (code != 0 && mpi && mpi->size() > 1) mpi->abort(code);  // the other ranks may wait for this one
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
