// Fitted vertex normals (fit_normals.hpp): a surface PN triangles reproduce exactly keeps
// its normals, perturbed normals converge back, the cost falls monotonically on a real
// crop, blocks agree with one problem, and geographic DEM samples land on the mesh.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "terrain/dem_io.hpp"
#include "terrain/fit_normals.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/pn_surface.hpp"
#include "terrain/prepare_grid.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

double quadratic(double x, double y) {
  return 100 + 0.1 * x - 0.05 * y + (x - 150) * (x - 150) / 800 - x * y / 3000;
}

// The mesh of the quadratic on a 50 m grid with its exact normals, and its own PN surface
// sampled every 10 m: a source the PN surface reproduces exactly with these normals.
struct ExactCase {
  GridMesh mesh;
  SourceSamples samples;
};
ExactCase exact_case() {
  ExactCase c;
  c.mesh = test::function_mesh(8, 9, 50.0, quadratic);
  for (std::size_t v = 0; v < c.mesh.n_vertices(); ++v) {
    const double x = c.mesh.positions[v].x(), y = c.mesh.positions[v].y();
    const double zx = 0.1 + (x - 150) / 400 - y / 3000, zy = -0.05 - x / 3000;
    c.mesh.normals[v] = Eigen::Vector3d(-zx, -zy, 1).normalized().cast<float>();
  }
  for (double y = -5; y >= -345; y -= 10)
    for (double x = 5; x <= 395; x += 10) {
      const auto p = pn_point_above(c.mesh, x, y);
      c.samples.x.push_back(c.mesh.geo.origin_x + x);  // world coordinates
      c.samples.y.push_back(c.mesh.geo.origin_y + y);
      c.samples.z.push_back(c.mesh.geo.origin_z + p->position.z());
    }
  return c;
}

// Largest angle between corresponding normals (atan2: acos loses precision near 0).
double max_angle_deg(const GridMesh& a, const GridMesh& b) {
  double worst = 0;
  for (std::size_t v = 0; v < a.n_vertices(); ++v) {
    const Eigen::Vector3d na = a.normals[v].cast<double>().normalized(),
                          nb = b.normals[v].cast<double>().normalized();
    worst = std::max(worst, std::atan2(na.cross(nb).norm(), na.dot(nb)) * 180 / M_PI);
  }
  return worst;
}

// The fit's analytic Jacobian (pn_face_residuals) equals central differences of its own
// residuals: a tilted 50 m face with unit normals leaning 10-25 degrees different ways, 40
// samples inside it, each of the 9 normal components moved by +-1e-4. The residual is
// exact to second order in the inverse evaluation's error, so the differences are clean.
TEST(FitNormals, AnalyticJacobianEqualsFiniteDifferences) {
  const std::array<Eigen::Vector3d, 3> corner{Eigen::Vector3d(0, 0, 10), Eigen::Vector3d(50, 0, 18),
                                              Eigen::Vector3d(0, 50, 4)};
  std::array<Eigen::Vector3d, 3> normal{Eigen::Vector3d(-0.3, 0.1, 1).normalized(),
                                        Eigen::Vector3d(-0.1, 0.4, 1).normalized(),
                                        Eigen::Vector3d(0.2, -0.2, 1).normalized()};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.02, 0.96);
  std::vector<Eigen::Vector3d> samples;
  while (samples.size() < 40) {
    const double a = unit(rng), b = unit(rng);
    if (a + b > 0.98) continue;
    samples.emplace_back(50 * a, 50 * b, 10 + 8 * a - 6 * b + 2 * std::sin(7 * a * b));
  }
  const std::size_t m = samples.size();
  auto residuals = [&](const std::array<Eigen::Vector3d, 3>& nn,
                       std::array<std::vector<double>, 3>* jac) {
    std::vector<double> r(m);
    std::array<double*, 3> j{nullptr, nullptr, nullptr};
    if (jac)
      for (std::size_t k = 0; k < 3; ++k) (*jac)[k].assign(3 * m, 0.0), j[k] = (*jac)[k].data();
    pn_face_residuals(corner, samples, {nn[0].data(), nn[1].data(), nn[2].data()}, r.data(), j);
    return r;
  };
  std::array<std::vector<double>, 3> jac;
  const std::vector<double> r0 = residuals(normal, &jac);
  const std::vector<double> plain =
      residuals(normal, nullptr);  // the same residuals without the Jacobian
  for (std::size_t i = 0; i < m; ++i) EXPECT_NEAR(r0[i], plain[i], 1e-9) << i;
  const double h = 1e-4;
  double worst = 0, largest = 0;
  for (std::size_t v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) {
      auto plus = normal, minus = normal;
      plus[v][k] += h, minus[v][k] -= h;
      const std::vector<double> rp = residuals(plus, nullptr), rm = residuals(minus, nullptr);
      for (std::size_t i = 0; i < m; ++i) {
        const double fd = (rp[i] - rm[i]) / (2 * h), an = jac[v][3 * i + std::size_t(k)];
        worst = std::max(worst, std::abs(fd - an));
        largest = std::max(largest, std::abs(an));
      }
    }
  EXPECT_GT(largest, 1.0);  // metres per unit of normal: the normals matter
  EXPECT_LT(worst, 1e-5 * largest) << "largest derivative " << largest;
}

