// The EDGE pass (object-space feature edges) on OpenGL (llvmpipe in CI): its classification
// equals the GL-free reference (feature_edges.hpp) exactly on analytic scenes, the crease
// threshold is monotone, exact caps leave no gap pixel along the drawn polylines, and edges
// behind the PN surface are hidden.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

#include <Eigen/Geometry>

#include "renderer/core/feature_edges.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/gl_contract.h"
#include "renderer/gl/terrain_renderer.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace renderer {
namespace {

using Eigen::Vector3d;

Style edge_style(double crease_angle, EdgeCaps caps = EdgeCaps::Exact,
                 std::uint8_t kinds = kAllEdgeKinds) {
  Style s;
  s.background = {1, 1, 1};
  s.edge_colour = {0, 0, 1};
  s.crease_angle = crease_angle;
  s.edge_caps = caps;
  s.edge_kinds = kinds;
  s.crease_lift = 0;
  return s;
}

Layers edge_layers() {
  Layers l{false, true, false, false};
  l.edges = true;
  return l;
}

FrameParams looking(const Vector3d& eye, double az, double alt, double fov,
                    bool orthographic = false) {
  FrameParams fp;
  fp.camera.eye = eye;
  fp.camera.view_az = az;
  fp.camera.view_alt = alt;
  fp.camera.fov = fov;
  fp.camera.orthographic = orthographic;
  return fp;
}

struct Scene {
  const char* name;
  terrain::GridMesh mesh;
  std::vector<FrameParams> views;
};

// The tent of feature_edges_test (ridge at x = 50), a pyramid (its ridges along both
// diagonals: one follows the grid's diagonal edges, the other a staircase of row and
// column edges) and the Gaussian ridge of the silhouette tests; the last view of each is
// orthographic (the facing tests along the line of sight).
std::vector<Scene> scenes() {
  std::vector<Scene> out;
  out.push_back(
      {"tent",
       terrain::test::function_mesh(9, 11, 10.0,
                                    [](double x, double) { return 100.0 - std::abs(x - 50.0); }),
       {looking({-300, -40, 120}, 90, 5, 60), looking({50, -40, 600}, 0, 90, 60),
        looking({150, 60, 180}, 200, 30, 60), looking({-300, -40, 120}, 90, 5, 60, true)}});
  out.push_back(
      {"pyramid",
       terrain::test::function_mesh(21, 21, 10.0,
                                    [](double x, double y) {
                                      return 80.0 - 0.8 * std::max(std::abs(x - 100.0),
                                                                   std::abs(y + 100.0));
                                    }),
       {looking({100, -100, 500}, 0, 90, 50), looking({-150, -180, 90}, 70, 10, 60),
        looking({260, 40, 140}, 225, 25, 60), looking({-150, -180, 90}, 70, 10, 60, true)}});
  const double H = 200, s = 100, yr = -3000;
  out.push_back(
      {"gaussian ridge",
       terrain::test::function_mesh(
           201, 101, 20.0,
           [=](double, double y) { return H * std::exp(-0.5 * (y - yr) * (y - yr) / (s * s)); }),
       {looking({1000, -3900, 100}, 0, 0, 30), looking({1000, -3900, 400}, 0, 0, 30),
        looking({-500, -2500, 600}, 120, 15, 45), looking({1000, -3900, 100}, 0, 3, 30, true)}});
  return out;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> drawn_set(
    const std::vector<std::array<std::uint32_t, 4>>& drawn) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> s;
  for (const auto& d : drawn) s.insert({std::min(d[0], d[1]), std::max(d[0], d[1])});
  return s;
}

// Every edge's kinds and the set of drawn edges equal the CPU reference's, for three
// views of each scene, three crease angles and two kind masks.
TEST(EdgesGl, ClassificationEqualsCpuReference) {
  GlContext ctx;
  for (const Scene& sc : scenes()) {
    const auto edges = mesh_edges(sc.mesh.topo);
    for (const double angle : {5.0, 20.0, 60.0})
      for (const std::uint8_t mask : {kAllEdgeKinds, std::uint8_t(kContourEdge)}) {
        TerrainRenderer r(ctx, sc.mesh, nullptr, 160, 120, edge_layers(),
                          edge_style(angle, EdgeCaps::Exact, mask));
        for (std::size_t v = 0; v < sc.views.size(); ++v) {
          SCOPED_TRACE(std::string(sc.name) + " view " + std::to_string(v) + " angle " +
                       std::to_string(angle));
          const FrameResult res = r.render(sc.views[v]);
          const auto gpu = r.read_edges();
          const auto cpu = classify_edges(edges, sc.mesh.positions, res.view.viewpoint(), angle);
          ASSERT_EQ(gpu.kinds.size(), cpu.size());
          std::size_t differ = 0, kinds_seen = 0;
          std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
          for (std::size_t i = 0; i < cpu.size(); ++i) {
            differ += gpu.kinds[i] != cpu[i];
            kinds_seen |= cpu[i];
            if (edge_drawn(cpu[i], mask))
              expected.insert(
                  {std::min(edges[i].v0, edges[i].v1), std::max(edges[i].v0, edges[i].v1)});
          }
          EXPECT_EQ(differ, 0u);
          EXPECT_EQ(drawn_set(gpu.drawn), expected);
          EXPECT_EQ(res.edges, expected.size());
          EXPECT_EQ(gpu.drawn.size(), expected.size());  // each once
          if (angle == 5.0 && mask == kAllEdgeKinds) {
            EXPECT_TRUE(kinds_seen & kCreaseEdge);  // not vacuous
          }
        }
      }
  }
}

// A larger crease angle never draws more crease edges (real terrain, GPU), and the count
// is the CPU reference's.
TEST(EdgesGl, CreaseThresholdIsMonotone) {
  const terrain::Grid dem = terrain::read_dem(terrain::test::data("msh_2007_utm10n_10m.tif"));
  terrain::Grid crop(48, 48, dem.geo);
  for (std::size_t r = 0; r < 48; ++r)
    for (std::size_t c = 0; c < 48; ++c) crop.at(r, c) = dem.at(150 + r, 100 + c);
  const terrain::GridMesh mesh = terrain::make_grid_mesh(crop, terrain::NormalWeighting::Uniform);
  const auto edges = mesh_edges(mesh.topo);
  GlContext ctx;
  // From 2 degrees: at 0 every float dot product of nearly coplanar faces rounds to 1.
  std::size_t previous = edges.size() + 1, first = 0;
  for (double angle = 2.0; angle <= 92.0; angle += 10.0) {
    TerrainRenderer r(ctx, mesh, nullptr, 160, 120, edge_layers(),
                      edge_style(angle, EdgeCaps::Cheap, kCreaseEdge));
    const FrameResult res = r.render(FrameParams{});
    const auto cpu = classify_edges(edges, mesh.positions, res.view.viewpoint(), angle);
    const auto expected = std::size_t(
        std::count_if(cpu.begin(), cpu.end(), [](auto k) { return edge_drawn(k, kCreaseEdge); }));
    EXPECT_EQ(res.edges, expected) << angle;
    EXPECT_LE(res.edges, previous) << angle;
    if (angle == 2.0) first = res.edges;
    previous = res.edges;
  }
  EXPECT_GT(first, previous);  // the threshold does remove edges
}

// Distance from p to segment ab.
double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t =
      d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * d - p).norm();
}

