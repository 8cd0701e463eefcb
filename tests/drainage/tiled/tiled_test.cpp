// Tiled drainage steps equal the single-grid ones exactly: real DEMs with tile sizes that
// do and do not divide the grid, and small constructed cases (a depression across four
// tiles, a basin whose outlet is three tiles away).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <string>

#include "drainage/fill.hpp"
#include "drainage/flats.hpp"
#include "drainage/network.hpp"
#include "drainage/pipeline.hpp"
#include "drainage/tiled.hpp"
#include "drainage/tiled_pipeline.hpp"
#include "drainage_test_support.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

// A window reader over a grid in memory, counting the samples it hands out.
struct MemoryReader {
  const terrain::Grid& g;
  std::atomic<std::size_t> samples = 0;  // the tiled functions read on several threads
  terrain::Grid operator()(const terrain::RasterWindow& w) {
    terrain::Georef geo = g.geo;
    geo.x0 += double(w.col0) * geo.dx;
    geo.y0 -= double(w.row0) * geo.dy;
    terrain::Grid out(w.rows, w.cols, geo);
    for (std::size_t r = 0; r < w.rows; ++r)
      for (std::size_t c = 0; c < w.cols; ++c) out.at(r, c) = g.at(w.row0 + r, w.col0 + c);
    samples += out.size();
    return out;
  }
};

// The tiled fill of `dem` assembled into one grid; checks the tiles' georeferencing. With
// `cache`, pass 2 reads pass 1's tiles from that file instead of flooding again.
terrain::Grid tiled_fill(const terrain::Grid& dem, std::size_t side, std::size_t& raised, const std::string& cache = {}) {
  terrain::Grid out(dem.rows, dem.cols, dem.geo, -1.0f);
  MemoryReader reader{dem};
  const TileGrid tiles{dem.rows, dem.cols, side};
  std::size_t calls = 0;
  raised = tiled_priority_flood_fill(tiles, std::ref(reader), [&](std::size_t t, terrain::Grid& tile) {
    const terrain::RasterWindow w = tiles.window(t);
    EXPECT_EQ(t, calls++);
    EXPECT_DOUBLE_EQ(tile.geo.x_of_col(0), dem.geo.x_of_col(double(w.col0)));
    EXPECT_DOUBLE_EQ(tile.geo.y_of_row(0), dem.geo.y_of_row(double(w.row0)));
    for (std::size_t r = 0; r < w.rows; ++r)
      for (std::size_t c = 0; c < w.cols; ++c) out.at(w.row0 + r, w.col0 + c) = tile.at(r, c);
  }, single_process(), cache);
  EXPECT_EQ(calls, tiles.count());
  if (!cache.empty()) {
    EXPECT_FALSE(std::filesystem::exists(cache)) << "the cache outlives the fill";
  }
  return out;
}

// Both strategies of pass 2 (flood again; read pass 1's tiles back) against the whole grid.
void expect_same_fill(const terrain::Grid& dem, std::size_t side) {
  terrain::Grid whole = dem;
  const std::size_t raised_whole = priority_flood_fill(whole);
  terrain::test::ScratchDir dir;
  for (const std::string& cache : {std::string(), dir.path("fill.cache")}) {
    std::size_t raised_tiled = 0;
    const terrain::Grid tiled = tiled_fill(dem, side, raised_tiled, cache);
    EXPECT_EQ(raised_tiled, raised_whole) << "tile side " << side << " cache '" << cache << "'";
    std::size_t differ = 0;
    for (std::size_t i = 0; i < dem.size(); ++i)
      differ += !(tiled.z[i] == whole.z[i] || (std::isnan(tiled.z[i]) && std::isnan(whole.z[i])));
    EXPECT_EQ(differ, 0u) << "tile side " << side << " cache '" << cache << "': " << differ << " samples differ";
  }
}

TEST(TiledFill, RealDemsEqualTheSingleGridFill) {
  for (const char* name : {"med_01_01_10m.tif", "msh_2007_utm10n_10m.tif", "logan_utm12n_100m.tif"}) {
    const terrain::Grid dem = terrain::read_dem(terrain::test::data(name));
    SCOPED_TRACE(name);
    for (const std::size_t side : {std::size_t(64), std::size_t(100), std::size_t(97), std::size_t(4096)})
      expect_same_fill(dem, side);
  }
}

