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

namespace tt = terrain::tools;

namespace {

// Grey + alpha hillshade of a DEM (no-data transparent).
std::vector<std::uint8_t> dem_shade(const terrain::Grid& g, double az, double alt, double zf) {
  const auto shade = terrain::hillshade_grid(g, az, alt, zf);
  std::vector<std::uint8_t> ga(2 * g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    ga[2 * i] = shade[i];
    ga[2 * i + 1] = g.valid(i) ? 255 : 0;
  }
  return ga;
}

}  // namespace

void add_preview_options(CLI::App* preview, PreviewArgs& a) {
  preview->add_option("FILE", a.file, "DEM, mesh or .dv")->required();
  preview->add_option("-o,--output", a.out, "PNG to write")->required();
  preview->add_option("--azimuth", a.azimuth, "Light azimuth, degrees clockwise from grid north")
      ->capture_default_str();
  preview->add_option("--altitude", a.altitude, "Light altitude above the horizon, degrees")
      ->check(CLI::Range(0.0, 90.0))
      ->capture_default_str();
  preview
      ->add_option("--colour-by", a.colour_by,
                   "Meshes: shade (hillshade of the normals), voronoi (vertex Voronoi area) or "
                   "normal-change "
                   "(degrees, from denoise-normals)")
      ->check(CLI::IsMember({"shade", "voronoi", "normal-change"}))
      ->capture_default_str();
  preview->add_option("--z-factor", a.zfactor, "Vertical exaggeration (DEMs only)")
      ->check(tt::kPositive)
      ->capture_default_str();
  preview->add_option("--min-flow", a.min_flow,
                      ".dv: draw points with at least this accumulated flow (default: the top 4 % "
                      "of points, at least 20)");
}

void run_preview(const PreviewArgs& a, const std::string& desc, const Verbosity& verb) {
  const std::string &file = a.file, &out = a.out, &colour_by = a.colour_by;
  const double azimuth = a.azimuth, altitude = a.altitude, zfactor = a.zfactor;
  const std::uint32_t min_flow = a.min_flow;
  const bool is_mesh = terrain::is_ply_file(file);
  const bool is_dv = drainage::is_dv_file(file);
  tt::check_distinct_paths({file}, {out});
  tt::warn_stale_temporaries(verb, {out});
  terrain::check_output_path(out);
  if (is_dv) {
    const drainage::DrainageDb db = drainage::read_dv(file);
    terrain::write_png(out, int(db.header.cols), int(db.header.rows), 3,
                       drainage::dv_preview(db, min_flow), desc);
  } else if (is_mesh) {
    const terrain::GridMesh m = terrain::read_mesh_ply(file);
    if (colour_by == "shade" && m.has_holes()) {  // grey + alpha: outside the data clear
      const std::vector<std::uint8_t> grey = terrain::hillshade(m.normals, azimuth, altitude);
      std::vector<std::uint8_t> ga(2 * grey.size());
      for (std::size_t i = 0; i < grey.size(); ++i)
        ga[2 * i] = grey[i], ga[2 * i + 1] = m.filled[i] == terrain::kOutside ? 0 : 255;
      terrain::write_png(out, int(m.topo.cols), int(m.topo.rows), 2, ga, desc);
    } else if (colour_by == "shade") {
      terrain::write_png(out, int(m.topo.cols), int(m.topo.rows), 1,
                         terrain::hillshade(m.normals, azimuth, altitude), desc);
    } else {
      const bool voronoi = colour_by == "voronoi";
      if (voronoi ? m.voronoi.empty() : m.normal_change.size() != m.n_vertices())
        throw terrain::Error("'" + file + "' has no " +
                             (voronoi ? "Voronoi weights (denoise-normals --iterations 0 adds them)"
                                      : "normal change (it was not made by denoise-normals)"));
      std::vector<float> v(voronoi ? m.voronoi.vertex_areas.begin() : m.normal_change.begin(),
                           voronoi ? m.voronoi.vertex_areas.end() : m.normal_change.end());
      std::vector<float> sorted = v;
      std::sort(sorted.begin(), sorted.end());  // ramp from the 2nd to the 98th percentile
      const double lo = voronoi ? sorted[sorted.size() / 50] : 0.0,
                   hi = sorted[sorted.size() * 49 / 50];
      terrain::write_png(out, int(m.topo.cols), int(m.topo.rows), 3,
                         terrain::colour_ramp(v, lo, hi),
                         desc + fmt::format(" [{} {:.4g} .. {:.4g}]", colour_by, lo, hi));
      std::cout << fmt::format("ramp: {:.4g} .. {:.4g}\n", lo, hi);
    }
  } else {
    const terrain::Grid g = terrain::read_dem(file);
    terrain::write_png(out, int(g.cols), int(g.rows), 2, dem_shade(g, azimuth, altitude, zfactor),
                       desc);
  }
  std::cout << "output: " << out << "\n";
}

}  // namespace terrain::tools::inspect