struct StrokeCount {
  std::size_t gaps = 0, overshoot = 0, beyond_mitre = 0, joins = 0, covered = 0;
};

// Along the drawn edges projected on the CPU: pixels whose centre lies within half the
// width (less 0.05 px) of an edge but are not covered (gaps), covered pixels farther than
// half the width plus one pixel from every edge (overshoot: square caps and mitres reach
// out of the round stroke), and covered pixels beyond the longest mitre the mitre limit
// allows (half the width / TR_MITER_MIN_COS, plus half a pixel).
StrokeCount count_stroke(const TerrainRenderer& r, const FrameResult& res,
                         const terrain::GridMesh& mesh, double width) {
  const auto out = r.read_edges();
  const auto buffers = r.read_buffers();
  const Eigen::Matrix4d vp = res.view.view_projection();
  auto screen = [&](std::uint32_t v) {
    const Eigen::Vector4d c = vp * mesh.positions[v].cast<double>().homogeneous();
    return Eigen::Vector2d((c.x() / c.w() + 1) * 0.5 * res.width,
                           (1 - c.y() / c.w()) * 0.5 * res.height);
  };
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segs;
  StrokeCount n;
  for (const auto& d : out.drawn) {
    segs.push_back({screen(d[0]), screen(d[1])});
    n.joins += (d[2] != MeshEdge::kNoVertex) + (d[3] != MeshEdge::kNoVertex);
  }
  for (int row = 0; row < res.height; ++row)
    for (int col = 0; col < res.width; ++col) {
      const Eigen::Vector2d p(col + 0.5, row + 0.5);
      double best = 1e30;
      for (const auto& [a, b] : segs) best = std::min(best, segment_distance(p, a, b));
      const bool on = buffers.edge[std::size_t(row) * std::size_t(res.width) + std::size_t(col)];
      n.covered += on;
      if (!on && best < 0.5 * width - 0.05) ++n.gaps;
      if (on && best > 0.5 * width + 1.0) ++n.overshoot;
      if (on && best > 0.5 * width / TR_MITER_MIN_COS + 0.5) ++n.beyond_mitre;
    }
  return n;
}

