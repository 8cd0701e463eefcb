#include "terrain/dem_io.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_alg.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>

#include "crs_info.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/memory.hpp"

namespace terrain {

void ensure_gdal() {
  static std::once_flag once;
  std::call_once(once, [] {
    GDALAllRegister();
    // GDAL prints its own errors to stderr by default; we turn them into Error messages.
    CPLSetErrorHandler(CPLQuietErrorHandler);
  });
}

namespace {

std::string last_gdal_error() {
  std::string msg = CPLGetLastErrorMsg();
  return msg.empty() ? std::string("unknown GDAL error") : msg;
}

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(ds); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

// A MEM dataset that aliases `grid.z` (no copy), nodata = NaN.
DatasetPtr wrap_in_mem_dataset(Grid& grid) {
  ensure_gdal();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  DatasetPtr ds(mem->Create("", int(grid.cols), int(grid.rows), 0, GDT_Float32, nullptr));
  if (!ds) throw Error("cannot create an in-memory raster: " + last_gdal_error());
  // CPLPrintPointer does not terminate what it prints: the buffer starts zeroed and it may
  // fill all but the last byte (an unterminated pointer string made MEM read a random
  // address).
  char ptr[64] = {};
  CPLPrintPointer(ptr, grid.z.data(), sizeof(ptr) - 1);
  std::string opt = std::string("DATAPOINTER=") + ptr;
  char* opts[] = {opt.data(), nullptr};
  if (ds->AddBand(GDT_Float32, opts) != CE_None)
    throw Error("cannot create an in-memory raster band: " + last_gdal_error());
  ds->GetRasterBand(1)->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  return ds;
}

}  // namespace

CrsInfo crs_info(const OGRSpatialReference& srs) {
  CrsInfo c;
  char* wkt = nullptr;
  const char* opts[] = {"FORMAT=WKT2_2019", "MULTILINE=NO", nullptr};
  if (srs.exportToWkt(&wkt, opts) == OGRERR_NONE && wkt) c.wkt = wkt;
  CPLFree(wkt);
  c.kind = srs.IsGeographic()  ? CrsKind::Geographic
           : srs.IsProjected() ? CrsKind::Projected
                               : CrsKind::None;
  OGRSpatialReference copy(srs);
  if (copy.GetAuthorityName(nullptr) == nullptr) copy.AutoIdentifyEPSG();
  const char* auth = copy.GetAuthorityName(nullptr);
  const char* code = copy.GetAuthorityCode(nullptr);
  if (auth && code && std::string(auth) == "EPSG") c.epsg = std::atoi(code);
  if (c.kind == CrsKind::Projected && std::abs(copy.GetLinearUnits() - 1.0) > 1e-12)
    c.non_metre_unit = copy.GetAttrValue("UNIT") ? copy.GetAttrValue("UNIT") : "non-metre units";
  return c;
}

void assign_crs(Georef& geo, const std::string& user_crs) {
  ensure_gdal();
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(user_crs.c_str()) != OGRERR_NONE)
    throw Error("cannot understand the CRS '" + user_crs + "'");
  const CrsInfo crs = crs_info(srs);
  if (crs.kind == CrsKind::None)
    throw Error("the CRS '" + user_crs + "' is neither geographic nor projected");
  if (!crs.non_metre_unit.empty())
    throw Error("the CRS '" + user_crs + "' is in " + crs.non_metre_unit + ", not metres");
  geo.crs_wkt = crs.wkt, geo.epsg = crs.epsg, geo.crs_kind = crs.kind;
}

static std::string crs_fields_check(const std::string& wkt, int epsg);

std::string crs_fields_problem(const std::string& wkt, int epsg) {
  // A windowed reader opens one file many times (a .dv band by band): the answer for the
  // last fields, kept per thread, spares PROJ's look-ups.
  thread_local std::string last_wkt, last_problem;
  thread_local int last_epsg = -1;
  if (epsg == last_epsg && wkt == last_wkt) return last_problem;
  last_problem = crs_fields_check(wkt, epsg);
  last_wkt = wkt, last_epsg = epsg;
  return last_problem;
}

