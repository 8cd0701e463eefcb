#include "drainage/rasters.hpp"

#include <algorithm>
#include <filesystem>

#include <gdal.h>
#include <fmt/format.h>

#include "drainage/dv_file.hpp"
#include "drainage/network.hpp"
#include "terrain/dem_io.hpp"

namespace drainage {

void write_drainage_rasters(const std::string& dir, const DrainageResult& r, D8Encoding encoding,
                            const std::string& provenance) {
  write_drainage_rasters([&](const std::string& name) { return (std::filesystem::path(dir) / name).string(); }, r,
                         encoding, provenance);
}

void write_drainage_rasters(const std::function<std::string(const std::string&)>& path, const DrainageResult& r,
                            D8Encoding encoding, const std::string& provenance) {
  using terrain::RasterType;
  const terrain::Grid& g = r.surface;
  const Network& net = r.net;
  if (net.normalized.size() != g.size())
    throw terrain::Error("write_drainage_rasters: the normalized flow was not listed (NetworkDetail::Full)");
  terrain::write_geotiff(g, path("surface.tif"), provenance);
  std::vector<std::int16_t> d8(g.size());
  for (std::size_t i = 0; i < g.size(); ++i)
    d8[i] = r.dirs[i] == kNodata ? std::int16_t(-32768) : std::int16_t(to_foreign_code(r.dirs[i], encoding));
  terrain::write_raster(path("d8.tif"), g.geo, g.rows, g.cols, RasterType::Int16, d8.data(), -32768.0, provenance);
  terrain::write_raster(path("accumulation.tif"), g.geo, g.rows, g.cols, RasterType::UInt32, net.accumulated.data(), 0.0,
                        provenance);
  terrain::write_raster(path("normalized_flow.tif"), g.geo, g.rows, g.cols, RasterType::Float32, net.normalized.data(),
                        0.0, provenance);
  terrain::write_raster(path("basin.tif"), g.geo, g.rows, g.cols, RasterType::UInt32, net.basin.data(),
                        double(kNone), provenance);
  terrain::write_raster(path("class.tif"), g.geo, g.rows, g.cols, RasterType::Byte, net.point_class.data(), 255.0,
                        provenance);
  terrain::write_raster(path("order.tif"), g.geo, g.rows, g.cols, RasterType::Byte, net.order.data(), 0.0, provenance);
}

std::size_t export_dv_rasters(const std::string& dv_path, const std::function<std::string(const std::string&)>& path,
                              D8Encoding encoding, const std::string& provenance, std::size_t window_rows) {
  using terrain::RasterType;
  const DvHeader h = read_dv_header(dv_path);
  const std::size_t R = std::size_t(h.rows), C = std::size_t(h.cols);
  // GDAL keeps written tiles in its block cache (by default 5 % of the memory): at most
  // 128 MiB here, so that memory follows the window; restored on the way out.
  struct CacheLimit {
    GIntBig before = GDALGetCacheMax64();
    CacheLimit() { GDALSetCacheMax64(std::min<GIntBig>(before, GIntBig(128) << 20)); }
    ~CacheLimit() { GDALSetCacheMax64(before); }
  } cache_limit;
  terrain::Georef geo;
  geo.dx = h.dx, geo.dy = h.dy;
  geo.x0 = h.origin_x - h.dx / 2, geo.y0 = h.origin_y + h.dy / 2;
  geo.crs_wkt = h.crs_wkt, geo.epsg = h.epsg;
  terrain::RasterWriter surface(path("surface.tif"), geo, R, C, RasterType::Float32, terrain::kGeoTiffNodata, provenance);
  terrain::RasterWriter d8(path("d8.tif"), geo, R, C, RasterType::Int16, -32768.0, provenance);
  terrain::RasterWriter acc(path("accumulation.tif"), geo, R, C, RasterType::UInt32, 0.0, provenance);
  terrain::RasterWriter flow(path("normalized_flow.tif"), geo, R, C, RasterType::Float32, 0.0, provenance);
  terrain::RasterWriter basin(path("basin.tif"), geo, R, C, RasterType::UInt32, double(kNone), provenance);
  terrain::RasterWriter cls(path("class.tif"), geo, R, C, RasterType::Byte, 255.0, provenance);
  terrain::RasterWriter order(path("order.tif"), geo, R, C, RasterType::Byte, 0.0, provenance);
  const std::size_t step = std::max<std::size_t>(1, window_rows);
  std::vector<float> vz, vf;
  std::vector<std::int16_t> vd;
  std::vector<std::uint32_t> va, vb;
  std::vector<std::uint8_t> vc, vo;
  for (std::size_t r0 = 0; r0 < R; r0 += step) {
    const std::size_t n = std::min(step, R - r0), m = n * C;
    const DrainageDb w = read_dv_window(dv_path, r0, 0, n, C);
    vz.resize(m), vf.resize(m), vd.resize(m), va.resize(m), vb.resize(m), vc.resize(m), vo.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      const DvVertex& v = w.vertices[i];
      const bool nodata = PointClass(v.point_class) == PointClass::Nodata;
      vz[i] = nodata ? float(terrain::kGeoTiffNodata) : float(h.origin_z + v.z);
      vd[i] = v.d8 == kNodata ? std::int16_t(-32768) : std::int16_t(to_foreign_code(v.d8, encoding));
      va[i] = v.accumulated, vf[i] = v.normalized, vb[i] = v.basin, vc[i] = v.point_class, vo[i] = v.order;
    }
    surface.write_rows(r0, n, vz.data());
    d8.write_rows(r0, n, vd.data());
    acc.write_rows(r0, n, va.data());
    flow.write_rows(r0, n, vf.data());
    basin.write_rows(r0, n, vb.data());
    cls.write_rows(r0, n, vc.data());
    order.write_rows(r0, n, vo.data());
  }
  for (terrain::RasterWriter* wr : {&surface, &d8, &acc, &flow, &basin, &cls, &order}) wr->commit();
  return R * C;
}

D8Codes read_d8_raster(const std::string& path, D8Encoding encoding, terrain::Grid& grid) {
  grid = terrain::read_dem(path);
  D8Codes dirs(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    try {
      dirs[i] = from_foreign_code(grid.z[i], encoding, false);
    } catch (const terrain::Error& e) {
      throw terrain::Error(fmt::format("'{}' row {}, column {}: {}", path, i / grid.cols, i % grid.cols, e.what()));
    }
  }
  return dirs;
}

}  // namespace drainage
