// The grid triangulation convention and vertex normals.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/grid_mesh.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

Grid analytic_grid(std::size_t rows, std::size_t cols, double h, double (*f)(double, double)) {
  Georef geo;
  geo.dx = geo.dy = h;
  geo.x0 = -h / 2;  // sample (0,0) at the origin
  geo.y0 = h / 2;
  Grid g(rows, cols, geo);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c)
      g.at(r, c) = float(f(geo.x_of_col(double(c)), geo.y_of_row(double(r))));
  return g;
}

TEST(GridTopology, ConventionOnA3x3Grid) {
  const GridTopology t{3, 3};
  // Vertices 0 1 2 / 3 4 5 / 6 7 8 (row 0 north). Cell (0,0): NW=0 NE=1 SW=3 SE=4.
  EXPECT_EQ(t.n_faces(), 8u);
  EXPECT_EQ(t.face(0), (std::array<std::uint32_t, 3>{0, 3, 4}));  // (NW, SW, SE)
  EXPECT_EQ(t.face(1), (std::array<std::uint32_t, 3>{0, 4, 1}));  // (NW, SE, NE)
  EXPECT_EQ(t.face(2), (std::array<std::uint32_t, 3>{1, 4, 5}));  // cell (0,1)
  EXPECT_EQ(t.face(7), (std::array<std::uint32_t, 3>{4, 8, 5}));  // cell (1,1), face 1
  EXPECT_EQ(t.face_of_cell(1, 1, 1), 7u);
}

TEST(GridMesh, FacesAreCounterClockwiseSeenFromAbove) {
  const Grid g = analytic_grid(4, 5, 10.0, [](double, double) { return 0.0; });
  const GridMesh m = make_grid_mesh(g, NormalWeighting::Uniform);
  for (std::size_t f = 0; f < m.n_faces(); ++f) {
    const auto v = m.topo.face(f);
    const Eigen::Vector3d n =
        face_normal(m.positions[v[0]].cast<double>(), m.positions[v[1]].cast<double>(),
                    m.positions[v[2]].cast<double>());
    ASSERT_NEAR(n.z(), 1.0, 1e-12) << f;
  }
  // Local coordinates: vertex (r, c) at (c dx, -r dy); origin at sample (0,0).
  EXPECT_EQ(m.positions[m.topo.cols * 2 + 3], Eigen::Vector3f(30.0f, -20.0f, 0.0f));
  EXPECT_DOUBLE_EQ(m.geo.origin_x, 0.0);
  EXPECT_DOUBLE_EQ(m.geo.origin_y, 0.0);
}

// On a plane z = a x + b y every face and vertex normal is the plane's normal.
TEST(GridMesh, PlaneNormalsEqualThePlaneNormal) {
  const Grid g =
      analytic_grid(7, 9, 25.0, [](double x, double y) { return 0.3 * x - 0.7 * y + 1500.0; });
  const Eigen::Vector3d expected = Eigen::Vector3d(-0.3, 0.7, 1.0).normalized();
  for (NormalWeighting w :
       {NormalWeighting::Uniform, NormalWeighting::Angle, NormalWeighting::Area}) {
    const GridMesh m = make_grid_mesh(g, w);
    for (std::size_t f = 0; f < m.n_faces(); ++f) {
      const auto v = m.topo.face(f);
      const Eigen::Vector3d n =
          face_normal(m.positions[v[0]].cast<double>(), m.positions[v[1]].cast<double>(),
                      m.positions[v[2]].cast<double>());
      ASSERT_LT((n - expected).norm(), 1e-6) << "face " << f;
    }
    for (std::size_t i = 0; i < m.n_vertices(); ++i)
      ASSERT_LT((m.normals[i].cast<double>() - expected).norm(), 1e-6)
          << to_string(w) << " vertex " << i;
  }
}

