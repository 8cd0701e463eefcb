#pragma once
// Scattered elevation points (lidar ground returns, survey points, contour vertices) to a
// regular grid (docs/dem2mesh.md, "Scattered points"):
//   read_points     any OGR point layer (GeoPackage, Shapefile, CSV with X/Y/Z columns
//                   through GDAL's CSV driver, ...) or XYZ text; recognised by content
//   points_to_grid  2D Delaunay triangulation of x, y (CGAL), then the grid's samples
//                   interpolated linearly (barycentric in the Delaunay triangle), with
//                   Sibson's C1 natural-neighbour interpolant (gradients fitted at the points:
//                   CGAL sibson_gradient_fitting, sibson_c1_interpolation) or with Sibson's C0
//                   one (natural-neighbour coordinates, CGAL natural_neighbor_coordinates_2).
// Samples outside the convex hull, and with max_edge > 0 samples in a Delaunay triangle
// with an edge longer than max_edge, are no-data.
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "terrain/dem_io.hpp"
#include "terrain/grid.hpp"

namespace terrain {

struct PointCloud {
  std::vector<double> x, y, z;
  std::string crs_wkt;  // empty: unknown
  int epsg = 0;
  CrsKind crs_kind = CrsKind::None;
  std::string format;  // "GPKG", "ESRI Shapefile", "CSV", "XYZ text", ...
  std::size_t size() const { return x.size(); }
};

// Whether `path` holds scattered points rather than a raster: GDAL opens it as a vector
// dataset with a point layer, or it is text whose first data lines are 3 numbers (and
// GDAL's raster drivers do not open it: a regular XYZ grid is a raster).
bool is_point_input(const std::string& path);

// The short name of the GDAL raster driver that opens `path` ("" when none does): "XYZ" for
// a text file of points GDAL reads as a grid (points on a lattice, holes as no-data).
std::string raster_driver(const std::string& path);

// All points of the first point layer (x, y from the geometry, z from the geometry's Z or
// else from a field named z, elevation, elev, height or alt), or of the XYZ text (x y z per
// line, separated by spaces, tabs, commas or semicolons; one header line and '#' comments
// allowed). Throws Error for a file without points, a point without z, a non-finite
// coordinate (naming the point), or fewer than 3 points.
PointCloud read_points(const std::string& path, const Progress& progress = {});

// Projected points as they are; geographic points projected to UTM (the zone of their
// centre or `utm_zone`, as dem2mesh does for grids). `src_crs` ("EPSG:32610", WKT, ...)
// gives the CRS of points that have none, and replaces theirs. Throws Error without a CRS.
void project_points(PointCloud& points, const std::string& src_crs,
                    const std::optional<std::string>& utm_zone);

// Natural: Sibson's C1 interpolant; it reproduces spherical quadratics, and falls back to
// NaturalC0 where a natural neighbour lies on the convex hull (no gradient fitted there).
enum class PointInterpolation { Linear, Natural, NaturalC0 };
PointInterpolation parse_point_interpolation(const std::string& name);

// The Delaunay triangulation of the points' x, y with their z. Duplicate x, y: one vertex
// whose z is the mean of the duplicates. Throws Error for fewer than 3 points, a non-finite
// coordinate, or points that are all collinear.
class PointSurface {
 public:
  explicit PointSurface(const PointCloud& points);
  ~PointSurface();
  PointSurface(const PointSurface&) = delete;
  PointSurface& operator=(const PointSurface&) = delete;
  std::size_t duplicates() const;  // points merged into an earlier one with the same x, y
  std::size_t vertices() const;
  // z at (x, y): NaN outside the convex hull, or (max_edge > 0) in a Delaunay triangle with
  // an edge longer than max_edge. Each query starts its walk where the last one ended:
  // fast for neighbouring queries, not thread-safe.
  double z_at(double x, double y, PointInterpolation method, double max_edge = 0) const;
  // z at every sample of g (its georeferencing), as z_at, on all threads.
  void sample(Grid& g, PointInterpolation method, double max_edge,
              const Progress& progress = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct PointGridRequest {
  double spacing = 10.0;  // metres
  PointInterpolation interpolation = PointInterpolation::Natural;
  double max_edge = 0.0;  // > 0: no-data in Delaunay triangles with a longer edge
  // Output extent XMIN YMIN XMAX YMAX; unset: the points' bounding box. Samples sit on
  // multiples of the spacing (x = k * spacing) inside the extent.
  std::optional<std::array<double, 4>> bbox;
};

struct PointGridResult {
  Grid grid;
  std::size_t duplicates = 0;  // points merged into an earlier point with the same x, y
  std::size_t vertices = 0;    // Delaunay vertices
  std::size_t nodata = 0;      // samples outside the hull or in long triangles
};
PointGridResult points_to_grid(const PointCloud& points, const PointGridRequest& request,
                               const Progress& progress = {});

// What terrain-inspect reports on points: count, extent, z range, duplicate x, y.
struct PointCloudSummary {
  std::size_t count = 0, duplicates = 0;
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0, zmin = 0, zmax = 0;
};
PointCloudSummary summarize_points(const PointCloud& points);

}  // namespace terrain
