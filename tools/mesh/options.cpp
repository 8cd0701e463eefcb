#include "mesh/options.hpp"

#include "mesh/banded.hpp"
#include "mesh/grid_input.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"

namespace terrain::tools::mesh {

// INPUT, OUTPUT and the grid: spacing, crop, zone, kernel, no-data, integer heights, normals.
void add_grid_options(CLI::App& app, Options& o) {
  app.add_option("INPUT", o.input,
                 "DEM in any raster format GDAL reads (band 1), or scattered points")
      ->required();
  app.add_option("OUTPUT", o.output, "Mesh file to write (.ply)")->required();
  o.spacing_opt = app.add_option("--spacing", o.spacing,
                                 "Grid spacing in metres (default: the DEM's own spacing)")
                      ->check(kPositive);
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
               "Interpolate every no-data sample (GDALFillNodata) and draw it, with no drainage "
               "over it;\nby default no-data is outside the mesh: no face touches it");
  app.add_option("--max-void", o.req.max_void,
                 "A void of at most this many no-data samples inside the data (not at the "
                 "grid's edge)\nis filled (GDALFillNodata) and flow runs through it; larger "
                 "ones stay holes")
      ->check(CLI::Range(std::size_t(0), std::size_t(1) << 30))
      ->capture_default_str();
  app.add_option("--nodata", o.nodata,
                 "This height is no-data too, where the raster does not say so (gdalwarp "
                 "-srcnodata): --nodata 0\nfor a DEM whose sea is 0");
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
  add_band_options(app, o.tile_size, o.memory_mib);
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
          ->check(kPositive);
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
terrain::Grid grid_of(const Options& o, const terrain::GridRequest& req, const Verbosity& verb,
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
    terrain::Grid g = raster_grid(input, req, o.dequantize, o.src_crs, o.nodata, verb,
                                  o.fit ? &source_dem : nullptr, filled);
    if (!filled.empty() && o.input_kind == "auto" && lattice())
      warn(verb, "'" + input +
                     "' was read as a grid of XYZ text with no-data at its missing points; "
                     "for scattered points pass --input points");
    return g;
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

}  // namespace terrain::tools::mesh
