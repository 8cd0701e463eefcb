// PN triangles against the worked examples of docs/algorithms.md 1.6 and 2.5 and their
// defining properties.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "terrain/pn_triangle.hpp"

namespace terrain {
namespace {

using Eigen::Vector3d;

PnPatch example_patch() {
  return make_pn_patch({0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, 1}, {0.6, 0, 0.8}, {0, 0.6, 0.8});
}

void expect_near(const Vector3d& a, const Vector3d& b, double tol, const char* what) {
  EXPECT_LT((a - b).norm(), tol) << what << ": " << a.transpose() << " vs " << b.transpose();
}

TEST(PnPatch, WorkedExampleControlPoints) {
  const PnPatch p = example_patch();
  expect_near(p.b[B210], {1, 0, 0}, 1e-12, "b210");
  expect_near(p.b[B120], {2.36, 0, 0.48}, 1e-12, "b120");
  expect_near(p.b[B021], {2.36, 1, 0.48}, 1e-12, "b021");
  expect_near(p.b[B012], {1, 2.36, 0.48}, 1e-12, "b012");
  expect_near(p.b[B102], {0, 2.36, 0.48}, 1e-12, "b102");
  expect_near(p.b[B201], {0, 1, 0}, 1e-12, "b201");
  expect_near(p.b[B111], {1.18, 1.18, 0.48}, 1e-12, "b111");
  expect_near(p.n[N110], {-0.316228, 0, 0.948683}, 1e-6, "n110");
  expect_near(p.n[N011], {0.331295, 0.331295, 0.883452}, 1e-6, "n011");
  expect_near(p.n[N101], {0, -0.316228, 0.948683}, 1e-6, "n101");
}

TEST(PnPatch, WorkedExampleEvaluation) {
  const PnPatch p = example_patch();
  expect_near(pn_position(p, 1.0 / 3, 1.0 / 3, 1.0 / 3), {1.12, 1.12, 0.32}, 1e-12, "centre = E");
  expect_near(pn_position(p, 0.5, 0.5, 0.0), {1.635, 0, 0.18}, 1e-12, "edge P1P2 midpoint");
  expect_near(pn_normal(p, 0.5, 0.5, 0.0), {0.102694, 0, 0.994713}, 1e-6, "paper-form normal");
}

TEST(PnPatch, InterpolatesCornersAndCornerNormals) {
  const PnPatch p = example_patch();
  expect_near(pn_position(p, 1, 0, 0), {0, 0, 0}, 1e-15, "P1");
  expect_near(pn_position(p, 0, 1, 0), {3, 0, 0}, 1e-15, "P2");
  expect_near(pn_position(p, 0, 0, 1), {0, 3, 0}, 1e-15, "P3");
  expect_near(pn_normal(p, 1, 0, 0), {0, 0, 1}, 1e-15, "N1");
  expect_near(pn_normal(p, 0, 1, 0), {0.6, 0, 0.8}, 1e-15, "N2");
  expect_near(pn_normal(p, 0, 0, 1), {0, 0.6, 0.8}, 1e-15, "N3");
  // The tangent plane at a corner is the plane of its normal.
  Vector3d ds, dt;
  pn_derivatives(p, 0, 1, 0, ds, dt);
  EXPECT_NEAR(ds.dot(Vector3d(0.6, 0, 0.8)), 0.0, 1e-12);
  EXPECT_NEAR(dt.dot(Vector3d(0.6, 0, 0.8)), 0.0, 1e-12);
}

TEST(PnPatch, DerivativesMatchFiniteDifferences) {
  const PnPatch p = example_patch();
  const double s = 0.3, t = 0.25, h = 1e-6;
  Vector3d ds, dt;
  pn_derivatives(p, 1 - s - t, s, t, ds, dt);
  const Vector3d fs =
      (pn_position(p, 1 - s - h - t, s + h, t) - pn_position(p, 1 - s + h - t, s - h, t)) / (2 * h);
  const Vector3d ft =
      (pn_position(p, 1 - s - t - h, s, t + h) - pn_position(p, 1 - s - t + h, s, t - h)) / (2 * h);
  expect_near(ds, fs, 1e-7, "dP/ds");
  expect_near(dt, ft, 1e-7, "dP/dt");
}

TEST(PnPatch, PlanarInputGivesThePlanarTriangle) {
  const Vector3d p1(10, 20, 5), p2(40, 25, 12), p3(15, 60, 30);
  const Vector3d n = (p2 - p1).cross(p3 - p1).normalized();
  const PnPatch p = make_pn_patch(p1, p2, p3, n, n, n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 200; ++k) {
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vector3d flat = (1 - a - b) * p1 + a * p2 + b * p3;
    expect_near(pn_position(p, 1 - a - b, a, b), flat, 1e-10, "planar position");
    expect_near(pn_normal(p, 1 - a - b, a, b), n, 1e-12, "planar normal");
  }
}

// Two patches sharing an edge (P2, P3) evaluate to identical points and normals along it,
// whatever the normals of their opposite corners.
TEST(PnPatch, NeighboursShareTheirEdgeCurve) {
  std::mt19937 rng(20261122);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 50; ++trial) {
    auto unit_up = [&] { return Vector3d(0.4 * g(rng), 0.4 * g(rng), 1.0).normalized(); };
    const Vector3d a(0, 0, g(rng)), b(10, 0, g(rng)), c(0, 10, g(rng)), d(10, 10, g(rng));
    const Vector3d na = unit_up(), nb = unit_up(), nc = unit_up(), nd = unit_up();
    const PnPatch left = make_pn_patch(a, b, c, na, nb, nc);   // edge b -> c: corners 2, 3
    const PnPatch right = make_pn_patch(d, c, b, nd, nc, nb);  // edge c -> b: corners 2, 3
    for (double t = 0; t <= 1.0; t += 0.125) {
      expect_near(pn_position(left, 0, 1 - t, t), pn_position(right, 0, t, 1 - t), 1e-12,
                  "shared edge point");
      expect_near(pn_normal(left, 0, 1 - t, t), pn_normal(right, 0, t, 1 - t), 1e-12,
                  "shared edge normal");
    }
  }
}

// docs/algorithms.md 2.5.
TEST(PnSolveXy, WorkedExample) {
  const PnPatch p = example_patch();
  const PnXySolution a = pn_solve_xy(p, 1.0, 1.0);
  ASSERT_TRUE(a.converged);
  EXPECT_NEAR(a.b2, 0.297978213, 1e-9);
  EXPECT_NEAR(a.b3, 0.297978213, 1e-9);
  EXPECT_NEAR(a.position.z(), 0.282841, 1e-6);
  const PnXySolution b = pn_solve_xy(p, 1.5, 0.0);
  ASSERT_TRUE(b.converged);
  EXPECT_NEAR(b.b2, 0.458971, 1e-6);
  EXPECT_NEAR(b.b3, 0.0, 1e-12);
  EXPECT_NEAR(b.position.z(), 0.164117, 1e-6);
  // Just outside the flat edge x + y = 3 but inside the bulging PN footprint.
  const PnXySolution c = pn_solve_xy(p, 1.6, 1.6);
  ASSERT_TRUE(c.converged);
  EXPECT_GE(std::min({c.b1, c.b2, c.b3}), 0.0);
}

}  // namespace
}  // namespace terrain
