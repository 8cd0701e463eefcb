#pragma once
// Rasters in and out of a drainage run: raster mode's inputs, and GeoTIFF views of a drainage
// result, for QGIS and for checking against other tools.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "drainage/d8.hpp"
#include "drainage/drainage_result.hpp"
#include "terrain/grid.hpp"

namespace drainage {

// The inputs of raster mode (build-drainage --raster DEM and/or --d8-input DIRS).
struct RasterInput {
  terrain::Grid surface;  // the DEM; with directions only, their grid with z = 0 (NaN at no-data)
  std::optional<D8Codes> dirs;  // given directions (--d8-input), masked by the DEM's no-data
  std::uint32_t dv_flags = 0;   // kDvHasElevations when a DEM was given
};

// Reads a DEM (any GDAL raster, projected or geographic: D8 then uses per-row metric cell
// sizes), directions in `encoding`, or both. Errors (terrain::Error): neither given, a DEM
// with no valid sample, a direction raster on a different grid than the DEM.
RasterInput read_raster_input(const std::string& dem_path, const std::string& d8_path,
                              D8Encoding encoding);

// Throws terrain::Error naming both files when `a` and `b` differ in size, origin or step.
void check_same_grid(const terrain::Grid& a, const terrain::Grid& b, const std::string& a_name,
                     const std::string& b_name);

// Writes into directory `dir` (which must exist): surface.tif (Float32), d8.tif (Int16, in
// `encoding`; 0 = no in-grid direction, -32768 = no-data), accumulation.tif (UInt32 points),
// normalized_flow.tif (Float32), basin.tif (UInt32, 4294967295 = no-data), class.tif (Byte:
// 0 ridge, 1 channel, 2 junction, 3 pit, 255 no-data), order.tif (Byte Strahler order,
// 0 = no-data). Each atomically, with the grid's CRS and `provenance`.
void write_drainage_rasters(const std::string& dir, const DrainageResult& r, D8Encoding encoding,
                            const std::string& provenance);

// The file names above, in the order they are written.
inline constexpr const char* kDrainageRasterNames[] = {
    "surface.tif", "d8.tif",    "accumulation.tif", "normalized_flow.tif",
    "basin.tif",   "class.tif", "order.tif"};

// The same rasters, each written to path_of(name) (name from kDrainageRasterNames): a
// tool stages them with terrain::OutputSet so that they land together with its other outputs.
void write_drainage_rasters(const std::function<std::string(const std::string&)>& path_of,
                            const DrainageResult& r, D8Encoding encoding,
                            const std::string& provenance);

// The same rasters from a .dv file (version 1 or 2), each to path_of(name): the same
// names, types, no-data values and values as write_drainage_rasters writes for the run that
// made the file (the surface as the file stores it: relative to its origin, in float, then
// back). Read and written `window_rows` rows at a time (read_dv_window: only the blocks under
// the window), so memory is bounded by the window, not the grid. Returns the grid's rows
// and columns written.
std::size_t export_dv_rasters(const std::string& dv_path,
                              const std::function<std::string(const std::string&)>& path_of,
                              D8Encoding encoding, const std::string& provenance,
                              std::size_t window_rows = 256);

// Reads a D8 direction raster in `encoding` into our codes (d8.hpp) with its grid (the
// Grid's z holds the raw codes). Throws terrain::Error naming the first invalid code and
// where it is.
D8Codes read_d8_raster(const std::string& path, D8Encoding encoding, terrain::Grid& grid);

}  // namespace drainage
