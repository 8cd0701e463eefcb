// terrain-inspect info: 'key: value' lines for a DEM, a mesh, its pyramid, scattered points
// or a .dv.
#include "inspect/commands.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/rasters.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/plan_map.hpp"
#include "renderer/core/vector_file.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/image_io.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"
#include "terrain/scattered.hpp"

namespace terrain::tools::inspect {

namespace {

std::string crs_line(const std::string& wkt, int epsg) {
  terrain::Georef g;
  g.crs_wkt = wkt;
  return terrain::crs_name(g) + (epsg ? fmt::format(" (EPSG:{})", epsg) : "");
}

void print_stats(const terrain::ElevationStats& s) {
  std::cout << fmt::format(
      "elevation_min: {:.3f}\nelevation_max: {:.3f}\nelevation_mean: {:.3f}\n"
      "elevation_stddev: {:.3f}\n",
      s.min, s.max, s.mean, s.stddev);
}

// What later steps added to a mesh: Voronoi weights, denoising, filled vertices, fitted
// normals.
void print_mesh_attributes(const terrain::GridMesh& m) {
  if (m.voronoi.empty()) {
    std::cout << "voronoi_weights: no (add them: denoise-normals MESH OUT --iterations 0)\n";
  } else {
    double total = 0, lo = 1e300, hi = 0;
    for (float a : m.voronoi.vertex_areas)
      total += a, lo = std::min(lo, double(a)), hi = std::max(hi, double(a));
    std::cout
        << "voronoi_weights: yes (corner areas, voronoi_area, tangent frames)\n"
        << fmt::format(
               "voronoi_area_total: {:.1f}\nvoronoi_area_min: {:.3f}\nvoronoi_area_max: {:.3f}\n",
               total, lo, hi);
  }
  if (m.normal_change.size() == m.n_vertices()) {
    double total = 0, hi = 0;
    for (float a : m.normal_change) total += a, hi = std::max(hi, double(a));
    std::cout << "denoised: yes\n"
              << fmt::format("normal_change_mean_deg: {:.4f}\nnormal_change_max_deg: {:.4f}\n",
                             total / double(m.n_vertices()), hi);
  } else {
    std::cout << "denoised: no\n";
  }
  // Where the heights come from (terrain::VertexSource): invented by --fill-nodata (no
  // drainage over their cells), outside the data (no face), small voids filled.
  const auto count = [&](std::uint8_t v) {
    return std::count(m.filled.begin(), m.filled.end(), v);
  };
  const std::size_t kept = m.kept_faces().size();
  std::cout << "filled_vertices: " << count(terrain::kInvented) << "\n"
            << "outside_vertices: " << count(terrain::kOutside) << "\n"
            << "void_filled_vertices: " << count(terrain::kVoidFilled) << "\n"
            << fmt::format("faces_kept: {} ({:.1f} % of the grid's)\n", kept,
                           100.0 * double(kept) / double(std::max<std::size_t>(1, m.n_faces())));
  const terrain::NormalFitInfo& fit = m.normal_fit;
  if (fit.fitted)
    std::cout << fmt::format(
        "normals_fitted: yes ({} source samples)\nfit_rmse_m: {:.4g} (before {:.4g})\n"
        "fit_max_m: {:.4g} (before {:.4g})\n",
        fit.samples, fit.rmse_after, fit.rmse_before, fit.max_after, fit.max_before);
  else
    std::cout << "normals_fitted: no\n";
}

void info_mesh(const std::string& path) {
  const terrain::GridMesh m = terrain::read_mesh_ply(path);
  const terrain::Grid g = terrain::mesh_to_grid(m);
  double tilt_sum = 0.0, tilt_max = 0.0;
  for (const auto& n : m.normals) {
    const double tilt = std::acos(std::clamp(double(n.z()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    tilt_sum += tilt;
    tilt_max = std::max(tilt_max, tilt);
  }
  std::cout << "file: " << path << "\n"
            << "type: terrain mesh (PLY)\n"
            << "grid: " << m.topo.cols << " x " << m.topo.rows << " (columns x rows)\n"
            << "vertices: " << m.n_vertices() << "\n"
            << "faces: " << m.n_faces() << "\n"
            << "crs: " << crs_line(m.geo.crs_wkt, m.geo.epsg) << "\n"
            << fmt::format("spacing: {} {}\n", m.geo.dx, m.geo.dy)
            << fmt::format("origin: {:.3f} {:.3f} {:.3f}\n", m.geo.origin_x, m.geo.origin_y,
                           m.geo.origin_z)
            << fmt::format("extent: {:.3f} {:.3f} {:.3f} {:.3f}\n", g.geo.x0,
                           g.geo.y0 - double(g.rows) * g.geo.dy,
                           g.geo.x0 + double(g.cols) * g.geo.dx, g.geo.y0);
  print_stats(terrain::elevation_stats(g.z));
  std::cout << fmt::format("normal_tilt_mean_deg: {:.3f}\nnormal_tilt_max_deg: {:.3f}\n",
                           tilt_sum / double(m.normals.size()), tilt_max);
  print_mesh_attributes(m);
  // The camera terrain-render frame takes with no camera option (the table's size and fov).
  const renderer::RenderSettings d;
  const double e = renderer::auto_exaggeration(m);
  const renderer::DefaultView av = renderer::default_view(
      m, renderer::ViewMode::Auto, e, d.frame.camera.fov, double(d.width) / d.height);
  std::cout << fmt::format("automatic_exaggeration: {:g}\n", e);
  std::cout
      << fmt::format(
             "automatic_view: --eye {:.3f} {:.3f} {:.3f} --view-az {:g} --view-alt {:g} --fov {:g} "
             "--light-az {:g} --light-alt {:g}\n",
             av.camera.eye->x(), av.camera.eye->y(), av.camera.eye->z(), av.camera.view_az,
             av.camera.view_alt, av.camera.fov, av.light.azimuth, av.light.altitude)
      << "automatic_view_rule: " << av.description << "\n";
  std::cout << "provenance: " << (m.provenance.empty() ? "unknown" : m.provenance) << "\n";
}

void info_dem(const std::string& path) {
  const terrain::Grid g = terrain::read_dem(path);
  const char* kind = g.geo.crs_kind == terrain::CrsKind::Geographic  ? "geographic"
                     : g.geo.crs_kind == terrain::CrsKind::Projected ? "projected"
                                                                     : "none";
  std::cout << "file: " << path << "\n"
            << "type: raster DEM\n"
            << "grid: " << g.cols << " x " << g.rows << " (columns x rows)\n"
            << "crs: " << crs_line(g.geo.crs_wkt, g.geo.epsg) << "\n"
            << "crs_kind: " << kind << "\n"
            << fmt::format("spacing: {:.10g} {:.10g}\n", g.geo.dx, g.geo.dy)
            << fmt::format("extent: {:.10g} {:.10g} {:.10g} {:.10g}\n", g.geo.x0,
                           g.geo.y0 - double(g.rows) * g.geo.dy,
                           g.geo.x0 + double(g.cols) * g.geo.dx, g.geo.y0);
  const terrain::ElevationStats s = terrain::elevation_stats(g.z);
  std::cout << "valid: " << s.count << "\nnodata: " << s.nodata << "\n";
  if (s.count > 0) print_stats(s);
}

void info_points(const std::string& path) {
  const terrain::PointCloud p = terrain::read_points(path);
  const terrain::PointCloudSummary s = terrain::summarize_points(p);
  const char* kind = p.crs_kind == terrain::CrsKind::Geographic  ? "geographic"
                     : p.crs_kind == terrain::CrsKind::Projected ? "projected"
                                                                 : "none";
  std::cout << "file: " << path << "\n"
            << "type: scattered points\n"
            << "format: " << p.format << "\n"
            << "points: " << s.count << "\n"
            << "duplicate_xy: " << s.duplicates << "\n"
            << "crs: " << crs_line(p.crs_wkt, p.epsg) << "\n"
            << "crs_kind: " << kind << "\n"
            << fmt::format("extent: {:.3f} {:.3f} {:.3f} {:.3f}\n", s.xmin, s.ymin, s.xmax, s.ymax)
            << fmt::format("z_min: {:.3f}\nz_max: {:.3f}\n", s.zmin, s.zmax);
}

void info_dv(const std::string& path) {
  // Header and a summary streamed in bands: a database larger than memory is fine.
  const drainage::DvHeader h = drainage::read_dv_header(path);
  const drainage::DvSummary s = drainage::summarize_dv_file(path);
  std::cout << "file: " << path << "\n"
            << "type: drainage vertex database (.dv version " << h.version << ")\n"
            << "grid: " << h.cols << " x " << h.rows << " (columns x rows)\n"
            << "crs: " << crs_line(h.crs_wkt, h.epsg) << "\n"
            << fmt::format("spacing: {} {}\n", h.dx, h.dy)
            << fmt::format("origin: {:.3f} {:.3f} {:.3f}\n", h.origin_x, h.origin_y, h.origin_z)
            << "source: "
            << ((h.flags & drainage::kDvFromPnSurface) ? "PN surface of a mesh" : "raster grid")
            << "\n"
            << "flats_resolved: " << ((h.flags & drainage::kDvFlatsResolved) ? "yes" : "no") << "\n"
            << "filled: " << ((h.flags & drainage::kDvFilled) ? "yes" : "no") << "\n"
            << "breached: " << ((h.flags & drainage::kDvBreached) ? "yes" : "no") << "\n"
            << "points: " << s.points << "\n"
            << "basins: " << h.basins << "\n"
            << "basins_over_1pct: " << s.basins_over_1pct << "\n"
            << "pits: " << s.pits << "\n"
            << "ridges: " << s.ridges << "\n"
            << "channels: " << s.channels << "\n"
            << "junctions: " << s.junctions << "\n"
            << "branches: " << h.branches << "\n";
  for (const auto& [order, count] : s.branches_per_order)
    std::cout << "branches_order_" << order << ": " << count << "\n";
  std::cout << "max_order: "
            << (s.branches_per_order.empty() ? 0 : s.branches_per_order.rbegin()->first) << "\n"
            << "flow_max: " << s.max_accumulated << "\n"
            << fmt::format("normalized_flow_mean: {:.6f}\n", s.mean_normalized)
            << "provenance: " << (h.provenance.empty() ? "unknown" : h.provenance) << "\n";
}

void info_pyramid(const std::string& path) {
  terrain::MeshPyramid p(path);
  const terrain::MeshGeoref& g = p.georef();
  std::size_t tiles = 0;
  for (int l = 0; l < p.level_count(); ++l)
    tiles += ((p.rows(l) - 1 + p.levels().block - 1) / p.levels().block) *
             ((p.cols(l) - 1 + p.levels().block - 1) / p.levels().block);
  std::cout << "file: " << path << "\n"
            << "type: mesh pyramid (levels of detail in tiles)\n"
            << "grid: " << p.topology().cols << " x " << p.topology().rows << " (columns x rows)\n"
            << "crs: " << crs_line(g.crs_wkt, g.epsg) << "\n"
            << fmt::format("spacing: {} {}\n", g.dx, g.dy)
            << fmt::format("origin: {:.3f} {:.3f} {:.3f}\n", g.origin_x, g.origin_y, g.origin_z)
            << "levels: " << p.level_count() << "\n"
            << "block: " << p.levels().block << " cells\n"
            << "blocks: " << p.levels().block_cols << " x " << p.levels().block_rows << "\n"
            << "tiles: " << tiles << "\n"
            << "slopes: "
            << (!p.levels().blocks.empty() && p.levels().blocks[0].slope.empty()
                    ? "not stored (a version-1 pyramid: dem2mesh --pyramid writes them)"
                    : "each block's at each level")
            << "\n"
            << "vertex_sources: "
            << (p.has_sources() ? "kept (the mesh's no-data: holed blocks drawn at level 0)"
                                : "none (every vertex data)")
            << "\n"
            << "bytes: " << std::filesystem::file_size(path) << "\n"
            << "version: " << p.version() << "\n"
            << "mesh_digest: "
            << (p.digest() ? terrain::digest_text(*p.digest()) : "none (before version 3)") << "\n";
  for (int l = 0; l < p.level_count(); ++l)
    std::cout << fmt::format("level_{}: {} x {} vertices\n", l, p.cols(l), p.rows(l));
  // Every tile read and checked (its CRC-32, its data, its vertices in its blocks' boxes).
  std::cout << "tiles_checked: " << p.check_tiles() << " (all)\n";
}

}  // namespace

void run_info(const std::string& file) {
  if (drainage::is_dv_file(file))
    info_dv(file);
  else if (terrain::is_mesh_pyramid(file))
    info_pyramid(file);
  else if (terrain::is_ply_file(file))
    info_mesh(file);
  else if (terrain::is_point_input(file))
    info_points(file);
  else
    info_dem(file);
}

}  // namespace terrain::tools::inspect
