// Photic extremum lines: the CPU reference on an analytic surface with a derived answer,
// the threshold, and the GPU passes against the CPU reference.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/pel.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector3d;

// A radially symmetric Gaussian bump z = H exp(-r^2 / 2 sigma^2) on a grid h metres apart,
// centred, with its Voronoi weights.
terrain::GridMesh bump_mesh(std::size_t n, double h, double H, double sigma) {
  const double c0 = double(n - 1) / 2 * h;  // the centre is at local (c0, -c0)
  terrain::GridMesh m = terrain::test::function_mesh(n, n, h, [=](double x, double y) {
    return H * std::exp(-((x - c0) * (x - c0) + (y + c0) * (y + c0)) / (2 * sigma * sigma));
  });
  m.voronoi = terrain::voronoi_weights(m);
  return m;
}

// Lit from straight above, f(r) = n_z = 1 / sqrt(1 + h'(r)^2) with h' = -(H r / sigma^2)
// exp(-r^2 / 2 sigma^2). The gradient of f on the surface is radial, of length
// m = |df/ds| = |f'(r)| / sqrt(1 + h'^2) = |f'(r)| f(r) (s: arc length along the profile);
// PELs are the maxima of m along that direction: dm/dr = 0 with m'' < 0, one circle inside
// r = sigma and one outside (H = 60, sigma = 80: r = 33.03 and 126.08).
std::vector<double> derived_pel_radii(double H, double sigma) {
  auto f = [&](double r) {
    const double hp = H * r / (sigma * sigma) * std::exp(-r * r / (2 * sigma * sigma));
    return 1 / std::sqrt(1 + hp * hp);
  };
  auto m = [&](double r) { return std::abs(f(r + 1e-3) - f(r - 1e-3)) / 2e-3 * f(r); };
  std::vector<double> radii;
  const double dr = 0.01;
  for (double r = dr; r < 4 * sigma; r += dr)
    if (m(r) > m(r - dr) && m(r) >= m(r + dr)) radii.push_back(r);
  return radii;
}

TEST(Pel, BumpLitFromAboveGivesCirclesAtTheDerivedRadii) {
  const double h = 2, H = 60, sigma = 80;
  const terrain::GridMesh m = bump_mesh(201, h, H, sigma);
  const auto radii = derived_pel_radii(H, sigma);
  ASSERT_EQ(radii.size(), 2u);
  EXPECT_LT(radii[0], sigma);
  EXPECT_GT(radii[1], sigma);
  const auto fields = renderer::pel_fields(m, Vector3d(0, 0, 1));
  const auto pels = renderer::extract_pels(m, fields, 0.1);
  ASSERT_GT(pels.size(), 200u);
  const double half_edge = 0.5 * (h + h + h * std::sqrt(2.0)) / 3;
  const double c0 = 100 * h;
  std::size_t near[2] = {0, 0}, off = 0;
  for (const auto& p : pels.points) {
    const double r = std::hypot(p.x() - c0, p.y() + c0);
    const int k = std::abs(r - radii[0]) < std::abs(r - radii[1]) ? 0 : 1;
    if (std::abs(r - radii[k]) <= half_edge) ++near[k];
    else ++off;
  }
  EXPECT_EQ(off, 0u) << "radii " << radii[0] << " " << radii[1];
  EXPECT_GT(near[0], 100u);  // both circles are found
  EXPECT_GT(near[1], 100u);
}

TEST(Pel, LargerThresholdNeverAddsSegments) {
  const terrain::GridMesh m = bump_mesh(101, 4, 60, 80);
  const auto fields = renderer::pel_fields(m, Vector3d(0.3, 0.2, 0.9).normalized());
  std::size_t previous = std::numeric_limits<std::size_t>::max();
  for (int i = 0; i <= 20; ++i) {
    const double tau = i / 20.0;
    const auto pels = renderer::extract_pels(m, fields, tau);
    EXPECT_LE(pels.size(), previous) << tau;
    previous = pels.size();
  }
  EXPECT_EQ(previous, 0u);  // tau = 1: nothing exceeds the maximum
}

}  // namespace
