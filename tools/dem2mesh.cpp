// dem2mesh: a DEM GDAL reads -> a regular metric (UTM) grid -> the terrain mesh (PLY).
#include <fmt/format.h>

#include <chrono>
#include <iostream>

#include "common.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/prepare_grid.hpp"

namespace tt = terrain::tools;

int main(int argc, char** argv) {
  CLI::App app{"Turn a DEM into a terrain mesh: reproject a geographic DEM onto UTM, crop, resample,\n"
               "triangulate (2 triangles per cell) and write a binary PLY with vertex normals and\n"
               "its georeferencing.",
               "dem2mesh"};
  app.footer(
      "Examples:\n"
      "  dem2mesh data/msh_2007_utm10n_10m.tif msh_50m.ply --spacing 50\n"
      "  dem2mesh eno_geographic.tif eno.ply --spacing 10 --utm-zone 17N\n"
      "  dem2mesh dem.tif crater.ply --center 562500 5116500 --size 2000 2000\n\n"
      "Output: stdout gets 'key: value' lines describing the mesh; progress and warnings go to stderr.\n"
      "See docs/dem2mesh.md for the grid, triangulation and file conventions.");
  app.set_version_flag("--version", tt::version());

  std::string input, output, resample = "bilinear", weighting = "uniform", grid_out;
  terrain::GridRequest req;
  std::array<double, 4> bbox{};
  std::array<double, 2> center{}, size{};
  std::string utm_zone;
  double spacing = 0.0;
  tt::Verbosity verb;
  app.add_option("INPUT", input, "DEM in any raster format GDAL reads (band 1)")->required();
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
  tt::add_verbosity_flags(app, verb);

  return tt::run_main(app, argc, argv, [&]() {
    using clock = std::chrono::steady_clock;
    if (!output.ends_with(".ply")) throw terrain::Error("OUTPUT must be a .ply file: '" + output + "'");
    tt::check_distinct_paths({input}, {output, grid_out});
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

    auto t0 = clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(clock::now() - t0).count(); };
    // Only the source window the crop needs is read (plus the kernel's margin).
    const terrain::DemInfo info = terrain::read_dem_info(input);
    const terrain::GridPlan plan = terrain::plan_grid(info.geo, info.rows, info.cols, req);
    const terrain::RasterWindow& win = plan.source_window;
    const terrain::Grid dem = terrain::read_dem(input, tt::terminal_progress(verb, "read"), win);
    tt::step(verb, fmt::format("read {} x {} of {} x {} samples: {:.2f} s", win.cols, win.rows, info.cols, info.rows,
                               seconds()));

    t0 = clock::now();
    terrain::PreparedGrid prepared = terrain::resample_to_plan(dem, plan, req, tt::terminal_progress(verb, "resample"));
    for (const auto& w : prepared.warnings) tt::warn(verb, w);
    if (prepared.filled > 0) tt::warn(verb, fmt::format("filled {} no-data samples by interpolation", prepared.filled));
    const terrain::Grid& grid = prepared.grid;
    tt::step(verb, fmt::format("grid {} x {} at {} m: {:.2f} s", grid.cols, grid.rows, grid.geo.dx, seconds()));
    terrain::OutputSet outputs;  // the mesh and the grid land together, or neither does
    if (!grid_out.empty())
      outputs.write([&] { terrain::write_geotiff(grid, outputs.stage(grid_out), tt::provenance(argc, argv)); });

    t0 = clock::now();
    terrain::GridMesh mesh = terrain::make_grid_mesh(grid, nw);
    mesh.provenance = tt::provenance(argc, argv);
    tt::step(verb, fmt::format("mesh and normals: {:.2f} s", seconds()));

    t0 = clock::now();
    outputs.write([&] { terrain::write_mesh_ply(mesh, outputs.stage(output)); });
    outputs.commit();
    tt::step(verb, fmt::format("write {}: {:.2f} s", output, seconds()));

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
    return 0;
  });
}
