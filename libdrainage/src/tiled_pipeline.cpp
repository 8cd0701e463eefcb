// build-drainage's raster mode tile by tile (tiled.hpp): GDAL windows in, .dv blocks out.
#include <gdal_priv.h>

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/tiled.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/dem_io.hpp"

namespace drainage {

namespace {

// A temporary Float32 GeoTIFF written window by window, then read window by window.
class ScratchRaster {
 public:
  ScratchRaster(const std::string& path, const terrain::DemInfo& info) : path_(path) {
    terrain::ensure_gdal();
    CPLStringList opts;
    opts.SetNameValue("TILED", "YES");
    opts.SetNameValue("BIGTIFF", "YES");
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    ds_ = gtiff->Create(path.c_str(), int(info.cols), int(info.rows), 1, GDT_Float32, opts.List());
    if (!ds_) throw terrain::Error("cannot create the temporary raster '" + path + "'");
    double gt[6] = {info.geo.x0, info.geo.dx, 0.0, info.geo.y0, 0.0, -info.geo.dy};
    ds_->SetGeoTransform(gt);
    if (!info.geo.crs_wkt.empty()) {
      OGRSpatialReference srs;
      if (srs.importFromWkt(info.geo.crs_wkt.c_str()) == OGRERR_NONE) ds_->SetSpatialRef(&srs);
    }
    ds_->GetRasterBand(1)->SetNoDataValue(-9999.0);
  }
  ~ScratchRaster() {
    if (ds_) GDALClose(ds_);
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  void write(const terrain::RasterWindow& w, const terrain::Grid& g) {
    std::vector<float> v(g.z.begin(), g.z.end());
    for (float& x : v)
      if (std::isnan(x)) x = -9999.0f;
    if (ds_->GetRasterBand(1)->RasterIO(GF_Write, int(w.col0), int(w.row0), int(w.cols), int(w.rows), v.data(),
                                        int(w.cols), int(w.rows), GDT_Float32, 0, 0) != CE_None)
      throw terrain::Error("cannot write the temporary raster '" + path_ + "' (disk full?)");
  }
  void close() {
    GDALClose(ds_);
    ds_ = nullptr;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  GDALDataset* ds_ = nullptr;
};

terrain::RasterWindow expanded(const terrain::RasterWindow& w, std::size_t rows, std::size_t cols) {
  terrain::RasterWindow h = w;
  if (h.row0 > 0) --h.row0, ++h.rows;
  if (h.col0 > 0) --h.col0, ++h.cols;
  h.rows = std::min(h.rows + 1, rows - h.row0);
  h.cols = std::min(h.cols + 1, cols - h.col0);
  return h;
}

}  // namespace

TiledSummary run_tiled_drainage(const TiledRun& run, const std::string& output_path, const terrain::Progress& progress) {
  if (run.tile == 0 || run.tile > 16384) throw terrain::Error("--tile-size must be between 1 and 16384");
  if (run.dem.empty() == run.d8.empty()) throw terrain::Error("tiled mode takes a DEM or a D8 raster (not both yet)");
  if (!run.dem.empty() && run.resolve_flats)
    throw terrain::Error("--tile-size resolves no flats yet: add --keep-flats (flats that cross tiles are the next step)");
  const std::string input = run.dem.empty() ? run.d8 : run.dem;
  const terrain::DemInfo info = terrain::read_dem_info(input);
  TiledSummary summary;
  summary.rows = info.rows, summary.cols = info.cols, summary.dx = info.geo.dx, summary.dy = info.geo.dy;
  const TileGrid tiles{info.rows, info.cols, run.tile};
  summary.tiles = tiles.count();
  auto read_z = [&, path = run.dem](const terrain::RasterWindow& w) { return terrain::read_dem(path, {}, w); };
  std::uint32_t flags = 0;
  std::function<terrain::Grid(const terrain::RasterWindow&)> surface = read_z;

  std::unique_ptr<ScratchRaster> scratch;
  if (!run.dem.empty() && run.fill) {
    scratch = std::make_unique<ScratchRaster>(output_path + ".filled.tmp.tif", info);
    summary.filled = tiled_priority_flood_fill(tiles, read_z, [&](std::size_t t, terrain::Grid& g) {
      scratch->write(tiles.window(t), g);
      terrain::report(progress, 0.3 * double(t + 1) / double(tiles.count()));
    });
    scratch->close();
    surface = [path = scratch->path()](const terrain::RasterWindow& w) { return terrain::read_dem(path, {}, w); };
    flags |= kDvFilled;
  }
  CodeReader codes;
  if (!run.dem.empty()) {
    flags |= kDvHasElevations;
    codes = [&](const terrain::RasterWindow& w) {  // D8 of the window, from the window with one more sample
      const terrain::RasterWindow h = expanded(w, info.rows, info.cols);
      const D8Codes all = d8_directions(surface(h));
      D8Codes out(w.rows * w.cols);
      for (std::size_t r = 0; r < w.rows; ++r)
        for (std::size_t c = 0; c < w.cols; ++c)
          out[r * w.cols + c] = all[(r + w.row0 - h.row0) * h.cols + c + w.col0 - h.col0];
      return out;
    };
  } else {
    codes = [&](const terrain::RasterWindow& w) {
      const terrain::Grid g = terrain::read_dem(run.d8, {}, w);
      D8Codes out(g.size());
      for (std::size_t i = 0; i < g.size(); ++i) {
        try {
          out[i] = from_foreign_code(g.z[i], run.encoding, std::isnan(g.z[i]));
        } catch (const terrain::Error& e) {
          throw terrain::Error(fmt::format("'{}' row {}, column {}: {}", run.d8, w.row0 + i / g.cols,
                                           w.col0 + i % g.cols, e.what()));
        }
      }
      return out;
    };
  }

  DvHeader h;
  h.flags = flags;
  h.rows = info.rows, h.cols = info.cols;
  h.origin_x = info.geo.x_of_col(0), h.origin_y = info.geo.y_of_row(0);
  h.dx = info.geo.dx, h.dy = info.geo.dy;
  h.epsg = info.geo.epsg;
  h.crs_wkt = info.geo.crs_wkt;
  h.provenance = run.provenance;
  h.block_rows = h.block_cols = std::uint32_t(run.tile);  // one block per tile
  terrain::write_stream_atomic(output_path, [&](std::ostream& file) {
    DvBlockWriter writer(file, output_path, h);
    summary.totals = tiled_network(tiles, codes, [&](std::size_t t, const NetworkTile& tile) {
      const std::size_t m = tile.dirs.size();
      DvBlockFields f;
      f.z.resize(m);
      if (flags & kDvHasElevations) {
        const terrain::Grid g = surface(tile.window);
        for (std::size_t q = 0; q < m; ++q) f.z[q] = std::isnan(g.z[q]) ? 0.0f : g.z[q];
      }
      f.d8.assign(tile.dirs.begin(), tile.dirs.end());
      f.cut.assign(tile.cut.begin(), tile.cut.end());
      f.accumulated.assign(tile.accumulated.begin(), tile.accumulated.end());
      f.basin.assign(tile.basin.begin(), tile.basin.end());
      f.order.assign(tile.order.begin(), tile.order.end());
      writer.put_block(t, encode_dv_block(f));
      terrain::report(progress, 0.3 + 0.7 * double(t + 1) / double(tiles.count()));
    });
    writer.finish(summary.totals.points, summary.totals.branches, summary.totals.pits, summary.totals.pit_accumulated);
  });
  return summary;
}

}  // namespace drainage
