#pragma once
// Raster I/O through GDAL: any format GDAL reads (GeoTIFF, ESRI ASCII grid, VRT, ...).
#include <optional>
#include <string>

#include "terrain/grid.hpp"

namespace terrain {

// Registers GDAL's drivers and routes GDAL's messages into our Error texts instead of
// stderr (once per process). Every function here calls it; call it before any other
// direct use of GDAL.
void ensure_gdal();

// Reads band 1 of `path` as float elevations; the band's no-data value (and NaN) become
// NaN. Requires a north-up geotransform (no rotation terms). The CRS is read as WKT and
// classified (geographic / projected / none); `epsg` is filled when GDAL can identify it.
// Throws Error: missing file, unreadable file, rotated raster, fewer than 2 x 2 samples.
Grid read_dem(const std::string& path);

// Writes `grid` as a Float32 GeoTIFF (DEFLATE, tiled) with its CRS and geotransform;
// NaN samples become the no-data value -9999. `metadata` is stored as the TIFF
// description (tool, version, command line). Atomic: temp file + rename.
void write_geotiff(const Grid& grid, const std::string& path, const std::string& metadata = {});

// Sample types of write_raster.
enum class RasterType { Byte, Int16, UInt32, Float32 };

// Writes a single-band GeoTIFF (DEFLATE, tiled when >= 256 x 256) of rows x cols values
// of `type` at `data` (row-major, row 0 north) with `geo`'s geotransform and CRS, and
// `nodata` as the band's no-data value when given. Atomic. Throws Error on failure.
void write_raster(const std::string& path, const Georef& geo, std::size_t rows, std::size_t cols,
                  RasterType type, const void* data, std::optional<double> nodata,
                  const std::string& metadata = {});

// Fills the no-data samples of `grid` in place by GDAL's inverse-distance interpolation
// (GDALFillNodata, unlimited search distance, no smoothing). Returns how many samples it
// filled. Throws Error when the grid has no valid sample.
std::size_t fill_nodata(Grid& grid);

}  // namespace terrain