// Logan at 10 m (gdalwarp -r cubic of the bundled 100 m DEM): 14.4 M samples, tiles of
// 1000 (does not divide 2890 x 4980) and 1245 (divides the rows: 4 x 1245 = 4980).
TEST(TiledFill, Logan10mEqualsTheSingleGridFill) {
  terrain::test::ScratchDir dir;
  const std::string tif = dir.path("logan10.tif");
  ASSERT_EQ(std::system(("gdalwarp -q -r cubic -tr 10 10 " + terrain::test::data("logan_utm12n_100m.tif") + " " + tif).c_str()), 0);
  const terrain::Grid dem = terrain::read_dem(tif);
  ASSERT_EQ(dem.size(), 14'392'200u);
  expect_same_fill(dem, 1000);
  expect_same_fill(dem, 1245);
}

// A square bowl whose floor spans the corner of four 8 x 8 tiles, draining over one low
// rim cell three tiles away from the bowl's tiles (a channel cut through a high ridge).
TEST(TiledFill, DepressionAcrossFourTilesAndAFarOutlet) {
  const std::size_t n = 40;
  terrain::Georef geo;
  terrain::Grid dem(n, n, geo, 100.0f);
  for (std::size_t r = 4; r < 12; ++r)  // the bowl: rows and columns 4..11, across tiles 0, 1, 5, 6
    for (std::size_t c = 4; c < 12; ++c) dem.at(r, c) = 10.0f + float(std::abs(int(r) - 8) + std::abs(int(c) - 8));
  for (std::size_t c = 12; c < n; ++c) dem.at(8, c) = 50.0f - float(c) * 0.5f;  // a channel east to the edge
  dem.at(8, 30) = 60.0f;  // a sill three tiles east of the bowl: the bowl fills to 60
  expect_same_fill(dem, 8);
  std::size_t raised = 0;
  const terrain::Grid filled = tiled_fill(dem, 8, raised);
  EXPECT_EQ(filled.at(8, 8), 60.0f);
  EXPECT_EQ(filled.at(8, 20), 60.0f);  // the channel behind the sill fills too
  EXPECT_EQ(filled.at(8, 35), dem.at(8, 35));  // below the sill water leaves
  // With no-data around a pit instead of the sill: the no-data is an outlet.
  dem.at(8, 30) = NAN;
  expect_same_fill(dem, 8);
  expect_same_fill(dem, 7);
  expect_same_fill(dem, 1);
}

