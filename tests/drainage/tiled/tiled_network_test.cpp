// The tiled network (tiled_network.cpp) equals analyze_network on the whole grid in every
// field: real DEMs with tile sizes that do and do not divide the grid, and a basin whose
// outlet is three tiles away.
#include <gtest/gtest.h>

#include <string>

#include "drainage/fill.hpp"
#include "drainage/network.hpp"
#include "drainage/pipeline.hpp"
#include "drainage/tiled.hpp"
#include "drainage_test_support.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

// The tiled network of `dirs` assembled into grids, against analyze_network: every field.
void expect_same_network(const D8Codes& dirs, std::size_t rows, std::size_t cols,
                         std::size_t side) {
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
          for (std::size_t c = 0; c < w.cols; ++c)
            out[r * w.cols + c] = dirs[(w.row0 + r) * cols + w.col0 + c];
        read_codes += out.size();
        return out;
      },
      [&](std::size_t t, const NetworkTile& tile) {
        const terrain::RasterWindow w = tiles.window(t);
        for (std::size_t r = 0; r < w.rows; ++r)
          for (std::size_t c = 0; c < w.cols; ++c) {
            const std::size_t i = (w.row0 + r) * cols + w.col0 + c, q = r * w.cols + c;
            ASSERT_EQ(tile.dirs[q], dirs[i]);
            acc[i] = tile.accumulated[q], basin[i] = tile.basin[q], order[i] = tile.order[q],
            cut[i] = tile.cut[q];
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
    const bool same = acc[i] == net.accumulated[i] && basin[i] == net.basin[i] &&
                      order[i] == net.order[i] &&
                      cut[i] == (dirs[i] < 8 && net.downstream[i] == kNone);
    if (!same && differ++ < 3)
      ADD_FAILURE() << "point " << i << ": accumulated " << acc[i] << " vs " << net.accumulated[i]
                    << ", basin " << basin[i] << " vs " << net.basin[i] << ", order "
                    << int(order[i]) << " vs " << int(net.order[i]);
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_LE(read_codes, 2 * (rows + 2 * tiles.tile_rows()) *
                            (cols + 2 * tiles.tile_cols()));  // two passes, halos
}

D8Codes resolved_directions(const terrain::Grid& dem) {
  D8Codes dirs = d8_directions(dem);
  resolve_flats(dem, dirs);
  return dirs;
}

TEST(TiledNetwork, RealDemsEqualTheSingleGridNetwork) {
  for (const char* name :
       {"med_01_01_10m.tif", "msh_2007_utm10n_10m.tif", "logan_utm12n_100m.tif"}) {
    SCOPED_TRACE(name);
    terrain::Grid dem = terrain::read_dem(terrain::test::data(name));
    const D8Codes plain = resolved_directions(dem);
    for (const std::size_t side :
         {std::size_t(64), std::size_t(97), std::size_t(1), std::size_t(4096)})
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
  EXPECT_GE(pit % n, 40u);                     // the pit is at the east end
  EXPECT_GT(net.accumulated[pit], n * n / 3);  // and drains a large share of the grid
  EXPECT_GE(int(net.order[pit]), 3);
  for (const std::size_t side : {std::size_t(8), std::size_t(11), std::size_t(16)})
    expect_same_network(dirs, n, n, side);
}

}  // namespace
}  // namespace drainage
