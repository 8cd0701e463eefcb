// Bilateral normal filtering (docs/algorithms.md 6) on planes and a sharp ridge with noise.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

#include "terrain/denoise.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

double angle_deg(const Vector3f& a, const Vector3d& b) {
  return std::acos(std::clamp(a.cast<double>().dot(b.normalized()), -1.0, 1.0)) * 180 /
         std::numbers::pi;
}

// z = f(x, y) + Gaussian noise (seeded) on n x n samples 1 m apart.
GridMesh noisy_mesh(std::size_t n, const std::function<double(double, double)>& f, double noise,
                    unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise);
  return test::function_mesh(n, n, 1.0, [&](double x, double y) { return f(x, y) + gauss(rng); });
}

// One round of the filter equals a brute-force evaluation of docs/algorithms.md 6.1 (every
// other face sharing a vertex, area x spatial x range weights), on a random mesh.
TEST(Denoise, OneRoundMatchesBruteForce) {
  const GridMesh m = noisy_mesh(
      7, [](double x, double y) { return 0.5 * x - 0.2 * y; }, 0.3, 99);
  const auto n0 = face_normals(m);
  DenoiseOptions o;
  o.iterations = 1;
  o.sigma_s = 1.3;
  double used = 0;
  const auto n1 = bilateral_filter_normals(m, n0, o, used);
  EXPECT_EQ(used, 1.3);
  auto centroid = [&](std::size_t f) {
    const auto t = m.topo.face(f);
    return Vector3d((m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]).cast<double>() / 3);
  };
  auto area = [&](std::size_t f) {
    const auto t = m.topo.face(f);
    return 0.5 * (m.positions[t[1]] - m.positions[t[0]])
                     .cast<double>()
                     .cross((m.positions[t[2]] - m.positions[t[0]]).cast<double>())
                     .norm();
  };
  for (std::size_t i = 0; i < m.n_faces(); ++i) {
    Vector3d sum = Vector3d::Zero();
    const auto ti = m.topo.face(i);
    for (std::size_t j = 0; j < m.n_faces(); ++j) {
      if (j == i) continue;
      const auto tj = m.topo.face(j);
      bool shares = false;
      for (auto a : ti)
        for (auto b : tj) shares = shares || a == b;
      if (!shares) continue;
      const double dc = (centroid(i) - centroid(j)).norm(),
                   dn = (n0[i] - n0[j]).cast<double>().norm();
      sum += area(j) * std::exp(-dc * dc / (2 * 1.3 * 1.3)) *
             std::exp(-dn * dn / (2 * 0.35 * 0.35)) * n0[j].cast<double>();
    }
    EXPECT_LT((n1[i].cast<double>() - sum.normalized()).norm(), 1e-6) << "face " << i;
  }
}

TEST(Denoise, PlaneNoiseErrorFallsByMoreThanHalf) {
  const Vector3d truth(-0.3, -0.1, 1.0);  // normal of z = 0.3 x + 0.1 y
  for (unsigned seed : {1u, 2u, 3u}) {
    GridMesh m = noisy_mesh(
        60, [](double x, double y) { return 0.3 * x + 0.1 * y; }, 0.05, seed);
    double before = 0, after = 0;
    for (const auto& n : m.normals) before += angle_deg(n, truth);
    const DenoiseStats s = denoise_normals(m, {});
    for (const auto& n : m.normals) after += angle_deg(n, truth);
    EXPECT_LT(after, 0.5 * before) << "seed " << seed;
    EXPECT_GT(s.mean_change_deg, 0.0);
    EXPECT_NEAR(s.sigma_s, 0.8, 0.2);  // edge-adjacent centroid distance on a 1 m grid
    ASSERT_EQ(m.normal_change.size(), m.n_vertices());
  }
}

// A roof ridge z = 20 - |x - 30| (a 90-degree crease along the column x = 30) with noise:
// the bilateral filter keeps the two sides' normals at the crease better than the same
// filter without its range kernel (plain area/distance-weighted averaging).
TEST(Denoise, SharpRidgeSurvivesBetterThanPlainAveraging) {
  auto roof = [](double x, double) { return 20.0 - std::abs(x - 30.0); };
  const GridMesh noisy = noisy_mesh(61, roof, 0.05, 7);
  auto crease_error = [&](const DenoiseOptions& o) {
    double sigma = 0;
    const auto filtered = bilateral_filter_normals(noisy, face_normals(noisy), o, sigma);
    double err = 0;
    std::size_t n = 0;
    for (std::size_t f = 0; f < noisy.n_faces(); ++f) {
      const std::size_t cell = f / 2, r = cell / 60, c = cell % 60;
      if (r < 3 || r > 56 || (c != 29 && c != 30)) continue;  // the faces touching the crease
      const Vector3d truth = c < 30 ? Vector3d(-1, 0, 1) : Vector3d(1, 0, 1);
      err += angle_deg(filtered[f], truth);
      ++n;
    }
    return err / double(n);
  };
  DenoiseOptions bilateral, plain;
  plain.sigma_r = 0;
  const double e_bilateral = crease_error(bilateral), e_plain = crease_error(plain);
  EXPECT_LT(e_bilateral, 0.5 * e_plain) << e_bilateral << " vs " << e_plain;
  EXPECT_LT(e_bilateral, 5.0);
}

TEST(Denoise, VertexUpdateKeepsTheGridAndItsBoundary) {
  GridMesh m = noisy_mesh(
      30, [](double x, double) { return 0.2 * x; }, 0.05, 11);
  const GridMesh original = m;
  DenoiseOptions o;
  o.update_vertices = true;
  const DenoiseStats s = denoise_normals(m, o);
  EXPECT_GT(s.max_vertex_shift, 0.0);
  EXPECT_LT(s.max_vertex_shift, 0.5);
  for (std::size_t v = 0; v < m.n_vertices(); ++v) {
    EXPECT_EQ(m.positions[v].x(), original.positions[v].x());  // only z moves
    EXPECT_EQ(m.positions[v].y(), original.positions[v].y());
    const std::size_t r = v / 30, c = v % 30;
    if (r == 0 || c == 0 || r == 29 || c == 29) {
      EXPECT_EQ(m.positions[v].z(), original.positions[v].z());
    }
  }
  // The surface got smoother: its normals are closer to the plane's.
  const Vector3d truth(-0.2, 0, 1);
  double before = 0, after = 0;
  for (std::size_t v = 0; v < m.n_vertices(); ++v) {
    before += angle_deg(original.normals[v], truth);
    after += angle_deg(m.normals[v], truth);
  }
  EXPECT_LT(after, 0.5 * before);
}

}  // namespace
}  // namespace terrain
