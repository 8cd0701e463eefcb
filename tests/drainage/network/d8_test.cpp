// D8 directions: the code table, the worked examples of docs/algorithms.md 7, tie-breaking and
// the boundary rule.
#include <gtest/gtest.h>

#include "drainage/d8.hpp"
#include "drainage_test_support.hpp"
#include "terrain/error.hpp"
#include "terrain/utm.hpp"

namespace drainage {
namespace {

using test::grid_of;

TEST(D8Codes, TableIsLocked) {
  // Our code k: E, NE, N, NW, W, SW, S, SE; row 0 is north (N = row - 1).
  EXPECT_EQ(kDRow[0], 0);
  EXPECT_EQ(kDCol[0], 1);  // E
  EXPECT_EQ(kDRow[2], -1);
  EXPECT_EQ(kDCol[2], 0);  // N
  EXPECT_EQ(kDRow[7], 1);
  EXPECT_EQ(kDCol[7], 1);  // SE
  // TauDEM 1..8 from E counter-clockwise; ESRI powers of two clockwise from E.
  const int esri[8] = {1, 128, 64, 32, 16, 8, 4, 2};
  for (std::uint8_t k = 0; k < 8; ++k) {
    EXPECT_EQ(to_foreign_code(k, D8Encoding::Taudem), k + 1);
    EXPECT_EQ(to_foreign_code(k, D8Encoding::Esri), esri[k]);
    EXPECT_EQ(from_foreign_code(k + 1, D8Encoding::Taudem, false), k);
    EXPECT_EQ(from_foreign_code(esri[k], D8Encoding::Esri, false), k);
  }
  EXPECT_EQ(from_foreign_code(0, D8Encoding::Taudem, false), kNoFlow);
  EXPECT_EQ(from_foreign_code(-32768, D8Encoding::Taudem, true), kNodata);
  EXPECT_THROW(from_foreign_code(9, D8Encoding::Taudem, false), terrain::Error);
  EXPECT_THROW(from_foreign_code(3, D8Encoding::Esri, false), terrain::Error);
  EXPECT_EQ(downstream(5, 2, 4), 1u);  // N of (1,1) in a 4-wide grid is (0,1)
}

// docs/algorithms.md 7.1: centre 10; N 8, NE 7.5, E 9.2, others higher.
TEST(D8Directions, SteepestSlopeDependsOnCellShape) {
  auto centre_code = [](double dx, double dy) {
    terrain::Grid g = grid_of(3, 3, {20, 8, 7.5f, 20, 10, 9.2f, 20, 20, 20});
    g.geo.dx = dx;
    g.geo.dy = dy;
    return d8_directions(g)[4];
  };
  EXPECT_STREQ(kName[centre_code(10, 10)], "N");
  EXPECT_STREQ(kName[centre_code(30, 10)], "N");
  EXPECT_STREQ(kName[centre_code(10, 30)], "E");
}

// A geographic grid at 60 N: a degree of longitude there is half a degree of latitude in
// metres (55.8 km vs 111.4 km on WGS84), and D8 uses those metres, as TauDEM does.
TEST(D8Directions, GeographicGridsUseMetricCellSizesPerRow) {
  terrain::Georef geo;
  geo.crs_kind = terrain::CrsKind::Geographic;  // no WKT: WGS84
  geo.dx = geo.dy = 1.0 / 3600.0;               // 1 arc-second
  geo.x0 = 10.0;
  geo.y0 = 60.0 + 1.5 / 3600.0;  // row 1 at 60 N
  const auto sizes = terrain::metric_cell_sizes(geo, 1, 1);
  EXPECT_NEAR(sizes[0].dx * 3600.0, 55'800.0, 20.0);   // 1 degree of longitude at 60 N
  EXPECT_NEAR(sizes[0].dy * 3600.0, 111'412.0, 20.0);  // 1 degree of latitude at 60 N
  // Drops of 1 m per cell eastwards and 1.2 m per cell northwards: in metres east is the
  // steepest (2.0 vs 1.2 vs 1.97 per N-S cell length); with cells taken as square it
  // would be NE (1.56 vs 1.0 vs 1.2).
  terrain::Grid g(3, 3, geo);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      g.at(std::size_t(r), std::size_t(c)) = float(100.0 - 1.0 * c + 1.2 * r);
  EXPECT_STREQ(kName[d8_directions(g)[4]], "E");
  g.geo.crs_kind = terrain::CrsKind::Projected;  // the same numbers as a projected grid
  EXPECT_STREQ(kName[d8_directions(g)[4]], "NE");
}

// docs/algorithms.md 7.8 (dx = 30 m, dy = 20 m): interior cells.
TEST(D8Directions, WorkedExampleInteriorCells) {
  terrain::Grid g = grid_of(4, 4, {9, 8, 7, 6, 8, 6, 5, 5, 7, 5, 3, 4, 6, 4, 2, 1});
  g.geo.dx = 30;
  g.geo.dy = 20;
  const auto d = d8_directions(g);
  EXPECT_EQ(to_foreign_code(d[5], D8Encoding::Taudem), 8);   // (1,1) SE
  EXPECT_EQ(to_foreign_code(d[6], D8Encoding::Taudem), 7);   // (1,2) S
  EXPECT_EQ(to_foreign_code(d[9], D8Encoding::Taudem), 8);   // (2,1) SE
  EXPECT_EQ(to_foreign_code(d[10], D8Encoding::Taudem), 8);  // (2,2) SE
  EXPECT_EQ(to_foreign_code(d[5], D8Encoding::Esri), 2);
}

TEST(D8Directions, TiesGoToTheFirstCardinalOfENWS) {
  // Equal slopes: E over N, W over S, and among diagonals NE, NW, SW, SE in that order.
  EXPECT_STREQ(kName[d8_directions(grid_of(3, 3, {9, 4, 9, 9, 5, 4, 9, 9, 9}))[4]], "E");
  EXPECT_STREQ(kName[d8_directions(grid_of(3, 3, {9, 9, 9, 4, 5, 9, 9, 4, 9}))[4]], "W");
  EXPECT_STREQ(kName[d8_directions(grid_of(3, 3, {9, 9, 3, 9, 5, 9, 3, 9, 9}))[4]], "NE");
  EXPECT_STREQ(kName[d8_directions(grid_of(3, 3, {9, 9, 9, 9, 5, 9, 3, 9, 3}))[4]], "SW");
  // A pit and a flat interior cell have no flow.
  EXPECT_EQ(d8_directions(grid_of(3, 3, {9, 9, 9, 9, 1, 9, 9, 9, 9}))[4], kNoFlow);
  EXPECT_EQ(d8_directions(grid_of(3, 3, {5, 5, 5, 5, 5, 5, 5, 5, 5}))[4], kNoFlow);
}

TEST(D8Directions, BoundaryRule) {
  // A plane falling to the south: interior and side columns flow S, the bottom row leaves
  // the grid (its extrapolated southern neighbour is lower).
  const terrain::Grid plane =
      test::analytic(6, 10.0, [](double, double y) { return 100.0 + 0.5 * y; });
  const auto d = d8_directions(plane);
  for (std::size_t r = 0; r < 6; ++r)
    for (std::size_t c = 0; c < 6; ++c)
      EXPECT_EQ(d[r * 6 + c], r == 5 ? kOutlet : 6) << r << "," << c;
  // No-data counts as outside: the cell north of a no-data hole in a south-falling
  // plane is an outlet.
  terrain::Grid holed = plane;
  holed.at(3, 2) = std::numeric_limits<float>::quiet_NaN();
  const auto h = d8_directions(holed);
  EXPECT_EQ(h[3 * 6 + 2], kNodata);
  EXPECT_EQ(h[2 * 6 + 2], kOutlet);
}

}  // namespace
}  // namespace drainage
