// build-drainage's run as named steps (job.hpp).
#include "drainage/job.hpp"

#include <fmt/format.h>

#include <malloc.h>

#include <chrono>
#include <filesystem>
#include <limits>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/pipeline.hpp"
#include "drainage/rasters.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/memory.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/pn_surface.hpp"

namespace drainage {

namespace {

using Clock = std::chrono::steady_clock;

// Times the steps of a run into the summary's timings.
struct StepClock {
  RunSummary& s;
  Clock::time_point t0 = Clock::now();
  void operator()(const std::string& name) {
    const auto t1 = Clock::now();
    s.timings.emplace_back(name, std::chrono::duration<double>(t1 - t0).count());
    t0 = t1;
  }
};

// Step 1 of an untiled run: the surface (a mesh's PN surface sampled at the job's spacing)
// or the raster's samples and codes; `flags` gets what the .dv records of the input.
RasterInput read_input(const DrainageJob& job, NetworkDetail detail, std::uint32_t& flags,
                       RunSummary& summary, const ProgressFor& progress) {
  const double per_cell = untiled_bytes_per_cell(detail);
  if (job.raster_mode()) {  // refused before reading anything when the whole grid does not fit
    const terrain::DemInfo info =
        terrain::read_dem_info(job.raster.empty() ? job.d8_input : job.raster);
    terrain::check_memory(
        double(info.rows) * double(info.cols) * per_cell,
        fmt::format("an untiled run of {} x {} cells", info.cols, info.rows),
        "run it tiled, which holds a tile at a time: --memory MiB (tiles sized to it) or "
        "--tile-size 4096");
    return read_raster_input(job.raster, job.d8_input, job.encoding);
  }
  std::string unused;  // why a pyramid beside it was not used
  const terrain::GridMesh mesh = terrain::read_terrain_mesh(job.mesh, nullptr, nullptr, &unused);
  if (!unused.empty()) summary.warnings.push_back(unused);
  const auto [nx, ny] = terrain::sampled_size(mesh, job.spacing);
  const double cells = double(nx) * double(ny);
  terrain::check_memory(
      cells * per_cell,
      fmt::format("sampling the mesh at {:g} m ({:.0f} points)", job.spacing, cells),
      "give a coarser --spacing");
  terrain::SampledSurface s = terrain::sample_pn_surface(mesh, job.spacing, progress("sample"));
  summary.pn_fallbacks = s.fallbacks;
  RasterInput input;
  input.surface = std::move(s.grid);
  flags |= kDvFromPnSurface;
  return input;
}

// The watersheds at the job's outlets on the .dv at `dv` (a staged path), staged in `outputs`.
std::vector<Watershed> stage_watersheds(const DrainageJob& job, const std::string& dv,
                                        terrain::OutputSet& outputs, const ProgressFor& progress) {
  return write_watersheds(dv, read_outlet_points(job.outlets, read_dv_header(dv).crs_wkt),
                          job.snap_distance, outputs.stage(job.watersheds),
                          outputs.stage(job.watershed_tif), job.provenance, progress("watersheds"));
}

// The classes and branches of a network, counted into the summary.
void count_classes(const Network& net, RunSummary& s) {
  std::size_t counts[4] = {0, 0, 0, 0};
  for (std::uint8_t c : net.point_class)
    if (c < 4) ++counts[c];
  s.points = net.points, s.basins = net.pits.size(), s.branches = net.branch_count;
  s.ridges = counts[0], s.channels = counts[1], s.junctions = counts[2], s.pits = counts[3];
}

}  // namespace

RunSummary run_untiled_job(const DrainageJob& job, const ProgressFor& progress) {
  RunSummary s;
  StepClock step{s};
  // A version-2 .dv stores neither normalized flow nor branches: list them only for
  // version 1 and --rasters.
  const auto detail =
      job.dv_version == 1 || !job.rasters_dir.empty() ? NetworkDetail::Full : NetworkDetail::Lean;
  std::uint32_t flags = 0;
  RasterInput input = read_input(job, detail, flags, s, progress);
  step("input");
  terrain::OutputSet outputs;  // every output lands together at the end, or none does
  if (!job.surface.empty())
    outputs.write(
        [&] { terrain::write_geotiff(input.surface, outputs.stage(job.surface), job.provenance); });
  DrainageResult result = run_drainage(
      std::move(input), {job.fill, !job.keep_flats, job.breach, detail}, progress("drainage"));
  flags |= result.dv_flags;
  for (const auto& [name, secs] : result.timings)
    s.timings.emplace_back("  " + std::string(name), secs);
  step("drainage (steps 2-6)");
  DvHeader header = make_dv_header(result.surface, result.net, flags, job.provenance);
  header.version = job.dv_version;
  outputs.write([&] {
    const std::string staged_dv = outputs.stage(job.output);
    write_dv(staged_dv, header, result.surface, result.dirs, result.net);
    if (!job.rasters_dir.empty())
      write_drainage_rasters(
          [&](const std::string& name) {
            return outputs.stage(std::filesystem::path(job.rasters_dir) / name);
          },
          result, job.encoding, job.provenance);
    if (!job.outlets.empty()) s.watersheds = stage_watersheds(job, staged_dv, outputs, progress);
  });
  outputs.commit();
  step("write");
  s.rows = result.surface.rows, s.cols = result.surface.cols, s.dx = result.surface.geo.dx,
  s.dy = result.surface.geo.dy;
  count_classes(result.net, s);
  s.flats = std::pair{result.flats.flats, result.flats.undrainable};
  s.filled = result.filled;
  if (job.breach) s.carved = std::pair{result.carved, result.max_carve};
  return s;
}

RunSummary run_tiled_job(const DrainageJob& job, const ProgressFor& progress,
                         const TileComm& comm) {
  // A tiled run frees and allocates its tiles' arrays (4 to 16 MiB each at tiles of 2048)
  // tile after tile: glibc keeps them in the heap below 32 MiB, and never trims it during
  // the run, instead of mapping fresh zeroed pages for every tile (docs/performance.md).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
  RunSummary s;
  StepClock step{s};
  TiledRun run;
  run.dem = job.raster, run.d8 = job.d8_input, run.encoding = job.encoding;
  run.tile = job.tile_size, run.fill = job.fill, run.resolve_flats = !job.keep_flats;
  run.provenance = job.provenance;
  // The .dv is staged and lands with the layers made from it (or none lands).
  terrain::OutputSet outputs;
  if (comm.root()) run.write_to = outputs.stage(job.output);
  TiledSummary r;
  outputs.write([&] { r = run_tiled_drainage(run, job.output, progress("tiles"), comm); });
  for (const auto& [name, secs] : r.timings) s.timings.emplace_back("  " + std::string(name), secs);
  step("tiled run");
  s.rows = r.rows, s.cols = r.cols, s.dx = r.dx, s.dy = r.dy, s.tiles = r.tiles;
  s.points = r.totals.points, s.basins = r.totals.pits.size(), s.branches = r.totals.branches,
  s.filled = r.filled;
  const auto& n = r.totals.classes;  // counted tile by tile in the network's second pass
  s.pits = n[0], s.ridges = n[1], s.channels = n[2], s.junctions = n[3];
  if (!comm.root()) return s;
  outputs.write([&] {
    if (!job.rasters_dir.empty())
      export_dv_rasters(
          run.write_to,
          [&](const std::string& name) {
            return outputs.stage(std::filesystem::path(job.rasters_dir) / name);
          },
          run.encoding, run.provenance);
    if (!job.outlets.empty()) s.watersheds = stage_watersheds(job, run.write_to, outputs, progress);
  });
  outputs.commit();
  step("layers from the .dv");
  return s;
}

std::string summary_text(const DrainageJob& job, const RunSummary& s) {
  std::string out = fmt::format(
      "output: {}\ngrid: {} x {} (columns x rows)\nspacing: {} {}\ntiles: {}\npoints: {}\nbasins: "
      "{}\npits: {}\n"
      "ridges: {}\nchannels: {}\njunctions: {}\nbranches: {}\n",
      job.output, s.cols, s.rows, s.dx, s.dy, s.tiles, s.points, s.basins, s.pits, s.ridges,
      s.channels, s.junctions, s.branches);
  out += s.flats ? fmt::format("flats: {} ({} undrainable)\n", s.flats->first, s.flats->second)
                 : std::string("flats: not counted (tiled run)\n");
  out += fmt::format("filled: {}\n", s.filled);
  if (s.carved)
    out += fmt::format("carved: {} (deepest {:.2f} m)\n", s.carved->first, s.carved->second);
  if (job.outlets.empty()) return out;
  out += "watersheds: " + job.watersheds + "\nwatershed_raster: " + job.watershed_tif + "\n";
  for (std::size_t k = 0; k < s.watersheds.size(); ++k) {
    const Watershed& w = s.watersheds[k];
    out += fmt::format(
        "outlet_{}: row {}, column {}, moved {:.2f} m, accumulated {}, cells {}, drains into {}\n",
        k, w.row, w.col, w.moved, w.accumulated, w.cells,
        w.downstream < 0 ? std::string("none") : std::to_string(w.downstream));
  }
  return out;
}

}  // namespace drainage