static std::string crs_fields_check(const std::string& wkt, int epsg) {
  ensure_gdal();
  OGRSpatialReference from_wkt, from_code;
  if (!wkt.empty() && from_wkt.importFromWkt(wkt.c_str()) != OGRERR_NONE)
    return "its CRS WKT does not parse";
  if (epsg != 0 && (epsg < 0 || from_code.importFromEPSG(epsg) != OGRERR_NONE))
    return "EPSG:" + std::to_string(epsg) + " is no CRS PROJ knows";
  if (wkt.empty() || epsg == 0) return "";
  const char* auth = from_wkt.GetAuthorityName(nullptr);
  const char* code = from_wkt.GetAuthorityCode(nullptr);
  if (auth && code && std::string(auth) == "EPSG" && std::atoi(code) != epsg)
    return "its CRS WKT says EPSG:" + std::string(code) + " but its EPSG field says " +
           std::to_string(epsg);
  if (bool(from_wkt.IsGeographic()) != bool(from_code.IsGeographic()) ||
      bool(from_wkt.IsProjected()) != bool(from_code.IsProjected()))
    return std::string("its CRS WKT is ") +
           (from_wkt.IsGeographic() ? "geographic" : "not geographic") + " but its EPSG field (" +
           std::to_string(epsg) + ") is " +
           (from_code.IsGeographic() ? "geographic" : "not geographic");
  return "";
}

namespace {

// An opened raster with its north-up georeferencing (a south-up raster's rows are read
// in reverse), and the CRS read into `geo`.
struct OpenRaster {
  DatasetPtr ds;
  std::size_t rows = 0, cols = 0;
  Georef geo;
  bool south_up = false;
};

// GDAL names that are not plain files (subdatasets such as NETCDF:f.nc:Band1,
// GTIFF_DIR:1:f.tif, /vsicurl/...): GDAL opens them, we must not test them as files.
bool is_gdal_special(const std::string& path) {
  if (path.rfind("/vsi", 0) == 0) return true;
  const auto colon = path.find(':');
  return colon != std::string::npos && colon > 1 && path.find('/') > colon;
}

// The raster's grid from its geotransform (pixel coordinates, row 0 at the top, without
// one), checked: north-up (south-up read flipped), finite, not rotated.
void read_geotransform(OpenRaster& r, const std::string& path) {
  const int rows = int(r.rows);
  double gt[6];
  if (r.ds->GetGeoTransform(gt) != CE_None && r.ds->GetGCPCount() > 0)
    // GDAL stores a geotransform it cannot invert (a zero pixel width or height) as ground
    // control points: placing the DEM at pixel coordinates would be silently wrong.
    throw Error(
        "cannot use '" + path +
        "': it is georeferenced by ground control points, not a geotransform (or its "
        "geotransform is invalid, e.g. a zero pixel width); warp it onto a grid first (gdalwarp)");
  if (r.ds->GetGeoTransform(gt) !=
      CE_None) {  // no georeferencing: pixel coordinates, row 0 at the top
    // Except for picture formats: a PNG or JPEG without a world file is a picture, not a DEM.
    const std::string driver = r.ds->GetDriver() ? r.ds->GetDriver()->GetDescription() : "";
    for (const char* image : {"PNG", "JPEG", "GIF", "BMP", "WEBP"})
      if (driver == image)
        throw Error("cannot use '" + path + "': an image without georeferencing (" + driver +
                    "), not a DEM; give it a world file or georeference it (gdal_translate -a_ullr "
                    "-a_srs)");
    const double pixel[6] = {0.0, 1.0, 0.0, double(rows), 0.0, -1.0};
    std::copy(pixel, pixel + 6, gt);
  }
  if (gt[2] != 0.0 || gt[4] != 0.0)
    throw Error("cannot use '" + path +
                "': rotated or sheared geotransform; warp it north-up first (gdalwarp)");
  if (!(gt[1] > 0.0) || gt[5] == 0.0 || !std::isfinite(gt[0]) || !std::isfinite(gt[3]) ||
      !std::isfinite(gt[1]) || !std::isfinite(gt[5]))
    throw Error("cannot use '" + path + "': invalid pixel size or origin in the geotransform");
  // South-up rasters (positive pixel height) are read flipped to the north-up convention.
  if (gt[5] > 0.0) {
    r.south_up = true;
    gt[3] += gt[5] * rows;
    gt[5] = -gt[5];
  }
  r.geo.x0 = gt[0];
  r.geo.y0 = gt[3];
  r.geo.dx = gt[1];
  r.geo.dy = -gt[5];
}

// The raster's CRS, checked: metres when projected, within the globe when geographic.
void read_crs(OpenRaster& r, const std::string& path) {
  const std::size_t rows = r.rows, cols = r.cols;
  if (const OGRSpatialReference* srs = r.ds->GetSpatialRef()) {
    const CrsInfo crs = crs_info(*srs);
    r.geo.crs_wkt = crs.wkt;
    r.geo.epsg = crs.epsg;
    r.geo.crs_kind = crs.kind;
    if (!crs.non_metre_unit.empty())
      throw Error("cannot use '" + path + "': its projected CRS is in " + crs.non_metre_unit +
                  ", not metres; reproject it first (gdalwarp -t_srs EPSG:...)");
  }
  if (r.geo.crs_kind == CrsKind::Geographic) {
    // Edges within one cell of the globe's (cell-centred global grids reach past 90 by half
    // a cell); longitudes -180..360 cover both conventions.
    const double north = r.geo.y0, south = r.geo.y0 - double(rows) * r.geo.dy;
    const double west = r.geo.x0, east = r.geo.x0 + double(cols) * r.geo.dx;
    if (north > 90.0 + r.geo.dy || south < -90.0 - r.geo.dy || west < -180.0 - r.geo.dx ||
        east > 360.0 + r.geo.dx)
      throw Error(fmt::format(
          "cannot use '{}': its geographic extent (longitude {:g} .. {:g}, latitude {:g} .. {:g}) "
          "lies outside the globe (-180 .. 360, -90 .. 90); is its CRS or geotransform right?",
          path, west, east, south, north));
  }
}

OpenRaster open_raster(const std::string& path) {
  ensure_gdal();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error("cannot read '" + path + "': it is a directory");
  CPLErrorReset();
  OpenRaster r;
  r.ds.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!r.ds) {
    if (!is_gdal_special(path) && !std::filesystem::exists(path, ec))
      throw Error("cannot read '" + path + "': no such file");
    throw Error("cannot read '" + path + "': not a raster GDAL can open (" + last_gdal_error() +
                ")");
  }
  if (r.ds->GetRasterCount() < 1) throw Error("cannot read '" + path + "': it has no raster band");
  const int cols = r.ds->GetRasterXSize(), rows = r.ds->GetRasterYSize();
  if (cols < 2 || rows < 2)
    throw Error("cannot use '" + path + "': " + std::to_string(cols) + " x " +
                std::to_string(rows) + " samples; a DEM needs at least 2 x 2");
  r.rows = std::size_t(rows);
  r.cols = std::size_t(cols);
  read_geotransform(r, path);
  read_crs(r, path);
  return r;
}