// Exact caps: no gap pixel where consecutive edges join (from above, the pyramid's
// staircase ridge turns by 90 degrees at every step; the oblique views turn by other
// angles); without caps the same views have gaps, so the count can fail. Cheap (square)
// caps have no gap either but overshoot outside the turns; the counts are printed.
TEST(EdgesGl, ExactCapsLeaveNoGap) {
  const Scene sc = scenes()[1];
  const double width = 5.0;
  GlContext ctx;
  for (const FrameParams& view : sc.views) {
    StrokeCount by_caps[3];
    for (const EdgeCaps caps : {EdgeCaps::None, EdgeCaps::Cheap, EdgeCaps::Exact}) {
      Style style = edge_style(20.0, caps);
      style.edge_width = width;
      TerrainRenderer r(ctx, sc.mesh, nullptr, 240, 240, edge_layers(), style);
      const FrameResult res = r.render(view);
      by_caps[int(caps)] = count_stroke(r, res, sc.mesh, width);
      const StrokeCount& n = by_caps[int(caps)];
      std::printf(
          "caps %d: %zu edges, %zu joins, %zu covered, %zu gap pixels, %zu overshoot pixels\n",
          int(caps), res.edges, n.joins, n.covered, n.gaps, n.overshoot);
    }
    EXPECT_GE(by_caps[int(EdgeCaps::Exact)].joins, 40u);  // polylines with many joins
    EXPECT_EQ(by_caps[int(EdgeCaps::Exact)].gaps, 0u);
    EXPECT_EQ(by_caps[int(EdgeCaps::Cheap)].gaps, 0u);  // square caps cover the round join too
    EXPECT_GT(by_caps[int(EdgeCaps::None)].gaps, 10u);
    for (const StrokeCount& n : by_caps) EXPECT_EQ(n.beyond_mitre, 0u);
  }
}

// Hidden lines: seen from below the Gaussian ridge's crest, the plain's far boundary lies
// behind the ridge. It is in the edge layer but not in the picture.
TEST(EdgesGl, EdgesBehindTheSurfaceAreHidden) {
  const Scene sc = scenes()[2];
  GlContext ctx;
  TerrainRenderer r(ctx, sc.mesh, nullptr, 320, 240, edge_layers(),
                    edge_style(20.0, EdgeCaps::Exact, kBoundaryEdge));
  const FrameResult res = r.render(sc.views[0]);
  const auto b = r.read_buffers();
  const Eigen::Vector4d far = res.view.view_projection() *
                              Eigen::Vector4d(1000 - sc.mesh.geo.origin_x, 0 - sc.mesh.geo.origin_y,
                                              0 - sc.mesh.geo.origin_z, 1);
  const int far_row = int((1 - far.y() / far.w()) * 0.5 * 240);
  std::size_t in_layer = 0, in_picture = 0;
  for (int row = far_row - 2; row <= far_row + 2; ++row)
    for (int col = 0; col < 320; ++col) {
      const std::size_t i = std::size_t(row) * 320 + std::size_t(col);
      in_layer += b.edge[i];
      in_picture += res.rgba[4 * i] == 0 && res.rgba[4 * i + 1] == 0 && res.rgba[4 * i + 2] == 255;
    }
  EXPECT_GE(in_layer, 300u) << "far boundary at row " << far_row;
  EXPECT_EQ(in_picture, 0u);
}

}  // namespace
}  // namespace renderer
