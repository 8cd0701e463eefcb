// Steps 2-6 of build-drainage on analytic surfaces: a bowl drains to its centre, filling
// removes every pit but the outlets, and given directions give the same network.
#include <gtest/gtest.h>

#include <cmath>

#include "drainage/dv_file.hpp"
#include "drainage/pipeline.hpp"
#include "drainage_test_support.hpp"

namespace drainage {
namespace {

using test::analytic;
using test::check_network_properties;

TEST(Pipeline, BowlDrainsToItsCentre) {
  const std::size_t n = 41;
  const terrain::Grid bowl = analytic(n, 10.0, [](double x, double y) { return std::hypot(x, y); });
  const DrainageResult r = compute_drainage(bowl, {});
  check_network_properties(r.net, r.dirs);
  ASSERT_EQ(r.net.pits.size(), 1u);
  EXPECT_EQ(r.net.pits[0], (n / 2) * n + n / 2);  // the centre sample
  EXPECT_EQ(r.net.accumulated[r.net.pits[0]], n * n);
  EXPECT_EQ(r.filled, 0u);
  EXPECT_TRUE(r.dv_flags & kDvHasElevations);
  EXPECT_FALSE(r.dv_flags & kDvFilled);
}

TEST(Pipeline, FillingLeavesOnlyOutlets) {
  const std::size_t n = 31;
  // A tilted plane with a bowl cut into it: without filling the bowl is a basin.
  const terrain::Grid g = analytic(
      n, 10.0, [](double x, double y) { return 0.1 * x + std::min(0.0, std::hypot(x, y) - 60.0); });
  const DrainageResult raw = compute_drainage(g, {false, true, {}});
  const DrainageResult filled = compute_drainage(g, {true, true, {}});
  check_network_properties(raw.net, raw.dirs);
  check_network_properties(filled.net, filled.dirs);
  EXPECT_GT(filled.filled, 0u);
  EXPECT_TRUE(filled.dv_flags & kDvFilled);
  EXPECT_LT(filled.net.pits.size(), raw.net.pits.size());
  for (std::uint32_t pit : filled.net.pits)  // every remaining pit is an outlet on the boundary
    EXPECT_TRUE(pit / n == 0 || pit / n == n - 1 || pit % n == 0 || pit % n == n - 1) << pit;
  for (std::size_t i = 0; i < g.size(); ++i) EXPECT_GE(filled.surface.z[i], g.z[i]);
}

TEST(Pipeline, GivenDirectionsGiveTheSameNetwork) {
  const terrain::Grid g = analytic(
      25, 5.0, [](double x, double y) { return std::sin(x / 20) * std::cos(y / 15) * 10; });
  const DrainageResult a = compute_drainage(g, {});
  const DrainageResult b = drainage_from_directions(g, a.dirs);
  EXPECT_EQ(b.net.accumulated, a.net.accumulated);
  EXPECT_EQ(b.net.basin, a.net.basin);
  EXPECT_EQ(b.net.order, a.net.order);
  EXPECT_EQ(b.net.point_class, a.net.point_class);
}

}  // namespace
}  // namespace drainage