// GDAL's progress callback over ours; remembers a request to cancel.
struct GdalProgress {
  const Progress& progress;
  bool cancelled = false;
};
int gdal_progress(double fraction, const char*, void* arg) {
  auto& g = *static_cast<GdalProgress*>(arg);
  g.cancelled = g.progress && !g.progress(fraction);
  return g.cancelled ? FALSE : TRUE;
}

// The heights read: no-data marked NaN, checked finite and within float precision.
void finish_heights(Grid& grid, GDALRasterBand& band_ref, const std::string& path,
                    const RasterWindow& w) {
  GDALRasterBand* band = &band_ref;
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  const float nd = float(nodata);
  std::size_t infinite = 0, first_inf = 0;
  for (std::size_t i = 0; i < grid.z.size(); ++i) {
    float& v = grid.z[i];
    if (has_nodata && (v == nd || (std::isnan(nodata) && std::isnan(v))))
      v = std::numeric_limits<float>::quiet_NaN();
    else if (std::isinf(v) && infinite++ == 0)
      first_inf = i;
  }
  if (infinite > 0)
    throw Error(fmt::format(
        "cannot use '{}': {} samples are infinite (the first at row {}, column {}); mark them as "
        "no-data (gdal_translate -a_nodata) or fix the DEM",
        path, infinite, w.row0 + first_inf / grid.cols, w.col0 + first_inf % grid.cols));
  // Heights are single-precision floats: above 2^24 they step by 2 or more, so the values
  // of a wider band type (UInt32 near 4e9 steps by 256 there) would lose their steps.
  const GDALDataType type = band->GetRasterDataType();
  if (GDALGetDataTypeSizeBits(type) > 16 && type != GDT_Float32) {
    float top = 0;
    for (const float v : grid.z)
      if (std::abs(v) > top) top = std::abs(v);  // NaN compares false
    if (top > float(1 << 24))
      throw Error(fmt::format(
          "cannot use '{}': its {} heights reach {:.10g}, where single-precision floats step by "
          "{:g}, so its steps would be lost; subtract an offset first (gdal_calc.py --calc "
          "\"A-{:.0f}\" --type Float32)",
          path, GDALGetDataTypeName(type), double(top), double(std::nextafter(top, INFINITY) - top),
          std::floor(double(top) / 1e6) * 1e6));
  }
}

}  // namespace

