#pragma once
// Raster I/O through GDAL: any format GDAL reads (GeoTIFF, ESRI ASCII grid, VRT, ...).
#include <memory>
#include <optional>
#include <string>

#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace terrain {

// Registers GDAL's drivers and routes GDAL's messages into our Error texts instead of
// stderr (once per process). Every function here calls it; call it before any other
// direct use of GDAL.
void ensure_gdal();

// What is wrong with a file's stored CRS (the WKT and EPSG code a mesh or .dv header
// carries), or "" when nothing is: a WKT that does not parse, an EPSG code PROJ does not
// know, a WKT whose own EPSG code differs from the stored one, or a geographic WKT beside a
// projected code (or the reverse). Either may be absent (empty, 0).
std::string crs_fields_problem(const std::string& wkt, int epsg);

// Gives `geo` the CRS `user_crs` (anything OGR's SetFromUserInput takes: EPSG:4326, a WKT,
// a PROJ string), replacing the one it has, as gdalwarp's -s_srs does. Throws Error when
// the CRS is not understood, or is projected in units other than metres.
void assign_crs(Georef& geo, const std::string& user_crs);

// A window of a raster in north-up sample indices (row 0 = the northernmost row).
struct RasterWindow {
  std::size_t row0 = 0, col0 = 0, rows = 0, cols = 0;
};

// What a raster is without its samples: north-up georeferencing (cell corner x0, y0,
// spacing, CRS as WKT, its kind, EPSG) and size. Opening only: cheap for any size.
struct DemInfo {
  Georef geo;
  std::size_t rows = 0, cols = 0;
};
DemInfo read_dem_info(const std::string& path);

// Reads band 1 of `path` (or only `window` of it) as float elevations; the band's no-data
// value (and NaN) become NaN. `path` is anything GDAL opens, also names that are not files
// (NETCDF:f.nc:Band1, GTIFF_DIR:1:f.tif, /vsizip/...). Requires a north-up geotransform
// (south-up rasters are flipped). The CRS is read as WKT and classified (geographic /
// projected / none); `epsg` is filled when GDAL can identify it. Progress comes from
// GDAL's reader. Throws Error: missing or unreadable file, a directory, rotated raster,
// fewer than 2 x 2 samples, a projected CRS not in metres, infinite samples, a window
// outside the raster, or more samples than fit in 80% of the machine's memory.
Grid read_dem(const std::string& path, const Progress& progress = {},
              std::optional<RasterWindow> window = {});

// Writes `grid` as a Float32 GeoTIFF (DEFLATE, tiled) with its CRS and geotransform;
// NaN samples become the no-data value -9999. `metadata` is stored as the TIFF
// description (tool, version, command line). Atomic: temp file + rename.
void write_geotiff(const Grid& grid, const std::string& path, const std::string& metadata = {});

// Sample types of write_raster.
enum class RasterType { Byte, Int16, UInt32, Float32 };

// The no-data value of the Float32 GeoTIFFs written here (write_geotiff).
inline constexpr double kGeoTiffNodata = -9999.0;

// Writes a single-band GeoTIFF (DEFLATE, tiled when >= 256 x 256) of rows x cols values
// of `type` at `data` (row-major, row 0 north) with `geo`'s geotransform and CRS, and
// `nodata` as the band's no-data value when given. Atomic. Throws Error on failure.
void write_raster(const std::string& path, const Georef& geo, std::size_t rows, std::size_t cols,
                  RasterType type, const void* data, std::optional<double> nodata,
                  const std::string& metadata = {});

// While alive, GDAL's block cache (by default 5 % of the memory, where read and written
// tiles wait) holds at most `mib` MiB, so that memory follows the windows; restored after.
class GdalCacheLimit {
 public:
  explicit GdalCacheLimit(int mib = 128);
  ~GdalCacheLimit();
  GdalCacheLimit(const GdalCacheLimit&) = delete;
  GdalCacheLimit& operator=(const GdalCacheLimit&) = delete;

 private:
  long long before_;
};

// The same GeoTIFF written window by window (rows of the full width at a time), for grids
// that do not fit in memory: staged in a temporary file and renamed by commit(); destroyed
// without commit(), nothing is left behind. Throws Error on failure.
class RasterWriter {
 public:
  RasterWriter(const std::string& path, const Georef& geo, std::size_t rows, std::size_t cols,
               RasterType type, std::optional<double> nodata, const std::string& metadata = {});
  ~RasterWriter();
  RasterWriter(const RasterWriter&) = delete;
  RasterWriter& operator=(const RasterWriter&) = delete;
  // Rows row0 .. row0 + n - 1: n x cols values of the writer's type at `data`, row-major.
  void write_rows(std::size_t row0, std::size_t n, const void* data);
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Fills the no-data samples of `grid` in place by GDAL's inverse-distance interpolation
// (GDALFillNodata, unlimited search distance, no smoothing). Returns how many samples it
// filled. Throws Error when the grid has no valid sample.
std::size_t fill_nodata(Grid& grid);

}  // namespace terrain