// docs/algorithms.md 3.2: z = 0.2x + 0.1y + 0.3x^2 + 0.4xy at the origin, h = 1, with the "/"
// diagonal. Our diagonal is NW-SE ("\"), the mirror image in y, so we mesh the mirrored
// surface z(x, -y) and expect the mirrored normals (y component negated).
TEST(GridMesh, WorkedExampleVertexNormals) {
  Georef geo;
  geo.x0 = -1.5;  // centre vertex (1, 1) at (0, 0)
  geo.y0 = 1.5;
  Grid centred(3, 3, geo);
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = geo.x_of_col(double(c)), ym = -geo.y_of_row(double(r));
      centred.at(r, c) = float(0.2 * x + 0.1 * ym + 0.3 * x * x + 0.4 * x * ym);
    }
  struct Case {
    NormalWeighting w;
    Eigen::Vector3d n;
  };
  const Case cases[] = {{NormalWeighting::Uniform, {-0.163850, 0.088066, 0.982547}},
                        {NormalWeighting::Area, {-0.195180, 0.097590, 0.975900}},
                        {NormalWeighting::Angle, {-0.167552, 0.084916, 0.982199}}};
  for (const Case& k : cases) {
    const GridMesh m = make_grid_mesh(centred, k.w);
    EXPECT_LT((m.normals[4].cast<double>() - k.n).norm(), 2e-6)
        << to_string(k.w) << ": " << m.normals[4].transpose();
  }
}

// Uniform weighting is computed a face per SIMD lane; here the rule itself, face by face:
// every vertex normal is the normalized sum of its incident faces' unit normals.
TEST(GridMesh, UniformNormalsAreTheNormalizedSumOfTheFacesNormals) {
  Grid g = analytic_grid(60, 47, 100.0, [](double x, double y) {
    return 300 * std::sin(x / 700) * std::cos(y / 450);
  });
  g.at(10, 10) = g.at(11, 10) = g.at(11, 11) = 5;  // a flat cell among slopes
  const GridMesh m = make_grid_mesh(g, NormalWeighting::Uniform);
  std::vector<Eigen::Vector3d> sum(m.n_vertices(), Eigen::Vector3d::Zero());
  for (std::size_t f = 0; f < m.n_faces(); ++f) {
    const auto v = m.topo.face(f);
    const Eigen::Vector3d n =
        face_normal(m.positions[v[0]].cast<double>(), m.positions[v[1]].cast<double>(),
                    m.positions[v[2]].cast<double>());
    for (auto i : v) sum[i] += n;
  }
  for (std::size_t i = 0; i < m.n_vertices(); ++i)
    ASSERT_LT((m.normals[i].cast<double>() - sum[i].normalized()).norm(), 1e-6) << "vertex " << i;
}

// GridMeshRows gives make_grid_mesh's floats for any band: the first and last rows, one
// row, the whole grid, bands that meet.
TEST(GridMesh, RowsInBandsEqualTheWholeMesh) {
  const Grid g = analytic_grid(
      23, 17, 30.0, [](double x, double y) { return 0.002 * x * y + 40 * std::sin(x / 90); });
  for (NormalWeighting w :
       {NormalWeighting::Uniform, NormalWeighting::Angle, NormalWeighting::Area}) {
    const GridMesh m = make_grid_mesh(g, w);
    GridMeshRows rows(g, w);
    for (auto [r0, r1] :
         {std::pair<std::size_t, std::size_t>{0, 1}, {0, 5}, {5, 6}, {6, 22}, {22, 23}, {0, 23}}) {
      std::vector<Eigen::Vector3f> p((r1 - r0) * g.cols), n(p.size());
      rows.rows(r0, r1, p.data(), n.data());
      for (std::size_t i = 0; i < p.size(); ++i) {
        ASSERT_EQ(p[i], m.positions[r0 * g.cols + i])
            << to_string(w) << " rows " << r0 << ".." << r1 << " " << i;
        ASSERT_EQ(n[i], m.normals[r0 * g.cols + i])
            << to_string(w) << " rows " << r0 << ".." << r1 << " " << i;
      }
    }
    EXPECT_THROW(rows.rows(20, 24, nullptr, nullptr), Error);
  }
}

TEST(GridMesh, MeshToGridRestoresTheGrid) {
  const Grid g = read_dem(test::data("logan_utm12n_100m.tif"));
  const GridMesh m = make_grid_mesh(g, NormalWeighting::Area);
  const Grid back = mesh_to_grid(m);
  EXPECT_EQ(back.z, g.z);
  EXPECT_DOUBLE_EQ(back.geo.x0, g.geo.x0);
  EXPECT_DOUBLE_EQ(back.geo.y0, g.geo.y0);
  EXPECT_EQ(back.geo.epsg, 26912);
}

TEST(GridMesh, RejectsNodata) {
  Grid g = analytic_grid(3, 3, 1.0, [](double, double) { return 1.0; });
  g.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(make_grid_mesh(g, NormalWeighting::Uniform), Error);
  EXPECT_THROW(GridMeshRows(g, NormalWeighting::Uniform), Error);
}

}  // namespace
}  // namespace terrain
