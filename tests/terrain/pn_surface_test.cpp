// The PN surface of a grid mesh: the point above (x, y).
#include <gtest/gtest.h>

#include <random>

#include <omp.h>

#include "terrain/dem_io.hpp"
#include "terrain/pn_surface.hpp"
#include "terrain/prepare_grid.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

TEST(PnPointAbove, PlanarMeshGivesThePlane) {
  Georef geo;
  geo.dx = geo.dy = 50.0;
  Grid g(6, 8, geo);
  for (std::size_t r = 0; r < g.rows; ++r)
    for (std::size_t c = 0; c < g.cols; ++c)
      g.at(r, c) = float(100.0 + 0.2 * double(c) * 50.0 + 0.1 * double(r) * 50.0);
  const GridMesh m = make_grid_mesh(g, NormalWeighting::Uniform);
  // Local coordinates: x = c * 50, y = -r * 50; z = 100 + 0.2 x - 0.1 y.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0, 350), uy(-250, 0);
  for (int k = 0; k < 300; ++k) {
    const double x = ux(rng), y = uy(rng);
    const auto p = pn_point_above(m, x, y);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->position.x(), x, 1e-7);  // Newton stops at 1e-9 x spacing
    EXPECT_NEAR(p->position.y(), y, 1e-7);
    EXPECT_NEAR(p->position.z(), 100.0 + 0.2 * x - 0.1 * y, 1e-4);  // float vertex z
    EXPECT_NEAR(p->normal.dot(Eigen::Vector3d(-0.2, 0.1, 1).normalized()), 1.0, 1e-6);
  }
  EXPECT_FALSE(pn_point_above(m, -100.0, -10.0));  // off the mesh
}

// Issue 48: on a checkerboard (cells alternating 0 and 100 m, 50 m apart) the patch walk
// stepped off the mesh's edge onto "no face" and read past the faces (SIGSEGV in
// dem2mesh --fit-normals). Every point inside and around the mesh is answered, inside
// with the patch's own point, never from a face that does not exist.
TEST(PnPointAbove, ACheckerboardNeverWalksOffTheMesh) {
  Georef geo;
  geo.dx = geo.dy = 50.0;
  Grid g(24, 24, geo);
  for (std::size_t r = 0; r < g.rows; ++r)
    for (std::size_t c = 0; c < g.cols; ++c) g.at(r, c) = float(100 * ((r + c) % 2));
  const GridMesh m = make_grid_mesh(g, NormalWeighting::Uniform);
  std::size_t answered = 0;
  for (double x = -60; x <= 23 * 50 + 60; x += 3.7)
    for (double y = 60; y >= -23 * 50 - 60; y -= 4.1) {
      const auto p = pn_point_above(m, x, y);
      if (!p) continue;
      ++answered;
      ASSERT_LT(p->face, m.n_faces());
      EXPECT_NEAR(p->position.x(), x, 1e-6);
      EXPECT_NEAR(p->position.y(), y, 1e-6);
    }
  EXPECT_GT(answered, std::size_t(0.8 * (1150 / 3.7) * (1150 / 4.1)));
}

