// Mixed Voronoi areas and tangent frames (docs/algorithms.md 4), and their round trip through
// the mesh file.
#include <gtest/gtest.h>

#include <random>

#include "terrain/dem_io.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

using Eigen::Vector3d;

TEST(Voronoi, WorkedExamples) {
  // docs/algorithms.md 4.2: acute (0,0),(4,0),(1,3): (2.25, 1.75, 2.0); right angle at the
  // origin: (1.0, 0.5, 0.5); obtuse at (2,1), area 2: Meyer (0.5, 0.5, 1.0).
  auto expect_corners = [](const Vector3d& got, const Vector3d& want) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-12) << "corner " << k;
  };
  expect_corners(mixed_voronoi_corners({0, 0, 0}, {4, 0, 0}, {1, 3, 0}), {2.25, 1.75, 2.0});
  expect_corners(mixed_voronoi_corners({0, 0, 0}, {2, 0, 0}, {0, 2, 0}), {1.0, 0.5, 0.5});
  expect_corners(mixed_voronoi_corners({0, 0, 0}, {4, 0, 0}, {2, 1, 0}), {0.5, 0.5, 1.0});
  // Order of the corners follows the arguments; a degenerate triangle has no area.
  const auto o2 = mixed_voronoi_corners({2, 1, 0}, {0, 0, 0}, {4, 0, 0});
  EXPECT_NEAR(o2[0], 1.0, 1e-12);
  EXPECT_EQ(mixed_voronoi_corners({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), Vector3d::Zero());
}

// The plane z = sx x + sy y.
GridMesh plane_mesh(std::size_t rows, std::size_t cols, double h, double sx, double sy) {
  return test::function_mesh(rows, cols, h, [=](double x, double y) { return sx * x + sy * y; });
}

TEST(Voronoi, RegularPlanarGridInteriorVertexGetsOneCell) {
  // Flat and tilted planes: each interior vertex's area is one cell (h^2 times the slope
  // factor sqrt(1 + sx^2 + sy^2) of the tilted plane's area element).
  for (const auto& [sx, sy] : {std::pair{0.0, 0.0}, {0.3, -0.2}}) {
    const GridMesh m = plane_mesh(6, 7, 10.0, sx, sy);
    const VoronoiWeights w = voronoi_weights(m);
    const double cell = 100.0 * std::sqrt(1 + sx * sx + sy * sy);
    for (std::size_t r = 1; r + 1 < 6; ++r)
      for (std::size_t c = 1; c + 1 < 7; ++c)
        EXPECT_NEAR(w.vertex_areas[r * 7 + c], cell, 1e-3 * cell) << r << " " << c;
    // Tangents: unit, perpendicular to the normal, pointing east.
    for (std::size_t v = 0; v < m.n_vertices(); ++v) {
      EXPECT_NEAR(w.tangents[v].norm(), 1.0f, 1e-6f);
      EXPECT_NEAR(w.tangents[v].dot(m.normals[v]), 0.0f, 1e-6f);
      EXPECT_GT(w.tangents[v].x(), 0.9f);
    }
  }
}

// Vertex areas sum to the mesh area on real data and on meshes full of obtuse triangles;
// no corner area is negative.
void check_sums(const GridMesh& m) {
  const auto [vertex_sum, face_sum] = voronoi_area_sums(m);
  EXPECT_NEAR(vertex_sum, face_sum, 1e-9 * face_sum);
  const VoronoiWeights w = voronoi_weights(m);
  for (std::size_t f = 0; f < m.n_faces(); ++f) ASSERT_GE(w.corner_areas[f].minCoeff(), 0.0f) << f;
}

TEST(Voronoi, AreasSumToMeshArea) {
  const Grid msh = read_dem(test::data("msh_2007_utm10n_10m.tif"));
  check_sums(make_grid_mesh(msh, NormalWeighting::Uniform));

  std::mt19937 rng(20261122);
  std::uniform_real_distribution<float> jitter(-0.45f, 0.45f), height(0.0f, 3.0f);
  for (int trial = 0; trial < 5; ++trial) {
    GridMesh m = plane_mesh(30, 40, 1.0, 0, 0);
    std::size_t obtuse = 0;
    for (auto& p : m.positions) p += Eigen::Vector3f(jitter(rng), jitter(rng), height(rng));
    for (std::size_t f = 0; f < m.n_faces(); ++f) {
      const auto t = m.topo.face(f);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3f a = m.positions[t[std::size_t(k)]],
                              b = m.positions[t[std::size_t((k + 1) % 3)]],
                              c = m.positions[t[std::size_t((k + 2) % 3)]];
        obtuse += (b - a).dot(c - a) < 0;
      }
    }
    EXPECT_GT(obtuse, m.n_faces() / 10) << "seed 20261122 trial " << trial;
    check_sums(m);
  }
}

TEST(Voronoi, StoredInTheMeshFile) {
  test::ScratchDir dir;
  GridMesh m = plane_mesh(5, 6, 10.0, 0.1, 0.2);
  m.voronoi = voronoi_weights(m);
  m.normal_change.assign(m.n_vertices(), 0.0f);
  m.normal_change[7] = 12.5f;
  write_mesh_ply(m, dir.path("w.ply"));
  const GridMesh back = read_mesh_ply(dir.path("w.ply"));
  ASSERT_FALSE(back.voronoi.empty());
  for (std::size_t v = 0; v < m.n_vertices(); ++v) {
    EXPECT_EQ(back.voronoi.vertex_areas[v], m.voronoi.vertex_areas[v]);
    EXPECT_EQ(back.voronoi.tangents[v], m.voronoi.tangents[v]);
  }
  for (std::size_t f = 0; f < m.n_faces(); ++f)
    EXPECT_EQ(back.voronoi.corner_areas[f], m.voronoi.corner_areas[f]);
  ASSERT_EQ(back.normal_change.size(), m.n_vertices());
  EXPECT_EQ(back.normal_change[7], 12.5f);
  // A mesh without them reads back without them.
  write_mesh_ply(plane_mesh(3, 3, 1.0, 0, 0), dir.path("p.ply"));
  const GridMesh plain = read_mesh_ply(dir.path("p.ply"));
  EXPECT_TRUE(plain.voronoi.empty());
  EXPECT_EQ(plain.normal_change.size(), 0u);
}

}  // namespace
}  // namespace terrain
