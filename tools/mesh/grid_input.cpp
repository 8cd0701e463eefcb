#include "mesh/grid_input.hpp"

#include <fmt/format.h>

#include <chrono>
#include <iostream>

#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/dequantize.hpp"
#include "terrain/fit_normals.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/memory.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/prepare_grid.hpp"
#include "terrain/scattered.hpp"

namespace terrain::tools::mesh {

namespace tt = terrain::tools;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// What became of the no-data samples (GridMesh::filled): a step at -v, no warning (the
// outline following the data is the rule, docs/dem2mesh.md "No-data").
void report_nodata(const tt::Verbosity& verb, const std::vector<std::uint8_t>& mask) {
  std::size_t counts[4] = {0, 0, 0, 0};
  for (const std::uint8_t m : mask) ++counts[m & 3];
  if (counts[terrain::kInvented] > 0)
    tt::warn(verb, fmt::format("filled {} no-data samples by interpolation (--fill-nodata)",
                               counts[terrain::kInvented]));
  if (counts[terrain::kOutside] + counts[terrain::kVoidFilled] > 0)
    tt::step(verb, fmt::format("no-data: {} samples outside the data (no faces), {} in small "
                               "voids filled",
                               counts[terrain::kOutside], counts[terrain::kVoidFilled]));
}

}  // namespace

// A raster DEM: only the source window the crop needs is read (plus the kernel's margin),
// then resampled onto the grid.
// `source` (optional) receives the source samples read, in the grid's CRS, for --fit-normals.
// `src_crs` (--src-crs) replaces the raster's own CRS, as gdalwarp's -s_srs.
terrain::Grid raster_grid(const std::string& input, const terrain::GridRequest& req,
                          const std::string& dequantize, const std::string& src_crs,
                          std::optional<double> nodata, const tt::Verbosity& verb,
                          terrain::Grid* source, std::vector<std::uint8_t>& filled) {
  auto t0 = Clock::now();
  terrain::DemInfo info = terrain::read_dem_info(input);
  if (!src_crs.empty()) terrain::assign_crs(info.geo, src_crs);
  const terrain::GridPlan plan = terrain::plan_grid(info.geo, info.rows, info.cols, req);
  const terrain::RasterWindow& win = plan.source_window;
  // Every buffer counted before anything is read: the source window (4 bytes a sample,
  // kept for --fit-normals) and the mesh (measured peak 31 bytes a vertex on Logan at 10 m:
  // grid, positions, normals, the writer's buffer).
  terrain::check_memory(
      double(win.rows) * double(win.cols) * 4.0 + double(plan.rows) * double(plan.cols) * 32.0,
      fmt::format("a {} x {} mesh from {} x {} source samples", plan.cols, plan.rows, win.cols,
                  win.rows),
      "crop it (--bbox, or --center with --size) or give a coarser --spacing");
  terrain::Grid dem = terrain::read_dem(input, tt::terminal_progress(verb, "read"), win);
  if (nodata) dem.mark_nodata(float(*nodata));
  if (!src_crs.empty()) terrain::assign_crs(dem.geo, src_crs);
  tt::step(verb, fmt::format("read {} x {} of {} x {} samples: {:.2f} s", win.cols, win.rows,
                             info.cols, info.rows, since(t0)));
  // Integer heights terrace gentle slopes into flats: heights between the terraces' contours.
  if (dequantize == "on" || (dequantize == "auto" && terrain::is_integer_dem(dem))) {
    t0 = Clock::now();
    const double change = terrain::dequantize(dem);
    tt::step(verb, fmt::format("integer heights: steps smoothed between the terraces' contours "
                               "(largest change {:.2f}): {:.2f} s",
                               change, since(t0)));
  }
  t0 = Clock::now();
  terrain::PreparedGrid prepared =
      terrain::resample_to_plan(dem, plan, req, tt::terminal_progress(verb, "resample"));
  for (const auto& w : prepared.warnings) tt::warn(verb, w);
  filled = std::move(prepared.filled_mask);
  report_nodata(verb, filled);
  tt::step(verb, fmt::format("grid {} x {} at {} m: {:.2f} s", prepared.grid.cols,
                             prepared.grid.rows, prepared.grid.geo.dx, since(t0)));
  if (source) *source = std::move(dem);
  return std::move(prepared.grid);
}