DemInfo read_dem_info(const std::string& path) {
  const OpenRaster r = open_raster(path);
  return {r.geo, r.rows, r.cols};
}

Grid read_dem(const std::string& path, const Progress& progress,
              std::optional<RasterWindow> window) {
  OpenRaster r = open_raster(path);
  RasterWindow w = window.value_or(RasterWindow{0, 0, r.rows, r.cols});
  if (w.rows < 1 || w.cols < 1 || w.row0 > r.rows || w.col0 > r.cols || w.rows > r.rows - w.row0 ||
      w.cols > r.cols - w.col0)
    throw Error("cannot read '" + path + "': window outside the raster");
  check_memory(double(w.rows) * double(w.cols) * sizeof(float),
               fmt::format("cannot read '{}': {} x {} samples", path, w.cols, w.rows),
               "crop it (dem2mesh --bbox reads only what it needs; build-drainage --tile-size "
               "reads a tile at a time)");
  Grid grid;
  grid.rows = w.rows;
  grid.cols = w.cols;
  grid.geo = r.geo;
  grid.geo.x0 = r.geo.x_of_col(double(w.col0)) - r.geo.dx / 2;
  grid.geo.y0 = r.geo.y_of_row(double(w.row0)) + r.geo.dy / 2;
  grid.z.resize(grid.rows * grid.cols);
  GDALRasterBand* band = r.ds->GetRasterBand(1);
  GDALRasterIOExtraArg extra;
  INIT_RASTERIO_EXTRA_ARG(extra);
  GdalProgress gdal_progress_data{progress};
  extra.pfnProgress = gdal_progress;
  extra.pProgressData = &gdal_progress_data;
  const std::size_t file_row0 = r.south_up ? r.rows - w.row0 - w.rows : w.row0;
  CPLErrorReset();
  if (band->RasterIO(GF_Read, int(w.col0), int(file_row0), int(w.cols), int(w.rows), grid.z.data(),
                     int(w.cols), int(w.rows), GDT_Float32, 0, 0, &extra) != CE_None) {
    if (gdal_progress_data.cancelled) throw Cancelled();
    throw Error("cannot read '" + path + "': " + last_gdal_error());
  }
  report(progress, 1.0);  // GDAL does not report every read (small VRT windows)
  if (r.south_up)
    for (std::size_t row = 0; row < grid.rows / 2; ++row)
      std::swap_ranges(grid.z.begin() + long(row * grid.cols),
                       grid.z.begin() + long((row + 1) * grid.cols),
                       grid.z.begin() + long((grid.rows - 1 - row) * grid.cols));

  finish_heights(grid, *band, path, w);
  return grid;
}

GdalCacheLimit::GdalCacheLimit(int mib) : before_(GDALGetCacheMax64()) {
  GDALSetCacheMax64(std::min<GIntBig>(before_, GIntBig(mib) << 20));
}
GdalCacheLimit::~GdalCacheLimit() { GDALSetCacheMax64(before_); }

struct RasterWriter::Impl {
  std::string path;
  AtomicFile out;
  DatasetPtr ds;
  GDALDataType gdt = GDT_Byte;
  std::size_t rows = 0, cols = 0;
  explicit Impl(const std::string& p) : path(p), out(p) {}
};

