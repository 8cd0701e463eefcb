#pragma once
// Helpers for the drainage tests: small grids from literals and analytic surfaces, and
// the invariants every drainage network must satisfy.
#include <gtest/gtest.h>

#include <functional>
#include <initializer_list>

#include "drainage/d8.hpp"
#include "drainage/network.hpp"
#include "terrain/grid.hpp"

namespace drainage::test {

// A rows x cols grid of square cells of `h` metres from row-major values (row 0 north).
inline terrain::Grid grid_of(std::size_t rows, std::size_t cols,
                             std::initializer_list<float> values, double h = 1.0) {
  terrain::Georef geo;
  geo.dx = geo.dy = h;
  terrain::Grid g(rows, cols, geo);
  std::copy(values.begin(), values.end(), g.z.begin());
  return g;
}

// z = f(x, y) sampled at cell centres, x east and y north, with (0, 0) at the centre sample.
inline terrain::Grid analytic(std::size_t n, double h,
                              const std::function<double(double, double)>& f) {
  terrain::Georef geo;
  geo.dx = geo.dy = h;
  geo.x0 = -double(n) * h / 2;
  geo.y0 = double(n) * h / 2;
  terrain::Grid g(n, n, geo);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < n; ++c)
      g.at(r, c) = float(f(geo.x_of_col(double(c)), geo.y_of_row(double(r))));
  return g;
}

// Checks the invariants of a network (issue 3): pit flows sum to the point count, basins
// partition the points and each is the basin of the pit its flow reaches, normalized flow
// in (0, 1] and 1 at pits, branches are chains of one order linked downstream that cover
// every point once, and classes agree with in/out degrees.
inline void check_network_properties(const Network& net, const D8Codes& dirs) {
  const std::size_t n = dirs.size();
  std::size_t points = 0;
  for (std::size_t i = 0; i < n; ++i) points += dirs[i] != kNodata;
  ASSERT_EQ(net.points, points);
  std::uint64_t pit_sum = 0;
  for (std::uint32_t p : net.pits) pit_sum += net.accumulated[p];
  EXPECT_EQ(pit_sum, points) << "pit flows must sum to the point count";

  std::vector<std::uint32_t> indeg(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (net.downstream[i] != kNone) ++indeg[net.downstream[i]];
  std::size_t class_count[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    if (dirs[i] == kNodata) {
      ASSERT_EQ(net.basin[i], kNone);
      continue;
    }
    const std::uint32_t b = net.basin[i];
    ASSERT_LT(b, net.pits.size());
    const std::uint32_t d = net.downstream[i];
    if (d == kNone) {
      ASSERT_EQ(net.pits[b], i) << "a pit heads its own basin";
      ASSERT_EQ(net.normalized[i], 1.0f);
    } else {
      ASSERT_EQ(net.basin[d], b) << "flow stays in its basin";
      ASSERT_GE(net.order[d], net.order[i]) << "Strahler order never falls downstream";
      ASSERT_GT(net.accumulated[d], net.accumulated[i]);
    }
    ASSERT_GT(net.normalized[i], 0.0f);
    ASSERT_LE(net.normalized[i], 1.0f);
    // Classes from degrees.
    const auto cls = PointClass(net.point_class[i]);
    const PointClass expected = d == kNone      ? PointClass::Pit
                                : indeg[i] == 0 ? PointClass::Ridge
                                : indeg[i] == 1 ? PointClass::Channel
                                                : PointClass::Junction;
    ASSERT_EQ(cls, expected) << "point " << i;
    ++class_count[int(cls)];
  }
  EXPECT_EQ(class_count[int(PointClass::Pit)], net.pits.size());

  std::vector<std::uint8_t> seen(n, 0);
  std::size_t covered = 0;
  for (const Branch& b : net.branches) {
    ASSERT_GT(b.count, 0u);
    for (std::uint32_t k = 0; k < b.count; ++k) {
      const std::uint32_t v = net.branch_vertices[b.first + k];
      ASSERT_EQ(seen[v], 0) << "vertex in two branches";
      seen[v] = 1;
      ASSERT_EQ(net.order[v], b.order);
      if (k + 1 < b.count) {
        ASSERT_EQ(net.downstream[v], net.branch_vertices[b.first + k + 1]) << "D8-linked chain";
      }
    }
    covered += b.count;
    const std::uint32_t last = net.branch_vertices[b.first + b.count - 1];
    ASSERT_EQ(b.drains_into, net.downstream[last]);
    if (b.drains_into != kNone) {
      ASSERT_GT(net.order[b.drains_into], b.order);
    }
  }
  EXPECT_EQ(covered, points);
}

}  // namespace drainage::test
