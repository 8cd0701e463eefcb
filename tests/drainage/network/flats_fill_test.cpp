// Flat resolution (Barnes et al. 2014b) and Priority-Flood filling (Barnes et al. 2014).
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <random>
#include <set>
#include <utility>

#include "drainage/fill.hpp"
#include "drainage/flats.hpp"
#include "drainage/pipeline.hpp"
#include "drainage_test_support.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

using test::grid_of;

// docs/algorithms.md 8.7 (the filled DEM): the flat drains towards its low edge and converges
// on the centre column.
TEST(ResolveFlats, WorkedExample) {
  const terrain::Grid g =
      grid_of(5, 5, {9, 9, 9, 9, 9, 9, 5, 5, 5, 9, 9, 5, 5, 5, 9, 9, 5, 5, 5, 9, 9, 9, 4, 9, 9});
  D8Codes d = d8_directions(g);
  for (std::size_t r = 1; r <= 2; ++r)
    for (std::size_t c = 1; c <= 3; ++c) ASSERT_EQ(d[r * 5 + c], kNoFlow);
  const FlatStats s = resolve_flats(g, d);
  EXPECT_EQ(s.flats, 1u);
  EXPECT_EQ(s.undrainable, 0u);
  EXPECT_EQ(s.cells_resolved, 6u);
  const char* expected[2][3] = {{"SE", "S", "SW"}, {"S", "S", "S"}};
  for (std::size_t r = 1; r <= 2; ++r)
    for (std::size_t c = 1; c <= 3; ++c)
      EXPECT_STREQ(kName[d[r * 5 + c]], expected[r - 1][c - 1]) << r << "," << c;
}

// A plateau inside a higher rim with one lower outlet cell on the southern edge drains
// entirely to it; with --keep-flats its interior cells stay one-point pits.
TEST(ResolveFlats, PlateauDrainsToItsOneOutlet) {
  const std::size_t n = 9;
  terrain::Grid g = test::analytic(n, 10.0, [](double, double) { return 50.0; });
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < n; ++c)
      if (r == 0 || c == 0 || r == n - 1 || c == n - 1) g.at(r, c) = 60.0f;
  g.at(n - 1, 4) = 40.0f;  // the outlet
  const DrainageResult resolved = compute_drainage(g, {});
  test::check_network_properties(resolved.net, resolved.dirs);
  const std::uint32_t outlet = std::uint32_t((n - 1) * n + 4);
  ASSERT_EQ(resolved.dirs[outlet], kOutlet);
  EXPECT_EQ(resolved.net.accumulated[outlet], n * n);  // the rim drains inwards or into the outlet
  EXPECT_EQ(resolved.net.pits.size(), 1u);
  std::size_t interior_pits = 0;
  for (std::uint32_t p : resolved.net.pits) interior_pits += g.at(p / n, p % n) == 50.0f;
  EXPECT_EQ(interior_pits, 0u);

  const DrainageResult literal =
      compute_drainage(g, {.fill = false, .resolve_flats = false, .breach_depth = {}});
  test::check_network_properties(literal.net, literal.dirs);
  interior_pits = 0;
  for (std::uint32_t p : literal.net.pits) interior_pits += g.at(p / n, p % n) == 50.0f;
  EXPECT_GT(interior_pits, (n - 2) * (n - 2) / 2);  // most plateau cells are their own pit
}

// A flat-bottomed closed depression becomes one basin with one pit, not one pit per cell.
TEST(ResolveFlats, UndrainableFlatHasOnePit) {
  terrain::Grid g =
      test::analytic(11, 1.0, [](double x, double y) { return std::max(9.0, x * x + y * y); });
  const DrainageResult r = compute_drainage(g, {});
  test::check_network_properties(r.net, r.dirs);
  EXPECT_EQ(r.flats.undrainable, 1u);
  std::size_t pits_on_floor = 0;
  for (std::uint32_t p : r.net.pits) pits_on_floor += g.z[p] == 9.0f;
  EXPECT_EQ(pits_on_floor, 1u);
  EXPECT_EQ(r.net.pits.size(), 1u);  // a bowl: everything drains to the floor
}

TEST(PriorityFlood, FillsAPitToItsSpillLevel) {
  terrain::Grid g = grid_of(4, 4, {9, 9, 9, 9, 9, 2, 3, 9, 9, 4, 9, 9, 9, 6, 9, 9});
  const std::size_t raised = priority_flood_fill(g);
  EXPECT_EQ(raised, 3u);  // 2, 3 and 4 rise to the spill level 6 (the edge cell)
  EXPECT_EQ(g.at(1, 1), 6.0f);
  EXPECT_EQ(g.at(1, 2), 6.0f);
  EXPECT_EQ(g.at(2, 1), 6.0f);
  EXPECT_EQ(g.at(3, 1), 6.0f);
  EXPECT_EQ(g.at(0, 0), 9.0f);
}

