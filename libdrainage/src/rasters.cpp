#include "drainage/rasters.hpp"

#include <filesystem>
#include <fmt/format.h>

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