// Scattered points: read, projected to UTM if geographic, triangulated and interpolated
// onto the grid; no-data samples (outside the hull, long triangles) are outside the data,
// as for rasters.
terrain::Grid points_grid(const std::string& input, const terrain::GridRequest& req,
                          const PointOptions& o, const tt::Verbosity& verb,
                          terrain::SourceSamples* source, std::vector<std::uint8_t>& filled) {
  if (!req.spacing)
    throw terrain::Error("scattered points need --spacing (the grid spacing in metres)");
  auto t0 = Clock::now();
  terrain::PointCloud points = terrain::read_points(input, tt::terminal_progress(verb, "read"));
  terrain::project_points(points, o.src_crs, req.utm_zone);
  tt::step(verb,
           fmt::format("read {} points ({}): {:.2f} s", points.size(), points.format, since(t0)));
  if (source) *source = {points.x, points.y, points.z};
  terrain::PointGridRequest pr;
  pr.spacing = *req.spacing;
  pr.interpolation = terrain::parse_point_interpolation(o.interpolation);
  pr.max_edge = o.max_edge;
  if (req.bbox) pr.bbox = req.bbox;
  if (req.center && req.size)
    pr.bbox = std::array<double, 4>{
        (*req.center)[0] - 0.5 * (*req.size)[0], (*req.center)[1] - 0.5 * (*req.size)[1],
        (*req.center)[0] + 0.5 * (*req.size)[0], (*req.center)[1] + 0.5 * (*req.size)[1]};
  t0 = Clock::now();
  terrain::PointGridResult r =
      terrain::points_to_grid(points, pr, tt::terminal_progress(verb, "interpolate"));
  if (r.duplicates)
    tt::warn(verb,
             fmt::format("{} points repeat an earlier x, y: their z is averaged", r.duplicates));
  tt::step(verb, fmt::format(
                     "Delaunay triangulation of {} points, grid {} x {} at {} m ({}): {:.2f} s",
                     r.vertices, r.grid.cols, r.grid.rows, pr.spacing, o.interpolation, since(t0)));
  if (r.nodata == r.grid.size())
    throw terrain::Error(fmt::format(
        "all {} grid samples lie outside the points' convex hull{}; crop with --bbox to the points",
        r.grid.size(), o.max_edge > 0 ? " or in triangles over --max-edge" : ""));
  if (r.nodata) {  // outside the points' hull (or in triangles over --max-edge)
    filled =
        req.fill_nodata ? r.grid.nodata_mask() : terrain::classify_nodata(r.grid, req.max_void);
    terrain::fill_nodata(r.grid);
    report_nodata(verb, filled);
  }
  return std::move(r.grid);
}

void print_mesh_summary(const std::string& output, const terrain::Georef& g,
                        const terrain::GridTopology& topo, terrain::NormalWeighting nw,
                        const terrain::NormalFitReport* fit, const std::string& pyramid,
                        std::uint64_t pyramid_bytes, std::size_t faces, std::size_t outside) {
  std::cout << "output: " << output << "\n"
            << "crs: " << terrain::crs_name(g) << (g.epsg ? fmt::format(" (EPSG:{})", g.epsg) : "")
            << "\n"
            << "grid: " << topo.cols << " x " << topo.rows << " (columns x rows)\n"
            << fmt::format("spacing: {} {}\n", g.dx, g.dy)
            << fmt::format("extent: {:.3f} {:.3f} {:.3f} {:.3f}\n", g.x0,
                           g.y0 - double(topo.rows) * g.dy, g.x0 + double(topo.cols) * g.dx, g.y0)
            << "vertices: " << topo.n_vertices() << "\n"
            << "faces: " << faces << "\n"
            << (outside
                    ? fmt::format("outside_vertices: {} (no data: no face touches them)\n", outside)
                    : "")
            << "normal_weighting: " << terrain::to_string(nw) << "\n";
  if (fit)
    std::cout << fmt::format(
        "normals: fitted\nfit_samples: {}\nfit_rmse_before: {:.4f}\nfit_rmse_after: {:.4f}\n"
        "fit_max_before: {:.4f}\nfit_max_after: {:.4f}\nfit_seconds: {:.2f}\n",
        fit->after.samples, fit->before.rmse, fit->after.rmse, fit->before.max_abs,
        fit->after.max_abs, fit->seconds);
  if (!pyramid.empty())
    std::cout << "pyramid: " << pyramid
              << fmt::format(" ({:.1f} MB)\n", double(pyramid_bytes) / 1e6);
}

}  // namespace terrain::tools::mesh
