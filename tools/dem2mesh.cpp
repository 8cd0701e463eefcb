// dem2mesh: a DEM GDAL reads, or scattered points (OGR point layer, XYZ text) -> a regular
// metric (UTM) grid -> the terrain mesh (PLY).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <optional>

#include "common.hpp"
#include "mesh/banded.hpp"
#include "mesh/grid_input.hpp"
#include "mesh/options.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/dequantize.hpp"
#include "terrain/fit_normals.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/memory.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"
#include "terrain/prepare_grid.hpp"
#include "terrain/scattered.hpp"

namespace tt = terrain::tools;
namespace tmesh = terrain::tools::mesh;
using tmesh::Options;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// --tile-size / --memory: the mesh made and written in bands of rows (mesh/banded.hpp).
int run_banded(const Options& o, const std::string& pyramid, terrain::NormalWeighting nw,
               const std::string& provenance, const tt::Verbosity& verb) {
  tmesh::check_banded(
      {o.input_kind == "points" || (o.input_kind == "auto" && terrain::is_point_input(o.input)),
       o.fit, o.req.fill_nodata, !o.grid_out.empty(), o.dequantize});
  const auto t0 = Clock::now();
  const tmesh::BandedResult r =
      tmesh::mesh_in_bands({o.input, o.output, pyramid, o.src_crs, o.dequantize, request_of(o), nw,
                            o.tile_size, o.memory_mib, provenance},
                           verb);
  tt::step(verb, fmt::format("{} x {} mesh in bands of {} rows: {:.2f} s", r.topo.cols, r.topo.rows,
                             r.band_rows, since(t0)));
  tmesh::print_mesh_summary(o.output, r.geo, r.topo, nw, nullptr, pyramid, r.pyramid_bytes,
                            r.topo.n_faces(), 0);
  return 0;
}

// --fit-normals: the mesh's normals fitted to the source's samples under it (the scattered
// `points` when given, else the DEM's).
terrain::NormalFitReport fit_normals(const Options& o, terrain::GridMesh& mesh,
                                     const terrain::SourceSamples* points,
                                     const terrain::Grid& source_dem, const tt::Verbosity& verb) {
  const auto t0 = Clock::now();
  const terrain::SourceSamples samples = points ? terrain::samples_inside_mesh(*points, mesh)
                                                : terrain::dem_samples_for_mesh(source_dem, mesh);
  const terrain::NormalFitReport rep =
      terrain::fit_pn_normals(mesh, samples, o.fit_opt, tt::terminal_progress(verb, "fit normals"));
  tt::step(
      verb,
      fmt::format("fit normals to {} samples ({} blocks, {} iterations): RMSE {:.3f} -> {:.3f} m, "
                  "max {:.3f} -> {:.3f} m: {:.2f} s",
                  rep.after.samples, rep.blocks, rep.iterations, rep.before.rmse, rep.after.rmse,
                  rep.before.max_abs, rep.after.max_abs, since(t0)));
  return rep;
}

