// The tiled Priority-Flood fill (tiled_fill.cpp) equals the single-grid fill exactly: real
// DEMs with tile sizes that do and do not divide the grid, both strategies of pass 2, and a
// depression across four tiles with a far outlet.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <string>

#include "drainage/fill.hpp"
#include "drainage/tiled.hpp"
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
terrain::Grid tiled_fill(const terrain::Grid& dem, std::size_t side, std::size_t& raised,
                         const std::string& cache = {}) {
  terrain::Grid out(dem.rows, dem.cols, dem.geo, -1.0f);
  MemoryReader reader{dem};
  const TileGrid tiles{dem.rows, dem.cols, side};
  std::size_t calls = 0;
  raised = tiled_priority_flood_fill(
      tiles, std::ref(reader),
      [&](std::size_t t, terrain::Grid& tile) {
        const terrain::RasterWindow w = tiles.window(t);
        EXPECT_EQ(t, calls++);
        EXPECT_DOUBLE_EQ(tile.geo.x_of_col(0), dem.geo.x_of_col(double(w.col0)));
        EXPECT_DOUBLE_EQ(tile.geo.y_of_row(0), dem.geo.y_of_row(double(w.row0)));
        for (std::size_t r = 0; r < w.rows; ++r)
          for (std::size_t c = 0; c < w.cols; ++c) out.at(w.row0 + r, w.col0 + c) = tile.at(r, c);
      },
      single_process(), cache);
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
    EXPECT_EQ(differ, 0u) << "tile side " << side << " cache '" << cache << "': " << differ
                          << " samples differ";
  }
}

TEST(TiledFill, RealDemsEqualTheSingleGridFill) {
  for (const char* name :
       {"med_01_01_10m.tif", "msh_2007_utm10n_10m.tif", "logan_utm12n_100m.tif"}) {
    const terrain::Grid dem = terrain::read_dem(terrain::test::data(name));
    SCOPED_TRACE(name);
    for (const std::size_t side :
         {std::size_t(64), std::size_t(100), std::size_t(97), std::size_t(4096)})
      expect_same_fill(dem, side);
  }
}

// Logan at 10 m (gdalwarp -r cubic of the bundled 100 m DEM): 14.4 M samples, tiles of
// 1000 (does not divide 2890 x 4980) and 1245 (divides the rows: 4 x 1245 = 4980).
TEST(TiledFill, Logan10mEqualsTheSingleGridFill) {
  terrain::test::ScratchDir dir;
  const std::string tif = dir.path("logan10.tif");
  ASSERT_EQ(std::system(("gdalwarp -q -r cubic -tr 10 10 " +
                         terrain::test::data("logan_utm12n_100m.tif") + " " + tif)
                            .c_str()),
            0);
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
    for (std::size_t c = 4; c < 12; ++c)
      dem.at(r, c) = 10.0f + float(std::abs(int(r) - 8) + std::abs(int(c) - 8));
  for (std::size_t c = 12; c < n; ++c)
    dem.at(8, c) = 50.0f - float(c) * 0.5f;  // a channel east to the edge
  dem.at(8, 30) = 60.0f;  // a sill three tiles east of the bowl: the bowl fills to 60
  expect_same_fill(dem, 8);
  std::size_t raised = 0;
  const terrain::Grid filled = tiled_fill(dem, 8, raised);
  EXPECT_EQ(filled.at(8, 8), 60.0f);
  EXPECT_EQ(filled.at(8, 20), 60.0f);          // the channel behind the sill fills too
  EXPECT_EQ(filled.at(8, 35), dem.at(8, 35));  // below the sill water leaves
  // With no-data around a pit instead of the sill: the no-data is an outlet.
  dem.at(8, 30) = NAN;
  expect_same_fill(dem, 8);
  expect_same_fill(dem, 7);
  expect_same_fill(dem, 1);
}

}  // namespace
}  // namespace drainage
