#include "drainage/rasters.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <memory>

#include <fmt/format.h>
#include <gdal.h>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/network.hpp"
#include "terrain/dem_io.hpp"

namespace drainage {

namespace {

// The layers' types and no-data values, in kDrainageRasterNames' order: the untiled run's
// rasters and a .dv's export are the same files.
constexpr std::size_t kLayers = std::size(kDrainageRasterNames);
struct LayerFormat {
  terrain::RasterType type;
  double nodata;
};
constexpr LayerFormat kFormat[kLayers] = {
    {terrain::RasterType::Float32, terrain::kGeoTiffNodata},  // surface
    {terrain::RasterType::Int16, -32768.0},                   // d8
    {terrain::RasterType::UInt32, 0.0},                       // accumulation
    {terrain::RasterType::Float32, 0.0},                      // normalized flow
    {terrain::RasterType::UInt32, double(kNone)},             // basin
    {terrain::RasterType::Byte, 255.0},                       // class
    {terrain::RasterType::Byte, 0.0},                         // order
};

std::int16_t d8_value(std::uint8_t code, D8Encoding encoding) {
  return code == kNodata ? std::int16_t(-32768) : std::int16_t(to_foreign_code(code, encoding));
}

}  // namespace

void write_drainage_rasters(const std::string& dir, const DrainageResult& r, D8Encoding encoding,
                            const std::string& provenance) {
  write_drainage_rasters(
      [&](const std::string& name) { return (std::filesystem::path(dir) / name).string(); }, r,
      encoding, provenance);
}

void write_drainage_rasters(const std::function<std::string(const std::string&)>& path,
                            const DrainageResult& r, D8Encoding encoding,
                            const std::string& provenance) {
  const terrain::Grid& g = r.surface;
  const Network& net = r.net;
  if (net.normalized.size() != g.size())
    throw terrain::Error(
        "write_drainage_rasters: the normalized flow was not listed (NetworkDetail::Full)");
  terrain::write_geotiff(g, path("surface.tif"), provenance);
  std::vector<std::int16_t> d8(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) d8[i] = d8_value(r.dirs[i], encoding);
  const void* data[kLayers] = {nullptr,
                               d8.data(),
                               net.accumulated.data(),
                               net.normalized.data(),
                               net.basin.data(),
                               net.point_class.data(),
                               net.order.data()};
  for (std::size_t k = 1; k < kLayers; ++k)
    terrain::write_raster(path(kDrainageRasterNames[k]), g.geo, g.rows, g.cols, kFormat[k].type,
                          data[k], kFormat[k].nodata, provenance);
}

std::size_t export_dv_rasters(const std::string& dv_path,
                              const std::function<std::string(const std::string&)>& path,
                              D8Encoding encoding, const std::string& provenance,
                              std::size_t window_rows) {
  const DvHeader h = read_dv_header(dv_path);
  const std::size_t R = std::size_t(h.rows), C = std::size_t(h.cols);
  const terrain::GdalCacheLimit cache_limit;  // memory follows the window
  const terrain::Georef geo = dv_georef(h);
  std::vector<std::unique_ptr<terrain::RasterWriter>> out;
  for (std::size_t k = 0; k < kLayers; ++k)
    out.push_back(std::make_unique<terrain::RasterWriter>(
        path(kDrainageRasterNames[k]), geo, R, C, kFormat[k].type, kFormat[k].nodata, provenance));
  const std::size_t step = std::max<std::size_t>(1, window_rows);
  std::vector<float> vz, vf;
  std::vector<std::int16_t> vd;
  std::vector<std::uint32_t> va, vb;
  std::vector<std::uint8_t> vc, vo;
  for (std::size_t r0 = 0; r0 < R; r0 += step) {
    const std::size_t n = std::min(step, R - r0), m = n * C;
    const DrainageDb w = read_dv_window(dv_path, r0, 0, n, C);
    vz.resize(m), vf.resize(m), vd.resize(m), va.resize(m), vb.resize(m), vc.resize(m),
        vo.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      const DvVertex& v = w.vertices[i];
      const bool nodata = PointClass(v.point_class) == PointClass::Nodata;
      vz[i] = nodata ? float(terrain::kGeoTiffNodata) : float(h.origin_z + v.z);
      vd[i] = d8_value(v.d8, encoding);
      va[i] = v.accumulated, vf[i] = v.normalized, vb[i] = v.basin, vc[i] = v.point_class,
      vo[i] = v.order;
    }
    const void* data[kLayers] = {vz.data(), vd.data(), va.data(), vf.data(),
                                 vb.data(), vc.data(), vo.data()};
    for (std::size_t k = 0; k < kLayers; ++k) out[k]->write_rows(r0, n, data[k]);
  }
  for (const auto& layer : out) layer->commit();
  return R * C;
}

void check_same_grid(const terrain::Grid& a, const terrain::Grid& b, const std::string& an,
                     const std::string& bn) {
  const double tol = 1e-6 * std::max(a.geo.dx, a.geo.dy);
  if (a.rows != b.rows || a.cols != b.cols || std::abs(a.geo.x0 - b.geo.x0) > tol ||
      std::abs(a.geo.y0 - b.geo.y0) > tol || std::abs(a.geo.dx - b.geo.dx) > tol ||
      std::abs(a.geo.dy - b.geo.dy) > tol)
    throw terrain::Error(fmt::format(
        "mismatched grids: '{}' is {} x {} at ({}, {}) step {}, '{}' is {} x {} at ({}, {}) "
        "step {}",
        an, a.cols, a.rows, a.geo.x0, a.geo.y0, a.geo.dx, bn, b.cols, b.rows, b.geo.x0, b.geo.y0,
        b.geo.dx));
}

RasterInput read_raster_input(const std::string& dem_path, const std::string& d8_path,
                              D8Encoding encoding) {
  if (dem_path.empty() && d8_path.empty())
    throw terrain::Error("raster mode needs a DEM or a D8 direction raster");
  RasterInput in;
  if (!dem_path.empty()) {
    in.surface = terrain::read_dem(dem_path);
    if (in.surface.count_nodata() == in.surface.size())
      throw terrain::Error("'" + dem_path + "' has no valid sample (every cell is no-data)");
    in.dv_flags |= kDvHasElevations;
  }
  if (d8_path.empty()) return in;
  terrain::Grid dir_grid;
  D8Codes dirs = read_d8_raster(d8_path, encoding, dir_grid);
  if (!dem_path.empty()) {
    check_same_grid(in.surface, dir_grid, dem_path, d8_path);
    for (std::size_t i = 0; i < in.surface.size(); ++i)  // no elevation: not a point
      if (std::isnan(in.surface.z[i])) dirs[i] = kNodata;
  } else {
    in.surface = std::move(dir_grid);
    for (std::size_t i = 0; i < in.surface.size(); ++i)
      in.surface.z[i] = dirs[i] == kNodata ? NAN : 0.0f;
  }
  in.dirs = std::move(dirs);
  return in;
}

D8Codes read_d8_raster(const std::string& path, D8Encoding encoding, terrain::Grid& grid) {
  grid = terrain::read_dem(path);
  D8Codes dirs(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    try {
      dirs[i] = from_foreign_code(grid.z[i], encoding, false);
    } catch (const terrain::Error& e) {
      throw terrain::Error(
          fmt::format("'{}' row {}, column {}: {}", path, i / grid.cols, i % grid.cols, e.what()));
    }
  }
  return dirs;
}

}  // namespace drainage
