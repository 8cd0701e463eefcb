// Depression breaching (Lindsay 2016; fill.hpp breach_depressions).
#include <gtest/gtest.h>

#include <cmath>

#include "drainage/d8.hpp"
#include "drainage/dv_file.hpp"
#include "drainage/fill.hpp"
#include "drainage/pipeline.hpp"
#include "drainage_test_support.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

using test::grid_of;

// The pit of PriorityFlood.FillsAPitToItsSpillLevel (2, 3 and 4 inside a rim of 9 whose
// lowest point is the edge cell 6 below them).
terrain::Grid small_pit() {
  return grid_of(4, 4, {9, 9, 9, 9, 9, 2, 3, 9, 9, 4, 9, 9, 9, 6, 9, 9});
}

// Deep enough: the path by which the flood came in (the 4, then the edge cell 6) is cut to
// below the pit's floor 2; the pit itself is left as it was and nothing is raised.
TEST(Breach, CutsThroughTheRimInsteadOfFilling) {
  terrain::Grid g = small_pit();
  const BreachStats s = breach_depressions(g, 10.0);
  EXPECT_EQ(s.carved, 2u);
  EXPECT_EQ(s.raised, 0u);
  EXPECT_EQ(g.at(1, 1), 2.0f);
  EXPECT_EQ(g.at(1, 2), 3.0f);
  EXPECT_LT(g.at(2, 1), 2.0f);
  EXPECT_LT(g.at(3, 1), g.at(2, 1));
  EXPECT_GT(g.at(3, 1), 1.999f);  // the path leaves the grid: a few float steps below the floor
  EXPECT_NEAR(s.max_carve, 4.0, 1e-3);
  for (std::size_t i : {0u, 3u, 7u, 10u, 15u}) EXPECT_EQ(g.z[i], small_pit().z[i]);
}

// Too shallow a cut allowed: the rim is cut by 2 (to just below 4, the first cell inside)
// and the rest of the pit fills to that level.
TEST(Breach, CutsAtMostMaxDepthAndFillsTheRest) {
  terrain::Grid g = small_pit();
  const BreachStats s = breach_depressions(g, 2.5);
  EXPECT_EQ(s.carved, 1u);
  EXPECT_EQ(s.raised, 2u);
  EXPECT_LT(g.at(3, 1), 4.0f);
  EXPECT_GT(g.at(3, 1), 3.999f);
  EXPECT_EQ(g.at(2, 1), 4.0f);
  EXPECT_EQ(g.at(1, 1), 4.0f);
  EXPECT_EQ(g.at(1, 2), 4.0f);
  EXPECT_LE(s.max_carve, 2.5);
}

// A V-shaped valley draining west with a dam across it, like a river crossing a bump of
// a resampled surface: the cut is on the valley axis only, through the dam, and the axis
// then falls steadily from the pool to below the dam.
TEST(Breach, ValleyWithADamIsCutOnItsAxis) {
  const std::size_t n = 21, axis = 10;
  terrain::Grid g = test::analytic(
      n, 10.0, [](double x, double y) { return 100.0 + 0.5 * x + 0.3 * std::abs(y); });
  const terrain::Grid dam_free = g;
  for (std::size_t r = 0; r < n; ++r) g.at(r, 8) += 8.0f;  // the dam: column 8, 8 m high
  const terrain::Grid before = g;
  const BreachStats s = breach_depressions(g, 20.0);
  EXPECT_EQ(s.raised, 0u);
  EXPECT_EQ(s.carved, 1u);  // the dam on the axis (the pool is the one cell above it)
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < n; ++c)
      if (g.at(r, c) != before.at(r, c)) {
        EXPECT_EQ(r, axis) << "cut off the axis at column " << c;
      }
  for (std::size_t c = 1; c < n; ++c)
    EXPECT_LT(g.at(axis, c - 1), g.at(axis, c)) << "axis rises at column " << c;
  // A uniform fall across the cut: the dam is lowered to halfway between the pool's floor
  // (column 9) and the valley floor below it (column 7), which are as they were.
  EXPECT_NEAR(g.at(axis, 8), 0.5 * (double(g.at(axis, 9)) + double(g.at(axis, 7))), 1e-3);
  EXPECT_EQ(g.at(axis, 7), dam_free.at(axis, 7));
  EXPECT_EQ(g.at(axis, 9), dam_free.at(axis, 9));
  // The pool drains along the axis: D8 from the east edge runs straight west.
  const D8Codes d = d8_directions(g);
  for (std::size_t c = 1; c + 1 < n; ++c)
    EXPECT_STREQ(kName[d[axis * n + c]], "W") << "column " << c;
}

// With no cut allowed, breaching is filling: the same elevations as Priority-Flood on a
// real DEM (which MatchesTaudemPitremove checks against TauDEM).
TEST(Breach, ZeroDepthEqualsPriorityFloodFill) {
  terrain::Grid breached = terrain::read_dem(terrain::test::data("med_01_01_10m.tif"));
  terrain::Grid filled = breached;
  const std::size_t raised = priority_flood_fill(filled);
  const BreachStats s = breach_depressions(breached, 0.0);
  EXPECT_EQ(s.carved, 0u);
  EXPECT_EQ(s.raised, raised);
  for (std::size_t i = 0; i < filled.size(); ++i)
    if (filled.valid(i)) {
      ASSERT_EQ(breached.z[i], filled.z[i]) << i;
    }
}

// On a real DEM with a 5 m limit: every sample drains to the edge (no pit, no undrainable
// flat), no cut is deeper than the limit, the surface stays at or below the filled one, and
// fewer samples are raised than by filling.
TEST(Breach, RealDemDrainsEverywhereChangingLessThanFilling) {
  const terrain::Grid dem = terrain::read_dem(terrain::test::data("logan_utm12n_100m.tif"));
  terrain::Grid breached = dem, filled = dem;
  const BreachStats s = breach_depressions(breached, 5.0);
  const std::size_t raised = priority_flood_fill(filled);
  EXPECT_GT(s.carved, 0u);
  EXPECT_LE(s.max_carve, 5.0);
  EXPECT_LT(s.raised, raised);
  for (std::size_t i = 0; i < dem.size(); ++i) {
    if (!dem.valid(i)) continue;
    ASSERT_GE(double(breached.z[i]), double(dem.z[i]) - 5.0) << i;
    ASSERT_LE(breached.z[i], filled.z[i]) << i;  // never above the filled surface
  }
  const DrainageResult r =
      compute_drainage(dem, {.fill = false, .resolve_flats = true, .breach_depth = 5.0});
  test::check_network_properties(r.net, r.dirs);
  EXPECT_EQ(r.flats.undrainable, 0u);
  EXPECT_EQ(r.carved, s.carved);
  EXPECT_EQ(r.filled, s.raised);
  EXPECT_TRUE(r.dv_flags & kDvBreached);
  EXPECT_FALSE(r.dv_flags & kDvFilled);
  for (std::uint32_t p : r.net.pits)
    EXPECT_EQ(r.dirs[p], kOutlet) << "pit inside the grid at " << p;
  EXPECT_THROW(compute_drainage(dem, {.fill = true, .resolve_flats = true, .breach_depth = 5.0}),
               terrain::Error);
}

}  // namespace
}  // namespace drainage
