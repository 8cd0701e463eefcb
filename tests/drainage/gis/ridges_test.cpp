// Ridge lines (drainage/ridges.hpp) on analytic surfaces whose crests are known: a tent
// whose two flanks drain to valleys along its long sides has one ridge, along its crest;
// a second, small tent on one flank parts only small basins and is left out at a larger
// minimum; the spur ends below a quarter of the relief are cut.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numeric>

#include "drainage/ridges.hpp"

namespace drainage {
namespace {

// The links of a z(x, y) grid (rows x cols, 10 m, row 0 north) by D8 steepest descent
// (downstream kNone at a pit or where the flow would leave the grid), accumulation by
// heights from the top.
terrain::DrainageLinks links_of(std::size_t rows, std::size_t cols,
                                const std::function<double(double, double)>& z) {
  terrain::DrainageLinks l;
  l.rows = rows, l.cols = cols, l.dx = l.dy = 10;
  const std::size_t n = rows * cols;
  for (std::size_t i = 0; i < n; ++i)
    l.z.push_back(float(z(double(i % cols) * 10, -double(i / cols) * 10)));
  l.valid.assign(n, 1);
  l.flow.assign(n, 1);
  l.downstream.assign(n, terrain::DrainageLinks::kNone);
  for (std::size_t i = 0; i < n; ++i) {
    const long r = long(i / cols), c = long(i % cols);
    double best = 0;
    for (long dr = -1; dr <= 1; ++dr)
      for (long dc = -1; dc <= 1; ++dc) {
        const long rr = r + dr, cc = c + dc;
        if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= long(rows) || cc >= long(cols))
          continue;
        const std::size_t j = std::size_t(rr) * cols + std::size_t(cc);
        const double drop = (double(l.z[i]) - double(l.z[j])) / std::hypot(double(dr), double(dc));
        if (drop > best) best = drop, l.downstream[i] = std::uint32_t(j);
      }
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return l.z[a] > l.z[b]; });
  l.accumulated.assign(n, 1);
  for (const std::size_t i : order)
    if (l.downstream[i] != terrain::DrainageLinks::kNone)
      l.accumulated[l.downstream[i]] += l.accumulated[i];
  return l;
}

// A tent 600 m across (crest at x = 300 m), its flanks falling 30 % to valleys along its
// long sides, the whole falling 2 % to the south, 1 km long.
double tent(double x, double y) { return 500 - 0.3 * std::abs(x - 300) + 0.02 * y; }

TEST(RidgeLines, ATentHasOneRidgeAlongItsCrest) {
  const terrain::DrainageLinks l = links_of(101, 61, tent);
  const std::vector<RidgeLine> ridges = ridge_lines(l, 1e4, 1e5);
  ASSERT_FALSE(ridges.empty());
  double length = 0;
  for (const RidgeLine& r : ridges) {
    EXPECT_GT(r.basin_area, 1e5);
    for (std::size_t k = 0; k < r.points.size(); ++k) {
      const Eigen::Vector3d& p = r.points[k];
      EXPECT_LE(std::abs(p.x() - 300), 10.0) << p.transpose();  // on the crest, within a cell
      EXPECT_NEAR(p.z(), tent(300, p.y()), 3.0 + 1e-3);  // the crest's height (its side's point)
      if (k > 0) length += (p - r.points[k - 1]).head<2>().norm();
    }
  }
  // Nearly the whole crest: 1 km less the cells at its ends.
  EXPECT_GT(length, 900.0);
  // The basins parted are the two flanks, about half the grid each: a larger minimum drops it.
  EXPECT_TRUE(ridge_lines(l, 1e4, 0.6 * 101 * 61 * 100).empty());
}

// A spur: a tent whose crest falls to the south into a valley that drains both flanks (a
// valley across the south end). The divide between the flanks descends along the crest to
// the confluence; its part lower than a quarter of its relief above the outlet is cut.
TEST(RidgeLines, TheSpurEndIsCut) {
  auto spur = [](double x, double y) {
    return 500 - 0.3 * std::abs(x - 300) + 0.4 * (y + 1000) * (y > -1000 ? 1 : 0);
  };
  const terrain::DrainageLinks l = links_of(111, 61, [&](double x, double y) {
    return y < -1000 ? 500 - 0.3 * 300 + 0.01 * x + 0.5 * (y + 1000) : spur(x, y);
  });
  const std::vector<RidgeLine> ridges = ridge_lines(l, 1e4, 1e4);
  ASSERT_FALSE(ridges.empty());
  // The crest's line (on x = 300 m) falls the whole relief to the confluence; what is kept
  // of each line lies within the upper three quarters of its relief.
  bool crest = false;
  for (const RidgeLine& r : ridges) {
    double lowest = 1e9, highest = -1e9;
    bool on_crest = true;
    for (const Eigen::Vector3d& p : r.points) {
      lowest = std::min(lowest, p.z()), highest = std::max(highest, p.z());
      on_crest = on_crest && std::abs(p.x() - 300) <= 10.0;
    }
    EXPECT_GE(lowest, highest - 0.75 * r.relief - 1e-6);
    if (on_crest && r.relief > 300) crest = true;
  }
  EXPECT_TRUE(crest);
}

}  // namespace
}  // namespace drainage