// The run: grid, mesh and normals (fitted with --fit-normals), written with --grid-out.
int run(const Options& o, const std::string& provenance, const tt::Verbosity& verb) {
  const std::string &output = o.output, &grid_out = o.grid_out;
  if (!output.ends_with(".ply"))
    throw terrain::Error("OUTPUT must be a .ply file: '" + output + "'");
  const std::string pyramid = o.pyramid ? terrain::pyramid_path_of(output) : std::string();
  tt::check_distinct_paths({o.input}, {output, grid_out, pyramid});
  tt::warn_stale_temporaries(verb, {output, grid_out, pyramid});
  terrain::check_output_path(output);
  if (!pyramid.empty()) terrain::check_output_path(pyramid);
  if (!grid_out.empty()) terrain::check_output_path(grid_out);
  const terrain::NormalWeighting nw = terrain::parse_normal_weighting(o.weighting);
  if (o.tile_size > 0 || o.memory_mib > 0) return run_banded(o, pyramid, nw, provenance, verb);
  const terrain::GridRequest req = request_of(o);
  terrain::Grid source_dem;
  terrain::SourceSamples source_points;
  bool points = false;
  std::vector<std::uint8_t> filled;
  const terrain::Grid grid = grid_of(o, req, verb, source_dem, source_points, points, filled);
  terrain::OutputSet outputs;  // the mesh and the grid land together, or neither does
  if (!grid_out.empty())
    outputs.write([&] { terrain::write_geotiff(grid, outputs.stage(grid_out), provenance); });
  auto t0 = Clock::now();
  terrain::GridMesh mesh = terrain::grid_mesh_frame(grid);
  mesh.provenance = provenance;
  mesh.filled.assign(filled.begin(), filled.end());
  const bool whole = o.fit || !pyramid.empty();  // else the rows are made as they are written
  if (whole) {
    terrain::GridMesh made = terrain::make_grid_mesh(grid, nw);
    mesh.positions = std::move(made.positions), mesh.normals = std::move(made.normals);
    tt::step(verb, fmt::format("mesh and normals: {:.2f} s", since(t0)));
  }
  terrain::NormalFitReport fit_rep;
  if (o.fit) fit_rep = fit_normals(o, mesh, points ? &source_points : nullptr, source_dem, verb);
  t0 = Clock::now();
  outputs.write([&] {
    whole ? terrain::write_mesh_ply(mesh, outputs.stage(output))
          : terrain::write_grid_mesh_ply(mesh, grid, nw, outputs.stage(output));
  });
  tt::step(verb, fmt::format("write {}: {:.2f} s", output, since(t0)));
  std::uint64_t pyramid_bytes = 0;
  if (!pyramid.empty()) {
    t0 = Clock::now();
    outputs.write([&] {
      pyramid_bytes =
          terrain::write_mesh_pyramid(mesh, outputs.stage(pyramid), terrain::kLevelBlock, pyramid);
    });
    tt::step(verb, fmt::format("levels of detail and {}: {:.2f} s", pyramid, since(t0)));
  }
  outputs.commit();
  const std::size_t outside =
      std::size_t(std::count(mesh.filled.begin(), mesh.filled.end(), terrain::kOutside));
  tmesh::print_mesh_summary(output, grid.geo, mesh.topo, nw, o.fit ? &fit_rep : nullptr, pyramid,
                            pyramid_bytes, outside ? mesh.kept_faces().size() : mesh.n_faces(),
                            outside);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Turn a DEM into a terrain mesh: reproject a geographic DEM onto UTM, crop, resample,\n"
      "triangulate (2 triangles per cell) and write a binary PLY with vertex normals and\n"
      "its georeferencing. Scattered points (an OGR point layer: GeoPackage, Shapefile, CSV\n"
      "with X/Y/Z columns; or XYZ text) are recognised by content, triangulated (Delaunay)\n"
      "and interpolated onto the grid first.",
      "dem2mesh"};
  app.footer(
      "Examples:\n"
      "  dem2mesh data/msh_2007_utm10n_10m.tif msh_50m.ply --spacing 50\n"
      "  dem2mesh eno_geographic.tif eno.ply --spacing 10 --utm-zone 17N\n"
      "  dem2mesh dem.tif crater.ply --center 562500 5116500 --size 2000 2000\n"
      "  dem2mesh lidar_ground.gpkg site.ply --spacing 10 --interpolation natural --max-edge 200\n"
      "  dem2mesh catchment_clipped.tif basin.ply             # no-data outside: the mesh "
      "follows the data\n"
      "  dem2mesh coast.tif coast.ply --nodata 0              # a DEM whose sea is 0, with no "
      "no-data value\n"
      "  dem2mesh survey.xyz site.ply --spacing 5 --src-crs EPSG:32610 --bbox 561000 5113000 "
      "564000 5116000\n"
      "  dem2mesh srtm_no_prj.asc srtm.ply --src-crs EPSG:4326            # an SRTM grid without "
      "its .prj\n"
      "  dem2mesh data/msh_2007_utm10n_10m.tif msh_50m_fit.ply --spacing 50 --fit-normals\n"
      "  dem2mesh lidar_2m.tif lidar.ply --pyramid --memory 1024        # a DEM larger than "
      "memory, in bands\n\n"
      "Output: stdout gets 'key: value' lines describing the mesh; progress and warnings go to "
      "stderr.\n"
      "See docs/dem2mesh.md for the grid, triangulation and file conventions.");
  app.set_version_flag("--version", tt::version());

  Options o;
  tt::Verbosity verb;
  add_grid_options(app, o);
  add_input_options(app, o);
  tt::add_verbosity_flags(app, verb);
  return tt::run_main(app, argc, argv, [&]() { return run(o, tt::provenance(argc, argv), verb); });
}
