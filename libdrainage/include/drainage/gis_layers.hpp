#pragma once
// A drainage database as GIS vector layers: basins (polygons), the divides between them
// (lines) and watersheds at given outlets (TauDEM's gagewatershed), in GeoPackages that
// QGIS reads; each read from a .dv window by window. docs/build-drainage.md, "GIS layers".
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "terrain/big_vector.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace drainage {

// ---- Divides: the cell edges between two basins, as lines ---------------------------

// One unit edge of the grid's corner lattice ((rows + 1) x (cols + 1) corners, corner
// (r, c) = r * (cols + 1) + c, the north-west corner of cell (r, c)) between a cell of
// basin `a` and a 4-neighbour of basin `b`, a < b.
struct DivideEdge {
  std::uint32_t a = 0, b = 0;
  std::uint64_t from = 0, to = 0;  // corners, from < to
};

// Appends the divide edges of rows row0 .. row0 + n - 1 of a basin-id grid with `cols`
// columns: `ids` holds those n rows and, when `below` is true, the row after them (n + 1
// rows), so that the edges to the next band are found once. kNone is no-data: edges
// between a basin and no-data or the grid's border are not divides.
void add_divide_edges(const std::uint32_t* ids, std::size_t row0, std::size_t n, std::size_t cols,
                      bool below, std::vector<DivideEdge>& edges);

// The divide between one pair of basins as polylines of corners: the edges chained at
// corners where exactly two of them meet; a chain ends at a corner of one edge or of
// three or four (where basins meet), and a closed ring is one chain starting and ending
// at the same corner. Corners along a straight run are left out. Takes edges of one pair
// (any order); chains are listed from the lowest free end, deterministically.
std::vector<std::vector<std::uint64_t>> chain_divide_edges(std::vector<DivideEdge> edges,
                                                           std::size_t cols);

// ---- Watersheds at outlets ---------------------------------------------------------------

// Each cell's nearest downstream outlet, as TauDEM's gagewatershed: following D8 codes
// (d8.hpp; rows x cols) from a cell, itself included, the index k of the first cell that is
// outlet_cells[k]; kNone where the flow ends (a pit, the grid's edge, no-data) without
// meeting one. Outlets upstream of others give nested watersheds: a downstream outlet's
// watershed leaves out the upstream ones. Throws terrain::Error when two outlets are one
// cell, or when the directions hold a cycle. O(cells), one pass.
terrain::BigVector<std::uint32_t> nearest_downstream_outlet(
    const D8Codes& dirs, std::size_t rows, std::size_t cols,
    const std::vector<std::uint64_t>& outlet_cells);

// A point of an outlet layer, in the CRS of the database it is used with.
struct OutletPoint {
  double x = 0, y = 0;
  std::int64_t fid = -1;  // its feature id in the source layer
};

// Every point of the first layer of `path` (any OGR vector source: GeoPackage, shapefile,
// GeoJSON, CSV with X/Y columns...), transformed to `crs_wkt` when the layer has another
// CRS (x east, y north). Throws terrain::Error: unreadable, no layer, no point, a
// geometry that is not a point, a CRS that cannot be transformed.
std::vector<OutletPoint> read_outlet_points(const std::string& path, const std::string& crs_wkt);

struct Watershed {
  OutletPoint given;
  std::size_t row = 0, col = 0;   // the outlet cell, after snapping
  double x = 0, y = 0;            // its centre (world)
  double moved = 0;               // metres from the given point to that centre
  std::uint32_t accumulated = 0;  // points draining through the outlet cell, itself included
  std::uint64_t cells = 0;        // cells in its watershed (nested watersheds left out)
  std::int64_t downstream = -1;   // the watershed its outlet drains into, -1: none
};

// The points of rows r0 .. r0 + rows - 1, columns c0 .. c0 + cols - 1 of a .dv (as
// read_dv_window gives them): the file's, or an in-memory database's for tests.
using DvWindowReader =
    std::function<DrainageDb(std::size_t r0, std::size_t c0, std::size_t rows, std::size_t cols)>;

// Outlets snapped as write_watersheds snaps them (below), on the grid of `h` whose points
// `window` reads; `cells` receives each outlet's cell (row-major index). Throws
// terrain::Error for a point outside the grid (in other coordinates: longitude and
// latitude in a file without a CRS), a snap distance larger than the grid, a point with no
// drainage point within reach, or two points on one cell.
std::vector<Watershed> snap_outlets(const DvHeader& h, const std::vector<OutletPoint>& points,
                                    double snap_distance, const DvWindowReader& window,
                                    std::vector<std::uint64_t>& cells);