TEST(FitNormals, ExactSurfaceKeepsItsNormals) {
  ExactCase c = exact_case();
  const GridMesh truth = c.mesh;
  const NormalFitReport r = fit_pn_normals(c.mesh, c.samples);
  EXPECT_LT(r.before.rmse, 1e-4);  // float vertices
  EXPECT_LT(r.after.rmse, 1e-4);
  EXPECT_LT(max_angle_deg(c.mesh, truth), 1e-3);
  EXPECT_TRUE(c.mesh.normal_fit.fitted);
}

// Without the pull (it would pull toward the perturbed normals), every normal returns to
// within 0.1 degrees of the one that made the surface.
TEST(FitNormals, PerturbedNormalsConvergeBack) {
  ExactCase c = exact_case();
  const GridMesh truth = c.mesh;
  std::mt19937 rng(5);
  std::normal_distribution<double> tilt(0.0, 0.05);  // about 3 degrees per axis
  for (auto& n : c.mesh.normals)
    n = (n.cast<double>() + Eigen::Vector3d(tilt(rng), tilt(rng), 0)).normalized().cast<float>();
  const double start = max_angle_deg(c.mesh, truth);
  ASSERT_GT(start, 4.0);
  NormalFitOptions o;
  o.regularization = 0;
  o.max_iterations = 200;
  const NormalFitReport r = fit_pn_normals(c.mesh, c.samples, o);
  std::printf("perturbed normals: max angle %.3f -> %.5f deg, RMSE %.4f -> %.6f m\n", start,
              max_angle_deg(c.mesh, truth), r.before.rmse, r.after.rmse);
  EXPECT_LT(max_angle_deg(c.mesh, truth), 0.1);
  EXPECT_LT(r.after.rmse, 1e-3);
}

// The Mount St. Helens crater rim at 50 m from the 10 m DEM: in one round the accepted
// costs fall monotonically, the surface error drops by a third or more, and blocks of
// 8 x 8 vertices (overlap 4) land within 5 % of the one-problem RMSE.
GridMesh msh_crop(Grid& dem) {
  dem = read_dem(test::data("msh_2007_utm10n_10m.tif"));
  GridRequest req;
  req.spacing = 50;
  req.center = std::array<double, 2>{562700, 5117000};
  req.size = std::array<double, 2>{1200, 1200};
  return make_grid_mesh(prepare_grid(dem, req).grid, NormalWeighting::Uniform);
}