// FloodQueue (the radix heap) takes cells in the order of a binary heap on (elevation,
// index), as a flood pushes them: each above the one last taken. Elevations from a small set
// (ties broken by index), negative ones, -0 beside +0 (equal elevations) and a denormal.
TEST(PriorityFlood, QueueTakesCellsInElevationThenIndexOrder) {
  const float levels[] = {-1000.5f, -2.0f, -0.0f, 0.0f, 1e-42f, 1.0f, 1.0f, 3.5f, 1.0e6f};
  std::mt19937 rng(7);
  FloodQueue queue;
  std::set<std::pair<float, std::uint32_t>> reference;  // -0 == +0: ties by index
  std::uint32_t next = 0;
  const auto push = [&](float z) {
    const std::uint32_t i = (next++ * 2654435761u) % 1000003u;  // indices out of order
    queue.push(z, i);
    reference.insert({z, i});
  };
  for (int k = 0; k < 40; ++k) push(levels[rng() % std::size(levels)]);
  std::size_t taken = 0;
  while (!reference.empty()) {
    ASSERT_FALSE(queue.empty());
    const auto [z, i] = *reference.begin();
    reference.erase(reference.begin());
    ASSERT_EQ(queue.pop(), i) << "take " << taken;
    ++taken;
    for (unsigned k = rng() % 4; k > 0 && next < 5000; --k) {  // pushes above the one taken
      const float above[] = {std::nextafter(z, INFINITY), z + 1.0f, z + 100.0f,
                             2.0f * std::abs(z) + 1.0f};
      push(std::max(above[rng() % 4], std::nextafter(z, INFINITY)));
    }
  }
  EXPECT_TRUE(queue.empty());
  EXPECT_GT(taken, 1000u);
}

// --fill on a real DEM against TauDEM's pitremove: within 1 mm on >= 99.99 % of cells.
TEST(PriorityFlood, MatchesTaudemPitremove) {
  terrain::Grid dem = terrain::read_dem(terrain::test::data("med_01_01_10m.tif"));
  const terrain::Grid ref =
      terrain::read_dem(terrain::test::data("med_01_01_10m_taudem_pitremove.tif"));
  ASSERT_EQ(dem.size(), ref.size());
  const std::size_t raised = priority_flood_fill(dem);
  EXPECT_GT(raised, 0u);  // the DEM has real pits
  std::size_t compared = 0, close = 0;
  for (std::size_t i = 0; i < dem.size(); ++i) {
    if (!ref.valid(i) || !dem.valid(i)) continue;
    ++compared;
    close += std::abs(double(dem.z[i]) - double(ref.z[i])) <= 1e-3;
  }
  ASSERT_GT(compared, dem.size() / 2);
  EXPECT_GE(double(close), 0.9999 * double(compared))
      << close << " of " << compared << " within 1 mm";
  RecordProperty("cells_within_1mm", std::to_string(close) + "/" + std::to_string(compared));
}

// A geographic DEM (the bundled Eno crop, NAD83 lat/lon) fills like any grid: filling
// compares elevations only, so the result is the one of the same array on a projected
// grid, and TauDEM's pitremove gives that array too (MatchesTaudemPitremove above; TauDEM's
// geographic reference enogeofel.tif is not in ../shared/data). Every filled cell then
// has no strict pit left: every interior cell has a neighbour at or below it.
TEST(PriorityFlood, GeographicDemFillsLikeTheSameArrayProjected) {
  terrain::Grid geo = terrain::read_dem(terrain::test::data("eno_nad83_geographic_crop.tif"));
  ASSERT_EQ(geo.geo.crs_kind, terrain::CrsKind::Geographic);
  terrain::Grid proj = geo;
  proj.geo.crs_kind = terrain::CrsKind::Projected;
  proj.geo.crs_wkt.clear();
  proj.geo.dx = proj.geo.dy = 10.0;
  const std::size_t raised = priority_flood_fill(geo);
  EXPECT_GT(raised, 0u);
  EXPECT_EQ(priority_flood_fill(proj), raised);
  for (std::size_t i = 0; i < geo.size(); ++i) ASSERT_EQ(geo.z[i], proj.z[i]) << i;
  const long R = long(geo.rows), C = long(geo.cols);
  for (long r = 1; r + 1 < R; ++r)
    for (long c = 1; c + 1 < C; ++c) {
      float low = INFINITY;  // lowest neighbour: a strict pit would be below all eight
      for (int k = 0; k < 8; ++k)
        low = std::min(low, geo.at(std::size_t(r + kDRow[k]), std::size_t(c + kDCol[k])));
      ASSERT_LE(low, geo.at(std::size_t(r), std::size_t(c)))
          << "pit left at row " << r << ", column " << c;
    }
}

}  // namespace
}  // namespace drainage