// The tiled network of `dirs` assembled into grids, against analyze_network: every field.
void expect_same_network(const D8Codes& dirs, std::size_t rows, std::size_t cols, std::size_t side) {
  SCOPED_TRACE("tile side " + std::to_string(side));
  const Network net = analyze_network(dirs, rows, cols);
  const TileGrid tiles{rows, cols, side};
  terrain::BigVector<std::uint32_t> acc(rows * cols, 7), basin(rows * cols, 7);
  terrain::BigVector<std::uint8_t> order(rows * cols, 99), cut(rows * cols, 9);
  std::size_t read_codes = 0;
  const NetworkTotals totals = tiled_network(
      tiles,
      [&](const terrain::RasterWindow& w) {
        D8Codes out(w.rows * w.cols);
        for (std::size_t r = 0; r < w.rows; ++r)
          for (std::size_t c = 0; c < w.cols; ++c) out[r * w.cols + c] = dirs[(w.row0 + r) * cols + w.col0 + c];
        read_codes += out.size();
        return out;
      },
      [&](std::size_t t, const NetworkTile& tile) {
        const terrain::RasterWindow w = tiles.window(t);
        for (std::size_t r = 0; r < w.rows; ++r)
          for (std::size_t c = 0; c < w.cols; ++c) {
            const std::size_t i = (w.row0 + r) * cols + w.col0 + c, q = r * w.cols + c;
            ASSERT_EQ(tile.dirs[q], dirs[i]);
            acc[i] = tile.accumulated[q], basin[i] = tile.basin[q], order[i] = tile.order[q], cut[i] = tile.cut[q];
          }
      });
  EXPECT_EQ(totals.points, net.points);
  EXPECT_EQ(totals.branches, net.branches.size());
  ASSERT_EQ(totals.pits.size(), net.pits.size());
  for (std::size_t b = 0; b < net.pits.size(); ++b) {
    ASSERT_EQ(totals.pits[b], net.pits[b]) << "basin " << b;
    ASSERT_EQ(totals.pit_accumulated[b], net.accumulated[net.pits[b]]) << "basin " << b;
  }
  std::size_t differ = 0;
  for (std::size_t i = 0; i < rows * cols; ++i) {
    const bool same = acc[i] == net.accumulated[i] && basin[i] == net.basin[i] && order[i] == net.order[i] &&
                      cut[i] == (dirs[i] < 8 && net.downstream[i] == kNone);
    if (!same && differ++ < 3)
      ADD_FAILURE() << "point " << i << ": accumulated " << acc[i] << " vs " << net.accumulated[i] << ", basin "
                    << basin[i] << " vs " << net.basin[i] << ", order " << int(order[i]) << " vs " << int(net.order[i]);
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_LE(read_codes, 2 * (rows + 2 * tiles.tile_rows()) * (cols + 2 * tiles.tile_cols()));  // two passes, halos
}

D8Codes resolved_directions(const terrain::Grid& dem) {
  D8Codes dirs = d8_directions(dem);
  resolve_flats(dem, dirs);
  return dirs;
}

TEST(TiledNetwork, RealDemsEqualTheSingleGridNetwork) {
  for (const char* name : {"med_01_01_10m.tif", "msh_2007_utm10n_10m.tif", "logan_utm12n_100m.tif"}) {
    SCOPED_TRACE(name);
    terrain::Grid dem = terrain::read_dem(terrain::test::data(name));
    const D8Codes plain = resolved_directions(dem);
    for (const std::size_t side : {std::size_t(64), std::size_t(97), std::size_t(1), std::size_t(4096)})
      expect_same_network(plain, dem.rows, dem.cols, side);
    priority_flood_fill(dem);  // filled: few, large basins that cross many tiles
    const D8Codes filled = resolved_directions(dem);
    expect_same_network(filled, dem.rows, dem.cols, 50);
    expect_same_network(filled, dem.rows, dem.cols, 128);
  }
}

// A basin whose pit is three tiles from most of its points: a long channel down a tilted
// plane into a pit, with ridges either side (orders rise where side streams meet).
TEST(TiledNetwork, BasinWhoseOutletIsThreeTilesAway) {
  const std::size_t n = 48;
  const terrain::Grid dem = test::analytic(n, 1.0, [](double x, double y) {
    return -0.2 * x + std::abs(y) + (std::abs(x - 20.5) < 1 && std::abs(y) < 1 ? -50.0 : 0.0);
  });
  const D8Codes dirs = resolved_directions(dem);
  const Network net = analyze_network(dirs, n, n);
  const std::size_t far = (n / 2) * n + 1;  // the channel's west end, 5 tiles of 8 from the pit
  ASSERT_EQ(net.point_class[net.pits[net.basin[far]]], std::uint8_t(PointClass::Pit));
  const std::size_t pit = net.pits[net.basin[far]];
  EXPECT_GE(pit % n, 40u);                                 // the pit is at the east end
  EXPECT_GT(net.accumulated[pit], n * n / 3);              // and drains a large share of the grid
  EXPECT_GE(int(net.order[pit]), 3);
  for (const std::size_t side : {std::size_t(8), std::size_t(11), std::size_t(16)}) expect_same_network(dirs, n, n, side);
}

// --memory: untiled while the grid fits at 40 bytes per point, else the largest multiple
// of 256 whose tiles fit at 100 bytes per point besides 64 MiB, at least 256.
TEST(TiledRun, TileSizeForMemory) {
  terrain::DemInfo info;
  info.rows = 4000, info.cols = 5000;  // 20 M points: 800 MB untiled
  EXPECT_EQ(tile_size_for_memory(info, 800e6), 0u);
  // The largest multiple of 256 whose run fits: 64 MiB + 100 side^2 + 190 * 4 * 20e6 / side.
  for (const double budget : {799e6, 200.0 * (1 << 20)})
    for (const int threads : {1, 2}) {
      const std::size_t side = tile_size_for_memory(info, budget, threads);
      EXPECT_LE(tiled_run_bytes(info, side, threads), budget) << budget << " " << threads;
      EXPECT_GT(tiled_run_bytes(info, side + 256, threads), budget) << budget << " " << threads;
    }
  EXPECT_EQ(tile_size_for_memory(info, 799e6), 2560u);  // 64 MiB + 655 MB + 5.9 MB
  EXPECT_EQ(tile_size_for_memory(info, 799e6, 2), 1792u);  // two threads hold two tiles
  EXPECT_EQ(tile_size_for_memory(info, 800e6, 2), 0u);  // untiled: one grid whatever the threads
  // Too little for any side: the side that needs least, not the smallest.
  const std::size_t least = tile_size_for_memory(info, 1e6);
  for (std::size_t side = 256; side <= 16384; side += 256)
    EXPECT_LE(tiled_run_bytes(info, least, 1), tiled_run_bytes(info, side, 1)) << side;
}

}  // namespace
}  // namespace drainage