TEST(FitNormals, MountStHelensCostFallsMonotonically) {
  Grid dem;
  GridMesh mesh = msh_crop(dem);
  const SourceSamples s = dem_samples_for_mesh(dem, mesh);
  EXPECT_GT(s.size(), 115u * 115u);  // the 10 m cells inside the 1200 m square crop
  NormalFitOptions o;
  o.rounds = 1;
  o.record_costs = true;
  const NormalFitReport r = fit_pn_normals(mesh, s, o);
  ASSERT_GE(r.costs.size(), 3u);
  for (std::size_t i = 1; i < r.costs.size(); ++i) EXPECT_LE(r.costs[i], r.costs[i - 1]) << i;
  std::printf("MSH crop at 50 m: RMSE %.3f -> %.3f m, max %.2f -> %.2f m, %zu iterations\n",
              r.before.rmse, r.after.rmse, r.before.max_abs, r.after.max_abs, r.iterations);
  // A third less: 3.692 -> 2.461 m with sparse Cholesky steps to a function tolerance of
  // 1e-6 (until stop 43), 2.473 m (0.5 % more) with CGNR steps to 1e-5, 3.6x faster.
  EXPECT_LT(r.after.rmse, 0.68 * r.before.rmse);

  GridMesh blocked = msh_crop(dem);
  o.block = 8;
  o.overlap = 4;
  const NormalFitReport rb = fit_pn_normals(blocked, s, o);
  EXPECT_EQ(rb.blocks, 9u);  // 25 x 25 vertices
  EXPECT_NEAR(rb.after.rmse, r.after.rmse, 0.05 * r.after.rmse);
  EXPECT_TRUE(rb.costs.empty());
}

// Geographic DEM: its samples are projected onto the mesh's UTM grid. The PN surface of the
// mesh made from the same DEM lies within a few metres of them (a wrong projection would be
// off by the relief), and the fit improves it.
TEST(FitNormals, GeographicSamplesLandOnTheMesh) {
  const Grid dem = read_dem(test::data("eno_nad83_geographic_crop.tif"));
  GridRequest req;
  req.spacing = 30;
  GridMesh mesh = make_grid_mesh(prepare_grid(dem, req).grid, NormalWeighting::Uniform);
  const SourceSamples s = dem_samples_for_mesh(dem, mesh);
  ASSERT_GT(s.size(), dem.size() / 2);
  const NormalFitReport r = fit_pn_normals(mesh, s);
  std::printf("Eno (geographic) at 30 m: %zu samples, RMSE %.3f -> %.3f m\n", s.size(),
              r.before.rmse, r.after.rmse);
  EXPECT_LT(r.before.rmse, 2.0);
  EXPECT_LT(r.after.rmse, r.before.rmse);
}

TEST(FitNormals, FitIsRecordedInTheMeshFile) {
  ExactCase c = exact_case();
  test::ScratchDir dir;
  write_mesh_ply(c.mesh, dir.path("plain.ply"));
  EXPECT_FALSE(read_mesh_ply(dir.path("plain.ply")).normal_fit.fitted);
  (void)fit_pn_normals(c.mesh, c.samples);
  write_mesh_ply(c.mesh, dir.path("m.ply"));
  const GridMesh back = read_mesh_ply(dir.path("m.ply"));
  EXPECT_TRUE(back.normal_fit.fitted);
  EXPECT_EQ(back.normal_fit.samples, c.samples.size());
  EXPECT_NEAR(back.normal_fit.rmse_after, c.mesh.normal_fit.rmse_after, 1e-6);
}

TEST(FitNormals, NoSamplesUnderTheMeshIsAnError) {
  ExactCase c = exact_case();
  SourceSamples far;
  far.x = {1e6};
  far.y = {1e6};
  far.z = {0};
  EXPECT_THROW(fit_pn_normals(c.mesh, far), Error);
  EXPECT_EQ(samples_inside_mesh(far, c.mesh).size(), 0u);
}

}  // namespace
}  // namespace terrain