// On real, rough terrain the returned point is exactly above the request (1e-6 m), lies
// inside its patch (or extrapolates a boundary patch), and is the patch's own point.
TEST(PnPointAbove, MountStHelensXyMatchesTheRequest) {
  const GridMesh m =
      make_grid_mesh(read_dem(test::data("msh_2007_utm10n_10m.tif")), NormalWeighting::Uniform);
  const double w = double(m.topo.cols - 1) * m.geo.dx, h = double(m.topo.rows - 1) * m.geo.dy;
  const unsigned seed = 42;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0, w), uy(-h, 0);
  double worst = 0.0;
  int hops_needed = 0;
  for (int k = 0; k < 20000; ++k) {
    const double x = ux(rng), y = uy(rng);
    const auto p = pn_point_above(m, x, y);
    ASSERT_TRUE(p) << "seed " << seed << " at " << x << ", " << y;
    worst = std::max(worst, std::hypot(p->position.x() - x, p->position.y() - y));
    const PnPatch patch = face_patch(m, p->face);
    EXPECT_LT((pn_position(patch, p->b1, p->b2, p->b3) - p->position).norm(), 1e-9);
    // The flat triangle under the point is not always the PN patch above it.
    const std::size_t c = std::size_t(x / m.geo.dx), r = std::size_t(-y / m.geo.dy);
    if (p->face / 2 != r * (m.topo.cols - 1) + c) ++hops_needed;
  }
  EXPECT_LT(worst, 1e-6) << "seed " << seed;
  EXPECT_GT(hops_needed, 0);  // the walk between patches was exercised
  // The corners of the mesh and points on its boundary have answers too.
  for (auto [x, y] : {std::pair{0.0, 0.0}, {w, -h}, {w / 2, 0.0}, {0.0, -h / 3}}) {
    const auto p = pn_point_above(m, x, y);
    ASSERT_TRUE(p) << x << ", " << y;
    EXPECT_LT(std::hypot(p->position.x() - x, p->position.y() - y), 1e-6);
  }
  // At a vertex the surface passes through the vertex.
  const auto v = pn_point_above(m, 100.0, -200.0);
  ASSERT_TRUE(v);
  EXPECT_NEAR(v->position.z(), m.positions[20 * m.topo.cols + 10].z(), 1e-4);
}

// sample_pn_surface: its samples are pn_point_above's heights (the cached monomial form
// changes nothing beyond rounding), at the mesh spacing they are the vertices, its grid is
// georeferenced on the mesh, and the thread count does not change it.
TEST(SamplePnSurface, SamplesArePointsAboveAndVerticesAtTheMeshSpacing) {
  GridRequest req;
  req.spacing = 50.0;
  req.bbox = std::array<double, 4>{561500, 5116000, 563500, 5118000};
  const GridMesh m =
      make_grid_mesh(prepare_grid(read_dem(test::data("msh_2007_utm10n_10m.tif")), req).grid,
                     NormalWeighting::Uniform);
  const SampledSurface fine = sample_pn_surface(m, 10.0);
  EXPECT_EQ(fine.fallbacks, 0u);
  ASSERT_EQ(fine.grid.cols, (m.topo.cols - 1) * 5 + 1);
  ASSERT_EQ(fine.grid.rows, (m.topo.rows - 1) * 5 + 1);
  EXPECT_DOUBLE_EQ(fine.grid.geo.x_of_col(0), m.geo.origin_x);
  EXPECT_DOUBLE_EQ(fine.grid.geo.y_of_row(0), m.geo.origin_y);
  EXPECT_EQ(fine.grid.geo.epsg, m.geo.epsg);
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> ur(0, fine.grid.rows - 1), uc(0, fine.grid.cols - 1);
  for (int k = 0; k < 500; ++k) {
    const std::size_t r = ur(rng), c = uc(rng);
    const auto p = pn_point_above(m, double(c) * 10.0, -double(r) * 10.0);
    ASSERT_TRUE(p);
    EXPECT_NEAR(fine.grid.at(r, c), m.geo.origin_z + p->position.z(), 1e-3) << r << ", " << c;
  }
  const SampledSurface coarse = sample_pn_surface(m, 50.0);
  for (std::size_t v = 0; v < m.n_vertices(); ++v)
    ASSERT_NEAR(coarse.grid.z[v], m.geo.origin_z + m.positions[v].z(), 1e-3) << v;
  omp_set_num_threads(1);
  const SampledSurface one = sample_pn_surface(m, 10.0);
  omp_set_num_threads(omp_get_num_procs());
  EXPECT_EQ(one.grid.z, fine.grid.z);
  EXPECT_THROW(sample_pn_surface(m, 0.0), Error);
}

}  // namespace
}  // namespace terrain
