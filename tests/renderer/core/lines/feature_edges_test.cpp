// Object-space feature edges (GL-free reference): the edge buffer of the grid
// triangulation, and contour, crease and boundary edges on surfaces whose answers are known.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "renderer/core/feature_edges.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/grid_mesh.hpp"
#include "test_support.hpp"

namespace renderer {
namespace {

std::size_t count(const std::vector<std::uint8_t>& kinds, std::uint8_t kind) {
  return std::size_t(
      std::count_if(kinds.begin(), kinds.end(), [&](std::uint8_t k) { return k & kind; }));
}

// Every edge once; interior edges have two faces whose third vertices lie on opposite
// sides; the boundary edges are the grid's perimeter.
TEST(FeatureEdges, EdgeBufferOfTheGrid) {
  const terrain::GridTopology topo{7, 11};
  const auto edges = mesh_edges(topo);
  EXPECT_EQ(edges.size(), 6u * 11 + 7u * 10 + 6u * 10);
  std::set<std::pair<std::uint32_t, std::uint32_t>> unique;
  std::size_t boundary = 0;
  for (const MeshEdge& e : edges) {
    unique.insert({std::min(e.v0, e.v1), std::max(e.v0, e.v1)});
    boundary += e.boundary();
    EXPECT_NE(e.v2, e.v3);
  }
  EXPECT_EQ(unique.size(), edges.size());
  EXPECT_EQ(boundary, 2u * 6 + 2u * 10);
  // A flat plane seen from anywhere above: no contour, no crease; the boundary is found.
  const terrain::GridMesh plane = terrain::test::function_mesh(
      7, 11, 10.0, [](double x, double y) { return 0.1 * x - 0.2 * y; });
  const auto kinds = classify_edges(edges, plane.positions, Eigen::Vector3d(50, -30, 500), 1.0);
  EXPECT_EQ(count(kinds, kContourEdge), 0u);
  EXPECT_EQ(count(kinds, kCreaseEdge), 0u);
  EXPECT_EQ(count(kinds, kBoundaryEdge), boundary);
}

// A tent: two planes of slope 1 meeting along the column x = 50 (normals 90 degrees
// apart). Its crease edges are exactly the ridge edges for angles below 90 and none above;
// the ridge is a contour for an eye low on one side and not for an eye above.
TEST(FeatureEdges, TentRidgeIsCreaseAndContour) {
  const std::size_t rows = 9, cols = 11;
  const terrain::GridMesh tent = terrain::test::function_mesh(
      rows, cols, 10.0, [](double x, double) { return 100.0 - std::abs(x - 50.0); });
  const auto edges = mesh_edges(tent.topo);
  auto on_ridge = [&](const MeshEdge& e) { return e.v0 % cols == 5 && e.v1 % cols == 5; };
  const std::size_t ridge_edges = rows - 1;
  for (double angle : {1.0, 30.0, 89.0}) {
    const auto kinds = classify_edges(edges, tent.positions, Eigen::Vector3d(50, -40, 1000), angle);
    std::size_t on = 0;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (kinds[i] & kCreaseEdge) {
        EXPECT_TRUE(on_ridge(edges[i])) << i;
        ++on;
      }
    }
    EXPECT_EQ(on, ridge_edges) << angle;
    EXPECT_EQ(count(kinds, kContourEdge), 0u);  // from high above both sides face the eye
  }
  EXPECT_EQ(count(classify_edges(edges, tent.positions, Eigen::Vector3d(50, -40, 1000), 91.0),
                  kCreaseEdge),
            0u);
  // Eye far to the west, a little above the ridge: the west slope faces it, the east slope
  // faces away; the ridge edges are contours, nothing else is.
  const auto side = classify_edges(edges, tent.positions, Eigen::Vector3d(-5000, -40, 120), 170.0);
  std::size_t contours = 0;
  for (std::size_t i = 0; i < edges.size(); ++i)
    if (side[i] & kContourEdge) {
      EXPECT_TRUE(on_ridge(edges[i])) << i;
      ++contours;
    }
  EXPECT_EQ(contours, ridge_edges);
  // From there the east slope faces away: its edges are not drawn, whatever their kind;
  // every edge with a vertex west of the ridge faces the eye.
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::size_t c0 = edges[i].v0 % cols, c1 = edges[i].v1 % cols;
    if (c0 > 5 || c1 > 5) {
      if (c0 >= 5 && c1 >= 5 && !on_ridge(edges[i])) {
        EXPECT_FALSE(side[i] & kFacingEye) << i;
      }
    } else {
      EXPECT_TRUE(side[i] & kFacingEye) << i;
    }
  }
}

// The edges of each vertex: every edge is listed at both its vertices, corners have 2 or 3
// edges, other boundary vertices 3 or 4, interior vertices 6.
TEST(FeatureEdges, VertexEdgeSlots) {
  const terrain::GridTopology topo{5, 6};
  const auto edges = mesh_edges(topo);
  const auto slots = vertex_edges(edges, topo.n_vertices());
  std::size_t listed = 0;
  for (std::size_t v = 0; v < topo.n_vertices(); ++v) {
    std::size_t degree = 0;
    for (std::size_t k = 0; k < kVertexEdgeSlots; ++k) {
      const std::uint32_t e = slots[v * kVertexEdgeSlots + k];
      if (e == MeshEdge::kNoVertex) continue;
      EXPECT_TRUE(edges[e].v0 == v || edges[e].v1 == v);
      ++degree;
    }
    listed += degree;
    const std::size_t r = v / topo.cols, c = v % topo.cols;
    const bool edge_r = r == 0 || r == topo.rows - 1, edge_c = c == 0 || c == topo.cols - 1;
    if (edge_r && edge_c) {
      EXPECT_TRUE(degree == 2 || degree == 3) << v;
    } else if (edge_r || edge_c) {
      EXPECT_TRUE(degree == 3 || degree == 4) << v;
    } else {
      EXPECT_EQ(degree, 6u) << v;
    }
  }
  EXPECT_EQ(listed, 2 * edges.size());
}

// On real terrain, a larger crease angle never adds crease edges, and every interior
// edge is a crease at angle 0 unless its faces are coplanar.
TEST(FeatureEdges, CreaseCountFallsWithTheAngle) {
  const terrain::GridMesh m =
      terrain::make_grid_mesh(terrain::read_dem(terrain::test::data("logan_utm12n_100m.tif")),
                              terrain::NormalWeighting::Uniform);
  const auto edges = mesh_edges(m.topo);
  std::size_t previous = edges.size() + 1;
  for (double angle = 0.0; angle <= 180.0; angle += 5.0) {
    const std::size_t n =
        count(classify_edges(edges, m.positions, Eigen::Vector3d(0, 0, 1e6), angle), kCreaseEdge);
    EXPECT_LE(n, previous) << angle;
    previous = n;
  }
  EXPECT_EQ(previous, 0u);  // 180 degrees: none
}

}  // namespace
}  // namespace renderer
