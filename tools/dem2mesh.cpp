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
using terrain::tools::mesh::points_grid;
using terrain::tools::mesh::raster_grid;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The options as CLI11 fills them, and the options whose presence matters.
struct Options {
  std::string input, output, resample = "bilinear", weighting = "uniform", grid_out;
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
void add_grid_options(CLI::App& app, Options& o) {
  app.add_option("INPUT", o.input,
                 "DEM in any raster format GDAL reads (band 1), or scattered points")
      ->required();
  app.add_option("OUTPUT", o.output, "Mesh file to write (.ply)")->required();
  o.spacing_opt = app.add_option("--spacing", o.spacing,
                                 "Grid spacing in metres (default: the DEM's own spacing)")
                      ->check(tt::kPositive);
  o.bbox_opt =
      app.add_option("--bbox", o.bbox, "Crop to XMIN YMIN XMAX YMAX in the output CRS (metres)");
  o.center_opt =
      app.add_option("--center", o.center, "Crop centre E N in the output CRS (with --size)");
  auto* size_opt =
      app.add_option("--size", o.size, "Crop width and height W H in metres (with --center)");
  o.center_opt->needs(size_opt);
  size_opt->needs(o.center_opt);
  o.bbox_opt->excludes(o.center_opt)->excludes(size_opt);
  app.add_option("--utm-zone", o.utm_zone,
                 "UTM zone for a geographic DEM, e.g. 17 or 17N (default: zone of the centre)");
  app.add_option("--resample", o.resample, "Resampling kernel")
      ->check(CLI::IsMember({"bilinear", "cubic"}))
      ->capture_default_str();
  app.add_flag("--fill-nodata", o.req.fill_nodata,
               "Interpolate no-data samples inside the area (GDALFillNodata) instead of failing");
  app.add_option("--normal-weighting", o.weighting,
                 "Vertex normals: uniform (normalized sum of face normals, the Creases paper), "
                 "angle or area")
      ->check(CLI::IsMember({"uniform", "angle", "area"}))
      ->capture_default_str();
  app.add_option("--grid-out", o.grid_out, "Also write the resampled grid as a GeoTIFF");
  app.add_flag("--pyramid", o.pyramid,
               "Also write the mesh pyramid beside the mesh (OUTPUT with .tpyr): its levels of "
               "detail in tiles of "
               "64 x 64 cells, read by the view's windows (docs/formats.md)");
  tmesh::add_band_options(app, o.tile_size, o.memory_mib);
  app.add_option("--dequantize", o.dequantize,
                 "Integer heights (whole metres: SRTM, many national DEMs) terrace gentle slopes "
                 "into flats: heights "
                 "interpolated between the terraces' edges (the contours half-way between two "
                 "values), smoothed "
                 "within 0.1 of that; auto: when every height is a whole number")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
}

// Scattered points' interpolation and CRS, what INPUT holds, and the normals' fit.
void add_input_options(CLI::App& app, Options& o) {
  o.interp_opt =
      app.add_option(
             "--interpolation", o.interpolation,
             "Scattered points: natural (Sibson's C1 natural-neighbour interpolant, gradients "
             "fitted at the points), natural-c0 (natural-neighbour weighted mean) or linear "
             "(barycentric in the Delaunay triangle)")
          ->check(CLI::IsMember({"natural", "natural-c0", "linear"}))
          ->capture_default_str();
  o.max_edge_opt =
      app.add_option(
             "--max-edge", o.max_edge,
             "Scattered points: samples in Delaunay triangles with an edge longer than this "
             "(metres) are no-data, like those outside the convex hull")
          ->check(tt::kPositive);
  app.add_option("--src-crs", o.src_crs,
                 "The input's CRS (EPSG:4326, EPSG:32610, WKT, PROJ string) where the file has "
                 "none (XYZ text, CSV, "
                 "an .asc without .prj), or instead of the file's (as gdalwarp -s_srs)");
  app.add_option("--input", o.input_kind,
                 "What INPUT holds: raster (a grid, holes are no-data), points (scattered points, "
                 "triangulated: also "
                 "points that lie on a lattice, such as a decimated grid or lidar ground points at "
                 "cell centres, which "
                 "GDAL's XYZ driver would read as a grid full of holes), or auto (points when GDAL "
                 "opens no raster)")
      ->check(CLI::IsMember({"auto", "points", "raster"}))
      ->capture_default_str();
  app.add_flag("--fit-normals", o.fit,
               "Fit the vertex normals (Ceres) so that the PN surface between the vertices "
               "reproduces the source "
               "DEM's samples (or the scattered points); see docs/dem2mesh.md");
  auto* fit_it_opt = app.add_option("--fit-iterations", o.fit_opt.max_iterations,
                                    "--fit-normals: Levenberg-Marquardt iterations per round")
                         ->check(CLI::Range(1, 10000))
                         ->capture_default_str();
  auto* fit_reg_opt =
      app.add_option("--fit-regularization", o.fit_opt.regularization,
                     "--fit-normals: weight of the pull toward the starting normals (residual "
                     "weight * spacing * |n - n0|, metres)")
          ->check(CLI::Range(0.0, 1e6))
          ->capture_default_str();
  fit_it_opt->needs("--fit-normals");
  fit_reg_opt->needs("--fit-normals");
}

// The grid the options ask for: a raster resampled, or scattered points interpolated;
// `source_dem` / `source_points` receive the source samples for --fit-normals.
terrain::Grid grid_of(const Options& o, const terrain::GridRequest& req, const tt::Verbosity& verb,
                      terrain::Grid& source_dem, terrain::SourceSamples& source_points,
                      bool& points, std::vector<std::uint8_t>& filled) {
  const std::string& input = o.input;
  points = o.input_kind == "points" || (o.input_kind == "auto" && terrain::is_point_input(input));
  // Points on a lattice that GDAL reads as a grid (its XYZ driver): the errors say how to
  // read them as points (asked only on the way to an error: it opens the file again).
  auto lattice = [&] { return o.input_kind == "auto" && terrain::raster_driver(input) == "XYZ"; };
  if (points)
    return points_grid(input, req, {o.interpolation, o.max_edge, o.src_crs}, verb,
                       o.fit ? &source_points : nullptr, filled);
  for (const CLI::Option* opt : {o.interp_opt, o.max_edge_opt})
    if (*opt)
      throw terrain::Error(opt->get_name() + " applies to scattered points; '" + input +
                           "' is a raster" +
                           (lattice() ? " of XYZ text: pass --input points" : ""));
  try {
    return raster_grid(input, req, o.dequantize, o.src_crs, verb, o.fit ? &source_dem : nullptr,
                       filled);
  } catch (const terrain::NodataError& e) {
    if (!lattice()) throw;
    throw terrain::Error(
        std::string(e.what()) +
        " (it was read as a grid of XYZ text; for scattered points pass --input points)");
  }
}

// The crop and grid request of the options.
terrain::GridRequest request_of(const Options& o) {
  terrain::GridRequest req = o.req;
  if (*o.spacing_opt) req.spacing = o.spacing;
  if (*o.bbox_opt) req.bbox = o.bbox;
  if (*o.center_opt) {
    req.center = o.center;
    req.size = o.size;
  }
  if (!o.utm_zone.empty()) req.utm_zone = o.utm_zone;
  req.resampling = terrain::parse_resampling(o.resample);
  return req;
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
  if (o.tile_size > 0 || o.memory_mib > 0) {  // in bands of rows (mesh/banded.hpp)
    tmesh::check_banded(
        {o.input_kind == "points" || (o.input_kind == "auto" && terrain::is_point_input(o.input)),
         o.fit, o.req.fill_nodata, !grid_out.empty(), o.dequantize});
    const auto t0 = Clock::now();
    const tmesh::BandedResult r =
        tmesh::mesh_in_bands({o.input, output, pyramid, o.src_crs, o.dequantize, request_of(o), nw,
                              o.tile_size, o.memory_mib, provenance},
                             verb);
    tt::step(verb, fmt::format("{} x {} mesh in bands of {} rows: {:.2f} s", r.topo.cols,
                               r.topo.rows, r.band_rows, since(t0)));
    tmesh::print_mesh_summary(output, r.geo, r.topo, nw, nullptr, pyramid, r.pyramid_bytes);
    return 0;
  }
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
  if (o.fit) {
    t0 = Clock::now();
    const terrain::SourceSamples samples = points
                                               ? terrain::samples_inside_mesh(source_points, mesh)
                                               : terrain::dem_samples_for_mesh(source_dem, mesh);
    fit_rep = terrain::fit_pn_normals(mesh, samples, o.fit_opt,
                                      tt::terminal_progress(verb, "fit normals"));
    tt::step(verb,
             fmt::format(
                 "fit normals to {} samples ({} blocks, {} iterations): RMSE {:.3f} -> {:.3f} m, "
                 "max {:.3f} -> {:.3f} m: {:.2f} s",
                 fit_rep.after.samples, fit_rep.blocks, fit_rep.iterations, fit_rep.before.rmse,
                 fit_rep.after.rmse, fit_rep.before.max_abs, fit_rep.after.max_abs, since(t0)));
  }
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
  tmesh::print_mesh_summary(output, grid.geo, mesh.topo, nw, o.fit ? &fit_rep : nullptr, pyramid,
                            pyramid_bytes);
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
      "  dem2mesh lidar_ground.gpkg site.ply --spacing 10 --interpolation natural --max-edge 200 "
      "--fill-nodata\n"
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