RasterWriter::RasterWriter(const std::string& path, const Georef& geo, std::size_t rows,
                           std::size_t cols, RasterType type, std::optional<double> nodata,
                           const std::string& metadata)
    : impl_(std::make_unique<Impl>(path)) {
  ensure_gdal();
  Impl& m = *impl_;
  m.rows = rows, m.cols = cols;
  m.gdt = type == RasterType::Byte     ? GDT_Byte
          : type == RasterType::Int16  ? GDT_Int16
          : type == RasterType::UInt32 ? GDT_UInt32
                                       : GDT_Float32;
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  CPLStringList opts;
  opts.SetNameValue("COMPRESS", "DEFLATE");
  opts.SetNameValue("PREDICTOR", type == RasterType::Float32 ? "3" : "2");
  if (cols >= 256 && rows >= 256) opts.SetNameValue("TILED", "YES");
  opts.SetNameValue("BIGTIFF", "IF_SAFER");
  opts.SetNameValue("NUM_THREADS", "ALL_CPUS");  // DEFLATE in parallel, tile by tile
  CPLErrorReset();
  m.ds.reset(gtiff->Create(m.out.temp_path().c_str(), int(cols), int(rows), 1, m.gdt, opts.List()));
  if (!m.ds) throw Error("cannot write '" + path + "': " + last_gdal_error());
  double gt[6] = {geo.x0, geo.dx, 0.0, geo.y0, 0.0, -geo.dy};
  m.ds->SetGeoTransform(gt);
  if (!geo.crs_wkt.empty()) {
    OGRSpatialReference srs;
    if (srs.importFromWkt(geo.crs_wkt.c_str()) == OGRERR_NONE) m.ds->SetSpatialRef(&srs);
  }
  if (!metadata.empty()) m.ds->SetMetadataItem("TIFFTAG_IMAGEDESCRIPTION", metadata.c_str());
  if (nodata) m.ds->GetRasterBand(1)->SetNoDataValue(*nodata);
}

RasterWriter::~RasterWriter() = default;

void RasterWriter::write_rows(std::size_t row0, std::size_t n, const void* data) {
  Impl& m = *impl_;
  if (!m.ds || row0 + n > m.rows)
    throw Error("RasterWriter: rows out of range or written after commit");
  if (m.ds->GetRasterBand(1)->RasterIO(GF_Write, 0, int(row0), int(m.cols), int(n),
                                       const_cast<void*>(data), int(m.cols), int(n), m.gdt, 0,
                                       0) != CE_None)
    throw Error("cannot write '" + m.path + "': " + last_gdal_error());
}

void RasterWriter::commit() {
  Impl& m = *impl_;
  // Closing flushes; a failure there (disk full) must not be committed.
  CPLErrorReset();
  m.ds.reset();
  if (CPLGetLastErrorType() >= CE_Failure)
    throw Error("cannot write '" + m.path + "': " + last_gdal_error());
  m.out.commit();
}

void write_raster(const std::string& path, const Georef& geo, std::size_t rows, std::size_t cols,
                  RasterType type, const void* data, std::optional<double> nodata,
                  const std::string& metadata) {
  RasterWriter w(path, geo, rows, cols, type, nodata, metadata);
  w.write_rows(0, rows, data);
  w.commit();
}

void write_geotiff(const Grid& grid, const std::string& path, const std::string& metadata) {
  BigVector<float> values(grid.z);
  for (float& v : values)
    if (std::isnan(v)) v = float(kGeoTiffNodata);
  write_raster(path, grid.geo, grid.rows, grid.cols, RasterType::Float32, values.data(),
               kGeoTiffNodata, metadata);
}

std::size_t fill_nodata(Grid& grid) {
  const std::size_t missing = grid.count_nodata();
  if (missing == 0) return 0;
  if (missing == grid.size()) throw Error("cannot fill no-data: the grid has no valid sample");
  DatasetPtr ds = wrap_in_mem_dataset(grid);
  GDALRasterBand* band = ds->GetRasterBand(1);
  const double max_search = double(std::max(grid.rows, grid.cols));
  // Its work rasters in memory: by default GDAL writes them as GeoTIFFs in the current
  // directory (up to 250 MB each), left behind when the run is interrupted.
  char temp_driver[] = "TEMP_FILE_DRIVER=MEM";
  char* fill_opts[] = {temp_driver, nullptr};
  if (GDALFillNodata(band, nullptr, max_search, 0, 0, fill_opts, nullptr, nullptr) != CE_None)
    throw Error("GDALFillNodata failed: " + last_gdal_error());
  ds.reset();  // the data pointer aliases grid.z: nothing to copy back
  const std::size_t left = grid.count_nodata();
  if (left != 0) throw Error("GDALFillNodata left " + std::to_string(left) + " no-data samples");
  return missing;
}

std::string crs_name(const Georef& geo) {
  if (geo.crs_wkt.empty()) return "none";
  ensure_gdal();
  OGRSpatialReference srs;
  if (srs.importFromWkt(geo.crs_wkt.c_str()) != OGRERR_NONE) return "unparsed CRS";
  const char* name = srs.GetName();
  return name ? name : "unnamed CRS";
}

}  // namespace terrain
