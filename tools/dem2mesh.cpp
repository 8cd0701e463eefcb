// dem2mesh: a DEM GDAL reads, or scattered points (OGR point layer, XYZ text) -> a regular
// metric (UTM) grid -> the terrain mesh (PLY).
#include <fmt/format.h>

#include <chrono>
#include <iostream>

#include "common.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/memory.hpp"
#include "terrain/fit_normals.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/dequantize.hpp"
#include "terrain/prepare_grid.hpp"
#include "terrain/scattered.hpp"

namespace tt = terrain::tools;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A raster DEM: only the source window the crop needs is read (plus the kernel's margin),
// then resampled onto the grid.
// `source` (optional) receives the source samples read, in the grid's CRS, for --fit-normals.
// `src_crs` (--src-crs) replaces the raster's own CRS, as gdalwarp's -s_srs.
terrain::Grid raster_grid(const std::string& input, const terrain::GridRequest& req, const std::string& dequantize,
                          const std::string& src_crs, const tt::Verbosity& verb, terrain::Grid* source) {
  auto t0 = Clock::now();
  terrain::DemInfo info = terrain::read_dem_info(input);
  if (!src_crs.empty()) terrain::assign_crs(info.geo, src_crs);
  const terrain::GridPlan plan = terrain::plan_grid(info.geo, info.rows, info.cols, req);
  const terrain::RasterWindow& win = plan.source_window;
  // Every buffer counted before anything is read: the source window (4 bytes a sample,
  // kept for --fit-normals) and the mesh (measured peak 31 bytes a vertex on Logan at 10 m:
  // grid, positions, normals, the writer's buffer).
  terrain::check_memory(double(win.rows) * double(win.cols) * 4.0 + double(plan.rows) * double(plan.cols) * 32.0,
                        fmt::format("a {} x {} mesh from {} x {} source samples", plan.cols, plan.rows, win.cols,
                                    win.rows),
                        "crop it (--bbox, or --center with --size) or give a coarser --spacing");
  terrain::Grid dem = terrain::read_dem(input, tt::terminal_progress(verb, "read"), win);
  if (!src_crs.empty()) terrain::assign_crs(dem.geo, src_crs);
  tt::step(verb, fmt::format("read {} x {} of {} x {} samples: {:.2f} s", win.cols, win.rows, info.cols, info.rows,
                             since(t0)));
  // Integer heights terrace gentle slopes into flats: heights between the terraces' contours.
  if (dequantize == "on" || (dequantize == "auto" && terrain::is_integer_dem(dem))) {
    t0 = Clock::now();
    const double change = terrain::dequantize(dem);
    tt::step(verb, fmt::format("integer heights: steps smoothed between the terraces' contours "
                               "(largest change {:.2f}): {:.2f} s",
                               change, since(t0)));
  }
  t0 = Clock::now();
  terrain::PreparedGrid prepared = terrain::resample_to_plan(dem, plan, req, tt::terminal_progress(verb, "resample"));
  for (const auto& w : prepared.warnings) tt::warn(verb, w);
  if (prepared.filled > 0) tt::warn(verb, fmt::format("filled {} no-data samples by interpolation", prepared.filled));
  tt::step(verb, fmt::format("grid {} x {} at {} m: {:.2f} s", prepared.grid.cols, prepared.grid.rows,
                             prepared.grid.geo.dx, since(t0)));
  if (source) *source = std::move(dem);
  return std::move(prepared.grid);
}

struct PointOptions {
  std::string interpolation;  // linear, natural, natural-c0
  double max_edge;
  std::string src_crs;
};

// Scattered points: read, projected to UTM if geographic, triangulated and interpolated
// onto the grid; no-data samples (outside the hull, long triangles) are an error unless
// --fill-nodata, as for rasters.
terrain::Grid points_grid(const std::string& input, const terrain::GridRequest& req, const PointOptions& o,
                          const tt::Verbosity& verb, terrain::SourceSamples* source) {
  if (!req.spacing) throw terrain::Error("scattered points need --spacing (the grid spacing in metres)");
  auto t0 = Clock::now();
  terrain::PointCloud points = terrain::read_points(input, tt::terminal_progress(verb, "read"));
  terrain::project_points(points, o.src_crs, req.utm_zone);
  tt::step(verb, fmt::format("read {} points ({}): {:.2f} s", points.size(), points.format, since(t0)));
  if (source) *source = {points.x, points.y, points.z};
  terrain::PointGridRequest pr;
  pr.spacing = *req.spacing;
  pr.interpolation = terrain::parse_point_interpolation(o.interpolation);
  pr.max_edge = o.max_edge;
  if (req.bbox) pr.bbox = req.bbox;
  if (req.center && req.size)
    pr.bbox = std::array<double, 4>{(*req.center)[0] - 0.5 * (*req.size)[0], (*req.center)[1] - 0.5 * (*req.size)[1],
                                    (*req.center)[0] + 0.5 * (*req.size)[0], (*req.center)[1] + 0.5 * (*req.size)[1]};
  t0 = Clock::now();
  terrain::PointGridResult r = terrain::points_to_grid(points, pr, tt::terminal_progress(verb, "interpolate"));
  if (r.duplicates) tt::warn(verb, fmt::format("{} points repeat an earlier x, y: their z is averaged", r.duplicates));
  tt::step(verb, fmt::format("Delaunay triangulation of {} points, grid {} x {} at {} m ({}): {:.2f} s", r.vertices,
                             r.grid.cols, r.grid.rows, pr.spacing, o.interpolation, since(t0)));
  if (r.nodata) {
    if (!req.fill_nodata)
      throw terrain::Error(fmt::format("{} of {} grid samples lie outside the points' convex hull{}; crop with --bbox "
                                       "or pass --fill-nodata",
                                       r.nodata, r.grid.size(), o.max_edge > 0 ? " or in triangles over --max-edge" : ""));
    tt::warn(verb, fmt::format("filled {} no-data samples by interpolation", terrain::fill_nodata(r.grid)));
  }
  return std::move(r.grid);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Turn a DEM into a terrain mesh: reproject a geographic DEM onto UTM, crop, resample,\n"
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
      "  dem2mesh lidar_ground.gpkg site.ply --spacing 10 --interpolation natural --max-edge 200 --fill-nodata\n"
      "  dem2mesh survey.xyz site.ply --spacing 5 --src-crs EPSG:32610 --bbox 561000 5113000 564000 5116000\n"
      "  dem2mesh srtm_no_prj.asc srtm.ply --src-crs EPSG:4326            # an SRTM grid without its .prj\n"
      "  dem2mesh data/msh_2007_utm10n_10m.tif msh_50m_fit.ply --spacing 50 --fit-normals\n\n"
      "Output: stdout gets 'key: value' lines describing the mesh; progress and warnings go to stderr.\n"
      "See docs/dem2mesh.md for the grid, triangulation and file conventions.");
  app.set_version_flag("--version", tt::version());

  std::string input, output, resample = "bilinear", weighting = "uniform", grid_out;
  std::string interpolation = "natural", src_crs;
  double max_edge = 0.0;
  terrain::GridRequest req;
  std::array<double, 4> bbox{};
  std::array<double, 2> center{}, size{};
  std::string utm_zone;
  double spacing = 0.0;
  tt::Verbosity verb;
  app.add_option("INPUT", input, "DEM in any raster format GDAL reads (band 1), or scattered points")->required();
  app.add_option("OUTPUT", output, "Mesh file to write (.ply)")->required();
  auto* spacing_opt = app.add_option("--spacing", spacing, "Grid spacing in metres (default: the DEM's own spacing)")
                          ->check(CLI::PositiveNumber);
  auto* bbox_opt = app.add_option("--bbox", bbox, "Crop to XMIN YMIN XMAX YMAX in the output CRS (metres)");
  auto* center_opt = app.add_option("--center", center, "Crop centre E N in the output CRS (with --size)");
  auto* size_opt = app.add_option("--size", size, "Crop width and height W H in metres (with --center)");
  center_opt->needs(size_opt);
  size_opt->needs(center_opt);
  bbox_opt->excludes(center_opt)->excludes(size_opt);
  app.add_option("--utm-zone", utm_zone, "UTM zone for a geographic DEM, e.g. 17 or 17N (default: zone of the centre)");
  app.add_option("--resample", resample, "Resampling kernel")
      ->check(CLI::IsMember({"bilinear", "cubic"}))
      ->capture_default_str();
  app.add_flag("--fill-nodata", req.fill_nodata,
               "Interpolate no-data samples inside the area (GDALFillNodata) instead of failing");
  app.add_option("--normal-weighting", weighting,
                 "Vertex normals: uniform (normalized sum of face normals, the Creases paper), angle or area")
      ->check(CLI::IsMember({"uniform", "angle", "area"}))
      ->capture_default_str();
  app.add_option("--grid-out", grid_out, "Also write the resampled grid as a GeoTIFF");
  std::string dequantize = "auto";
  app.add_option("--dequantize", dequantize,
                 "Integer heights (whole metres: SRTM, many national DEMs) terrace gentle slopes into flats: heights "
                 "interpolated between the terraces' edges (the contours half-way between two values), smoothed "
                 "within 0.1 of that; auto: when every height is a whole number")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  auto* interp_opt = app.add_option("--interpolation", interpolation,
                                    "Scattered points: natural (Sibson's C1 natural-neighbour interpolant, gradients "
                                    "fitted at the points), natural-c0 (natural-neighbour weighted mean) or linear "
                                    "(barycentric in the Delaunay triangle)")
                         ->check(CLI::IsMember({"natural", "natural-c0", "linear"}))
                         ->capture_default_str();
  auto* max_edge_opt = app.add_option("--max-edge", max_edge,
                                      "Scattered points: samples in Delaunay triangles with an edge longer than this "
                                      "(metres) are no-data, like those outside the convex hull")
                           ->check(CLI::PositiveNumber);
  app.add_option("--src-crs", src_crs,
                 "The input's CRS (EPSG:4326, EPSG:32610, WKT, PROJ string) where the file has none (XYZ text, CSV, "
                 "an .asc without .prj), or instead of the file's (as gdalwarp -s_srs)");
  std::string input_kind = "auto";
  app.add_option("--input", input_kind,
                 "What INPUT holds: raster (a grid, holes are no-data), points (scattered points, triangulated: also "
                 "points that lie on a lattice, such as a decimated grid or lidar ground points at cell centres, which "
                 "GDAL's XYZ driver would read as a grid full of holes), or auto (points when GDAL opens no raster)")
      ->check(CLI::IsMember({"auto", "points", "raster"}))
      ->capture_default_str();
  bool fit = false;
  terrain::NormalFitOptions fit_opt;
  app.add_flag("--fit-normals", fit,
               "Fit the vertex normals (Ceres) so that the PN surface between the vertices reproduces the source "
               "DEM's samples (or the scattered points); see docs/dem2mesh.md");
  auto* fit_it_opt = app.add_option("--fit-iterations", fit_opt.max_iterations,
                                    "--fit-normals: Levenberg-Marquardt iterations per round")
                         ->check(CLI::Range(1, 10000))
                         ->capture_default_str();
  auto* fit_reg_opt = app.add_option("--fit-regularization", fit_opt.regularization,
                                     "--fit-normals: weight of the pull toward the starting normals (residual "
                                     "weight * spacing * |n - n0|, metres)")
                          ->check(CLI::Range(0.0, 1e6))
                          ->capture_default_str();
  fit_it_opt->needs("--fit-normals");
  fit_reg_opt->needs("--fit-normals");
  tt::add_verbosity_flags(app, verb);

  return tt::run_main(app, argc, argv, [&]() {
    if (!output.ends_with(".ply")) throw terrain::Error("OUTPUT must be a .ply file: '" + output + "'");
    tt::check_distinct_paths({input}, {output, grid_out});
    tt::warn_stale_temporaries(verb, {output, grid_out});
    terrain::check_output_path(output);
    if (!grid_out.empty()) terrain::check_output_path(grid_out);
    if (*spacing_opt) req.spacing = spacing;
    if (*bbox_opt) req.bbox = bbox;
    if (*center_opt) {
      req.center = center;
      req.size = size;
    }
    if (!utm_zone.empty()) req.utm_zone = utm_zone;
    req.resampling = terrain::parse_resampling(resample);
    const terrain::NormalWeighting nw = terrain::parse_normal_weighting(weighting);

    terrain::Grid grid, source_dem;
    terrain::SourceSamples source_points;
    const bool points = input_kind == "points" || (input_kind == "auto" && terrain::is_point_input(input));
    // Points on a lattice that GDAL reads as a grid (its XYZ driver): the errors say how to
    // read them as points (asked only on the way to an error: it opens the file again).
    auto lattice = [&] { return input_kind == "auto" && terrain::raster_driver(input) == "XYZ"; };
    if (points) {
      grid = points_grid(input, req, {interpolation, max_edge, src_crs}, verb, fit ? &source_points : nullptr);
    } else {
      for (const CLI::Option* o : {interp_opt, max_edge_opt})
        if (*o)
          throw terrain::Error(o->get_name() + " applies to scattered points; '" + input + "' is a raster" +
                               (lattice() ? " of XYZ text: pass --input points" : ""));
      try {
        grid = raster_grid(input, req, dequantize, src_crs, verb, fit ? &source_dem : nullptr);
      } catch (const terrain::Error& e) {
        const std::string what = e.what();
        if (what.find("no-data") == std::string::npos || !lattice()) throw;
        throw terrain::Error(what + " (it was read as a grid of XYZ text; for scattered points pass --input points)");
      }
    }
    terrain::OutputSet outputs;  // the mesh and the grid land together, or neither does
    if (!grid_out.empty())
      outputs.write([&] { terrain::write_geotiff(grid, outputs.stage(grid_out), tt::provenance(argc, argv)); });

    auto t0 = Clock::now();
    terrain::GridMesh mesh = terrain::make_grid_mesh(grid, nw);
    mesh.provenance = tt::provenance(argc, argv);
    tt::step(verb, fmt::format("mesh and normals: {:.2f} s", since(t0)));
    terrain::NormalFitReport fit_rep;
    if (fit) {
      t0 = Clock::now();
      const terrain::SourceSamples samples = points ? terrain::samples_inside_mesh(source_points, mesh)
                                                    : terrain::dem_samples_for_mesh(source_dem, mesh);
      fit_rep = terrain::fit_pn_normals(mesh, samples, fit_opt, tt::terminal_progress(verb, "fit normals"));
      tt::step(verb, fmt::format("fit normals to {} samples ({} blocks, {} iterations): RMSE {:.3f} -> {:.3f} m, "
                                 "max {:.3f} -> {:.3f} m: {:.2f} s",
                                 fit_rep.after.samples, fit_rep.blocks, fit_rep.iterations, fit_rep.before.rmse,
                                 fit_rep.after.rmse, fit_rep.before.max_abs, fit_rep.after.max_abs, since(t0)));
    }

    t0 = Clock::now();
    outputs.write([&] { terrain::write_mesh_ply(mesh, outputs.stage(output)); });
    outputs.commit();
    tt::step(verb, fmt::format("write {}: {:.2f} s", output, since(t0)));

    const auto& g = grid.geo;
    std::cout << "output: " << output << "\n"
              << "crs: " << terrain::crs_name(g) << (g.epsg ? fmt::format(" (EPSG:{})", g.epsg) : "") << "\n"
              << "grid: " << grid.cols << " x " << grid.rows << " (columns x rows)\n"
              << fmt::format("spacing: {} {}\n", g.dx, g.dy)
              << fmt::format("extent: {:.3f} {:.3f} {:.3f} {:.3f}\n", g.x0, g.y0 - double(grid.rows) * g.dy,
                             g.x0 + double(grid.cols) * g.dx, g.y0)
              << "vertices: " << mesh.n_vertices() << "\n"
              << "faces: " << mesh.n_faces() << "\n"
              << "normal_weighting: " << terrain::to_string(nw) << "\n";
    if (fit)
      std::cout << fmt::format("normals: fitted\nfit_samples: {}\nfit_rmse_before: {:.4f}\nfit_rmse_after: {:.4f}\n"
                               "fit_max_before: {:.4f}\nfit_max_after: {:.4f}\nfit_seconds: {:.2f}\n",
                               fit_rep.after.samples, fit_rep.before.rmse, fit_rep.after.rmse,
                               fit_rep.before.max_abs, fit_rep.after.max_abs, fit_rep.seconds);
    return 0;
  });
}