// Watersheds of `points` on the .dv at `dv_path`: each point moved to the cell of highest
// accumulation whose centre lies within `snap_distance` metres (ties: the nearest, then
// the first in row order; 0: the cell holding the point), as TauDEM's
// moveoutletstostreams moves outlets onto streams; then nearest_downstream_outlet over
// the file's D8 (read window by window: 5 bytes a cell held). Writes `tif_path` (UInt32
// watershed index, 4294967295 = none) and `gpkg_path` with layers "outlets" (points at
// the outlet cells) and "watersheds" (one MultiPolygon each, GDALPolygonize of the
// raster), each atomic. Throws terrain::Error naming the point when no valid cell lies
// within the distance, or when two points snap to one cell.
std::vector<Watershed> write_watersheds(const std::string& dv_path,
                                        const std::vector<OutletPoint>& points,
                                        double snap_distance, const std::string& gpkg_path,
                                        const std::string& tif_path, const std::string& provenance,
                                        const terrain::Progress& progress = {});

// ---- terrain-inspect export X.dv --to gpkg ------------------------------------------------

// The rivers as a map draws them (docs/build-drainage.md, "GIS layers"): the points through
// which at least `min_area_m2` drains (a channel-initiation area, as terrain-render's
// --min-area; 0: every D8 link), Strahler's orders counted on that network (TauDEM's
// StreamNet does the same on its thresholded grid), and chains of points of one order
// followed downstream, each ending on the river it joins (that point last) or at its
// outlet. Points as the .dv's indices; max_flow the chain's own largest accumulation.
struct RiverLine {
  std::vector<std::uint32_t> points;
  int strahler = 0;
  std::uint32_t max_flow = 0;
};
std::vector<RiverLine> river_lines(const DrainageDb& db, double min_area_m2);
// A river line's points (the .dv's local frame) smoothed as the renderer smooths creases:
// x, y the Gaussian mean along the line (sigma in points, a window symmetric about each
// point, up to 2 sigma: its ends stay), z the surface there (bilinear over `surface`, the
// .dv's heights: dv_elevations); as they are with sigma 0.
std::vector<Eigen::Vector3d> river_shape(const DrainageDb& db, const terrain::Grid& surface,
                                         const RiverLine& line, double sigma_samples);

// The points of `line` (x, y) a Douglas-Peucker simplification within `tolerance` keeps,
// ascending, its ends always (terrain::douglas_peucker).
std::vector<std::size_t> kept_points(const std::vector<Eigen::Vector3d>& line, double tolerance);

struct RiverOptions {
  int min_order = 1;            // lines of at least this order
  double min_area_m2 = 1e4;     // river_lines' channel-initiation area (1 ha)
  double smooth_samples = 1.5;  // river_shape's sigma; 0: the D8 polyline (not simplified)
  // A smoothed line's points kept within this share of the grid's spacing (kept_points):
  // a curve, not a point every sample.
  double simplify_spacings = 0.1;
};

// Writes a GeoPackage (GDAL/OGR) with layer "branches": one LineString ZM per river line
// (river_lines, river_shape), world coordinates, M = the normalized flow of its point;
// fields strahler, basin, max_flow (points) and vertices. Atomic. Returns the number of
// features written.
std::size_t export_branches_gpkg(const DrainageDb& db, const std::string& path,
                                 const RiverOptions& rivers = {});

struct GpkgLayers {
  bool branches = true, basins = true, divides = true;
  RiverOptions rivers;  // which branches, and their shape
};
struct GpkgCounts {
  std::size_t branches = 0, basins = 0, divides = 0;
};

// Writes a GeoPackage (atomic) from the .dv at `dv_path` with the layers asked for:
// - "branches": as export_branches_gpkg (dv_views.hpp; the database is read whole);
// - "basins": one MultiPolygon per basin, the union of its cells' squares (GDALPolygonize
//   of the basin ids, written window by window to a scratch GeoTIFF), with fields id,
//   cells, area_m2, outlet_x, outlet_y (its pit's centre), outlet ("pit": no lower
//   neighbour; "edge": the flow leaves the grid or enters no-data) and max_order (the
//   Strahler order at the outlet, the largest in the basin);
// - "divides": one MultiLineString per pair of basins that share cell edges, along those
//   edges (chain_divide_edges), with fields basin_a < basin_b, max_order (the larger of the
//   two basins' max_order: show major divides only by filtering on it) and length_m.
// Memory: a window of rows, the polygons and the divide edges (24 bytes each).
GpkgCounts export_dv_gpkg(const std::string& dv_path, const std::string& out_path,
                          const GpkgLayers& layers, const terrain::Progress& progress = {});

}  // namespace drainage
