// Levels of detail (renderer/core/lod.hpp): the patches of any mix of levels form one surface
// without cracks; errors are zero on a plane and grow with the level; the selection
// coarsens with distance and keeps full detail at bound 0.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "renderer/core/camera.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/scene/scene.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/pn_triangle.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector3d;

// A bumpy surface: hills of several wavelengths on a tilt.
terrain::GridMesh bumps(std::size_t rows, std::size_t cols) {
  return terrain::test::function_mesh(rows, cols, 10.0, [](double x, double y) {
    return 0.05 * x + 40 * std::sin(x / 90) * std::cos(y / 70) + 8 * std::sin(x / 23 + y / 31);
  });
}

// The patches' plan (x, y) area, counter-clockwise positive, and how often each directed
// edge occurs.
struct Patches {
  double area = 0, smallest = 1e300;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
};
Patches tally(const terrain::GridMesh& m, const std::vector<std::uint32_t>& idx) {
  Patches p;
  for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
    const Eigen::Vector3f a = m.positions[idx[t]], b = m.positions[idx[t + 1]],
                          c = m.positions[idx[t + 2]];
    const double area = 0.5 * ((double(b.x()) - a.x()) * (double(c.y()) - a.y()) -
                               (double(b.y()) - a.y()) * (double(c.x()) - a.x()));
    p.area += area;
    p.smallest = std::min(p.smallest, area);
    for (int k = 0; k < 3; ++k)
      ++p.edges[{idx[t + std::size_t(k)], idx[t + std::size_t((k + 1) % 3)]}];
  }
  return p;
}

// Whether vertex v lies on the mesh's outer boundary.
bool on_rim(const terrain::GridTopology& g, std::uint32_t v) {
  const std::size_t r = v / g.cols, c = v % g.cols;
  return r == 0 || c == 0 || r + 1 == g.rows || c + 1 == g.cols;
}

}  // namespace

// All blocks at level 0 give the mesh's own faces. Any mix of levels (random, and every
// block one level apart from its neighbours' extremes, and with any blocks marked facing)
// covers the mesh's extent exactly once: every patch is counter-clockwise with positive area, the
// areas sum to the extent, and every edge inside the mesh is used once in each direction (an edge
// used once, a T-junction, would be a crack between two blocks).
TEST(Lod, AnyMixOfLevelsJoinsWithoutCracks) {
  const terrain::GridMesh m =
      bumps(150, 131);  // blocks of 16 cells: partial blocks at the right and bottom
  const renderer::LodHierarchy h = renderer::build_lod(m, 16);
  ASSERT_EQ(h.block_rows, 10u);  // 149 cells
  ASSERT_EQ(h.block_cols, 9u);   // 130 cells
  std::vector<std::uint8_t> zero(h.blocks.size(), 0);
  const auto full = renderer::lod_patches(h, zero);
  ASSERT_EQ(full.size(), 3 * m.n_faces());
  for (std::size_t f = 0; f < m.n_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(full[3 * f + std::size_t(k)], m.topo.face(f)[std::size_t(k)]);

  const double extent = 130 * 10.0 * 149 * 10.0;
  std::mt19937 rng(52);
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<std::uint8_t> levels(h.blocks.size());
    for (std::size_t k = 0; k < levels.size(); ++k) {
      const int top = h.blocks[k].levels() - 1;
      levels[k] = std::uint8_t(trial == 0   ? top
                               : trial == 1 ? (k % 2 ? top : 0)
                                            : int(rng() % std::uint32_t(top + 1)));
    }
    const auto idx = renderer::lod_patches(h, levels);
    const Patches p = tally(m, idx);
    // What the GPU holds without the whole mesh (lod_mesh): each block's level grid and no
    // more, so the vertices follow the levels (the coarsest: a block's four corners).
    const renderer::LodMesh lm = renderer::lod_mesh(h, levels);
    std::size_t grid = 0;
    for (std::size_t k = 0; k < levels.size(); ++k)
      grid += terrain::level_count(h.blocks[k].nr, levels[k]) *
              terrain::level_count(h.blocks[k].nc, levels[k]);
    EXPECT_EQ(lm.vertices.size(), grid);
    if (trial == 0) {
      EXPECT_EQ(lm.vertices.size(), 4 * h.blocks.size());
    }
    ASSERT_EQ(lm.patches.size(), idx.size());
    for (std::size_t k = 0; k < idx.size(); ++k) ASSERT_EQ(lm.vertices.at(lm.patches[k]), idx[k]);
    // Blocks marked facing (facing_blocks) only move their patches after the others: the
    // same patches, the first may_face_away of them those of the blocks not marked.
    std::vector<std::uint8_t> facing(h.blocks.size());
    for (auto& f : facing) f = std::uint8_t(rng() % 2);
    std::size_t away = 0;
    auto sorted = [](std::vector<std::uint32_t> v) {
      std::vector<std::array<std::uint32_t, 3>> t(v.size() / 3);
      for (std::size_t i = 0; i < t.size(); ++i) t[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
      std::sort(t.begin(), t.end());
      return t;
    };
    const auto ordered = renderer::lod_patches(h, levels, facing, &away);
    EXPECT_EQ(sorted(ordered), sorted(idx));
    EXPECT_GT(away, 0u);
    EXPECT_LT(away, ordered.size() / 3);
    EXPECT_LT(idx.size(), full.size());
    EXPECT_GT(p.smallest, 0.0) << "trial " << trial;
    EXPECT_NEAR(p.area, extent, 1e-6 * extent) << "trial " << trial;
    std::size_t once = 0;
    for (const auto& [e, n] : p.edges) {
      EXPECT_EQ(n, 1);
      const bool twin = p.edges.count({e.second, e.first}) > 0;
      if (!twin) {
        ++once;
        EXPECT_TRUE(on_rim(m.topo, e.first) && on_rim(m.topo, e.second))
            << "a crack at " << e.first << "-" << e.second;
      }
    }
    EXPECT_GT(once, 0u);
  }
}

// A plane's PN patches are the plane at every level: no error. On relief the error is zero
// at level 0, grows with the level, and the coarsest level of a block covers it with one
// cell.
TEST(Lod, ErrorsAreNoneOnAPlaneAndGrowWithTheLevel) {
  const terrain::GridMesh plane = terrain::test::function_mesh(
      70, 70, 10.0, [](double x, double y) { return 100 + 0.2 * x - 0.1 * y; });
  for (const auto& b : renderer::build_lod(plane, 32).blocks)
    for (float e : b.error) EXPECT_LT(e, 1e-3f);
  const renderer::LodHierarchy h = renderer::build_lod(bumps(129, 129), 32);  // 4 x 4 blocks
  for (const auto& b : h.blocks) {
    ASSERT_GE(b.levels(), 2);
    EXPECT_EQ(b.error[0], 0.0f);
    for (int l = 1; l < b.levels(); ++l)
      EXPECT_GE(b.error[std::size_t(l)], b.error[std::size_t(l - 1)]);
    EXPECT_GT(b.error.back(), 5.0f);
    EXPECT_GE(std::uint32_t(1) << (b.levels() - 1), std::max(b.nr, b.nc));
    EXPECT_LT(std::uint32_t(1) << (b.levels() - 2), std::max(b.nr, b.nc));
  }
}

// Seen along a long terrain of identical blocks (its relief repeats every block) from one
// end, blocks get coarser (never finer) with distance along the line of sight; bound 0
// keeps every block in view at level 0; blocks behind the eye are at their coarsest.
TEST(Lod, SelectionCoarsensWithDistance) {
  constexpr double kTwoPi = 2 * 3.141592653589793;
  const terrain::GridMesh m = terrain::test::function_mesh(65, 1025, 10.0, [=](double x, double y) {
    return 30 * std::sin(kTwoPi * x / 640) * std::cos(y / 70) +
           6 * std::sin(5 * kTwoPi * x / 640 + y / 31);
  });  // 16 blocks of 64 cells in a row
  const renderer::LodHierarchy h = renderer::build_lod(m);
  renderer::Camera cam;
  cam.view_az = 90;  // looking east along the row
  cam.view_alt = 20;
  cam.fov = 40;
  cam.eye = Vector3d(-200, -320, 150);
  renderer::Box box{{0, -640, -60}, {10240, 0, 600}};
  const renderer::View v = renderer::make_view(cam, Vector3d::Zero(), box, 1280, 720);
  const auto levels = renderer::select_lod(h, v, 1.0, 1.0);
  ASSERT_EQ(levels.size(), 16u);
  EXPECT_LE(levels.front(), 1);
  EXPECT_GE(levels.back(), levels.front() + 2);
  for (std::size_t k = 1; k < levels.size(); ++k) EXPECT_GE(levels[k], levels[k - 1]) << k;
  for (std::uint8_t l : renderer::select_lod(h, v, 1.0, 0.0)) EXPECT_EQ(l, 0);
  renderer::Camera away = cam;
  away.view_az = 270;  // looking west, away from the terrain
  away.eye = Vector3d(-300, -320, 100);
  const auto unseen = renderer::select_lod(
      h, renderer::make_view(away, Vector3d::Zero(), box, 1280, 720), 1.0, 1.0);
  for (std::size_t k = 0; k < unseen.size(); ++k) EXPECT_EQ(unseen[k], h.blocks[k].levels() - 1);
  // Raising the bound never makes a block finer.
  const auto coarse = renderer::select_lod(h, v, 1.0, 4.0);
  for (std::size_t k = 0; k < levels.size(); ++k) EXPECT_GE(coarse[k], levels[k]);
}

// A plane's slope is its gradient at every level (the vertex normals, the mid-edge
// coefficients, the corner planes and the cubic's samples are all the plane's); on relief
// the slopes are finite and positive.
TEST(Lod, SlopesOfAPlaneAreItsGradientAtEveryLevel) {
  const terrain::GridMesh plane = terrain::test::function_mesh(
      70, 70, 10.0, [](double x, double y) { return 100 + 0.2 * x - 0.1 * y; });
  for (const auto& b : renderer::build_lod(plane, 32).blocks) {
    ASSERT_EQ(b.slope.size(), b.error.size());
    for (float s : b.slope) EXPECT_NEAR(s, std::sqrt(0.05), 1e-5);
  }
  for (const auto& b : renderer::build_lod(bumps(129, 129), 32).blocks)
    for (float s : b.slope) EXPECT_TRUE(s > 0 && std::isfinite(s)) << s;
}

// A block faces the eye when the eye's elevation seen from anywhere in its box exceeds
// kFacingMargin (1.25) times its slope: a plane of gradient 0.5 over one block (640 m
// square, z up to 320 m) seen from 2000 m south of its northern edge, whose farthest top
// corner is 2025 m away in plan, faces an eye above 320 + 1.25 x 0.5 x 2025 = 1586 m, not
// one below; exaggerated twice, an eye above 640 + 1.25 x 1.0 x 2025 = 3172 m. From
// straight above (the orthographic map) it always faces.
TEST(Lod, ABlockFacesTheEyeAboveItsSlopeTimesTheMargin) {
  const terrain::GridMesh plane =
      terrain::test::function_mesh(65, 65, 10.0, [](double x, double) { return 0.5 * x; });
  const renderer::LodHierarchy h = renderer::build_lod(plane);
  ASSERT_EQ(h.blocks.size(), 1u);
  const renderer::Box box{{0, -640, 0}, {640, 0, 640}};
  auto view_from = [&](double height, bool orthographic = false) {
    renderer::Camera cam;
    cam.eye = Vector3d(320, -2000, height);
    cam.view_az = 0;
    cam.view_alt = 30;
    cam.orthographic = orthographic;
    if (orthographic) cam.view_alt = 90, cam.map_scale = 2;
    return renderer::make_view(cam, Vector3d::Zero(), box, 640, 480);
  };
  const std::vector<std::uint8_t> level0{0};
  EXPECT_EQ(renderer::facing_blocks(h, view_from(1600), 1.0, level0)[0], 1);
  EXPECT_EQ(renderer::facing_blocks(h, view_from(1570), 1.0, level0)[0], 0);
  EXPECT_EQ(renderer::facing_blocks(h, view_from(3190), 2.0, level0)[0], 1);
  EXPECT_EQ(renderer::facing_blocks(h, view_from(3150), 2.0, level0)[0], 0);
  EXPECT_EQ(renderer::facing_blocks(h, view_from(1000, true), 8.0, level0)[0], 1);
  // A plane has no error: every level fits, facing or not.
  EXPECT_EQ(renderer::select_lod(h, view_from(1570), 1.0, 0.25)[0], h.blocks[0].levels() - 1);
}

// What a level marked facing draws faces the eye: on relief seen obliquely from several
// sides, for every patch of the facing blocks (lod_patches' tail) the PN normal of a fine
// patch, and the cubic's geometric normal and its corners' plane for a coarse one, face the
// eye at every sampled point (exaggeration 1, where the slope measures what is drawn).
// The blocks marked facing are some, not all (15 and 38 of 64 at 3000 and 4000 m up), so
// both sides of the rule are exercised (3500 m up here). (The thin triangles of a cell snapped to a
// coarser neighbour, which lod_patches keeps among those that may face away, failed it.)
TEST(Lod, WhatALevelMarkedFacingDrawsFacesTheEye) {
  const terrain::GridMesh m = bumps(257, 257);
  const renderer::LodHierarchy h = renderer::build_lod(m, 32);
  const renderer::Box box{{0, -2560, -60}, {2560, 0, 200}};
  for (const double az : {0.0, 100.0, 215.0}) {
    renderer::Camera cam;
    const double a = az * 3.141592653589793 / 180;
    cam.eye = Vector3d(1280 - 3000 * std::sin(a), -1280 - 3000 * std::cos(a), 3500);
    cam.view_az = az;
    cam.view_alt = 35;
    const renderer::View v = renderer::make_view(cam, Vector3d::Zero(), box, 960, 540);
    const auto levels = renderer::select_lod(h, v, 1.0, 0.5, 6);
    const auto facing = renderer::facing_blocks(h, v, 1.0, levels);
    const auto marked = std::count(facing.begin(), facing.end(), std::uint8_t(1));
    EXPECT_GT(marked, 0) << az;
    EXPECT_LT(marked, std::ptrdiff_t(facing.size())) << az;
    std::size_t away = 0;
    const auto idx = renderer::lod_patches(h, levels, facing, &away);
    ASSERT_LT(away, idx.size() / 3);
    const double cell = 10 * std::sqrt(2.0) * 1.001;
    std::size_t checked = 0;
    for (std::size_t t = away; t < idx.size() / 3; ++t) {
      Vector3d p[3], n[3];
      for (std::size_t k = 0; k < 3; ++k) {
        p[k] = m.positions[idx[3 * t + k]].cast<double>();
        n[k] = m.normals[idx[3 * t + k]].cast<double>();
      }
      const bool coarse = std::max({(p[1] - p[0]).head<2>().norm(), (p[2] - p[1]).head<2>().norm(),
                                    (p[0] - p[2]).head<2>().norm()}) > cell;
      const terrain::PnPatch patch = terrain::make_pn_patch(p[0], p[1], p[2], n[0], n[1], n[2]);
      if (coarse) {
        EXPECT_GT((p[1] - p[0]).cross(p[2] - p[0]).dot(v.eye - p[0]), 0) << az << " patch " << t;
      }
      for (int i = 0; i <= 6; ++i)
        for (int j = 0; i + j <= 6; ++j) {
          const double b2 = i / 6.0, b3 = j / 6.0, b1 = 1 - b2 - b3;
          const Vector3d q = terrain::pn_position(patch, b1, b2, b3);
          Vector3d normal;
          if (coarse) {
            Vector3d ds, dt;
            terrain::pn_derivatives(patch, b1, b2, b3, ds, dt);
            normal = ds.cross(dt);
          } else {
            normal = terrain::pn_normal(patch, b1, b2, b3);
          }
          EXPECT_GT(normal.dot(v.eye - q), 0) << az << " patch " << t;
          ++checked;
        }
    }
    EXPECT_GT(checked, 1000u) << az;
  }
}

// The cells' cap: a map at 5 m a pixel of a 10 m mesh (cells of 14.1 m diagonal, 2.8 px)
// with any error bound draws no level coarser than 1 (5.7 px) under a 6 px cap, and its
// plane's coarsest without it.
TEST(Lod, NoLevelCoarserThanTheCellCap) {
  const terrain::GridMesh plane = terrain::test::function_mesh(
      129, 129, 10.0, [](double x, double y) { return 0.1 * x + 0.05 * y; });
  const renderer::LodHierarchy h = renderer::build_lod(plane);
  renderer::Camera cam;
  cam.eye = Vector3d(640, -640, 5000);
  cam.orthographic = true, cam.view_alt = 90, cam.view_az = 0, cam.map_scale = 5;
  const renderer::View v =
      renderer::make_view(cam, Vector3d::Zero(), {{0, -1280, 0}, {1280, 0, 200}}, 256, 256);
  for (const std::uint8_t l : renderer::select_lod(h, v, 1.0, 100, 6)) EXPECT_EQ(l, 1);
  for (const std::uint8_t l : renderer::select_lod(h, v, 1.0, 100)) EXPECT_EQ(l, 6);
}

// What terrain-view reads of a mesh over its memory bound (renderer/scene/scene.hpp): at the start
// and before each full frame, what terrain-render frame reads (hold_views for a Frame:
// a near view past the north-west corner of 5 x 5 blocks, the 2 x 2 blocks in view at level
// 0, 400 KB of the 1 MB bound; the whole level 0 takes 1.95 MB); nothing while what it holds
// serves the view; before a cheap frame whose view leaves those blocks (turned to look over
// the mesh), the whole mesh at the finest level within the bound (level 1, 490 KB); the
// full frame of that view then reads nothing (the whole of level 1 is what frame reads for
// it); back at the near view, its window again.
TEST(Lod, AViewerReadsTheBlocksInViewAndTheWholeMeshWhenTheViewLeavesThem) {
  const terrain::GridMesh mesh = bumps(300, 271);
  terrain::test::ScratchDir dir;
  terrain::write_mesh_ply(mesh, dir.path("m.ply"));
  terrain::write_mesh_pyramid(mesh, dir.path("m.tpyr"));
  const std::uint64_t bound = 1 << 20;
  renderer::Scene s = renderer::load_scene(dir.path("m.ply"), "", renderer::CreaseRules{}, bound);
  ASSERT_TRUE(s.deferred);
  EXPECT_EQ(s.mesh_level, 2);  // the preview, within a quarter of the bound
  renderer::Style style;
  renderer::Camera near;
  near.eye = Vector3d(500, -500, 200);
  near.view_az = 315;
  near.view_alt = 15;
  near.fov = 40;
  renderer::Camera over = near;
  over.view_az = 135;
  const int w = 480, h = 360;
  const std::string start = renderer::hold_views(s, {near}, w, h, style, renderer::HoldFor::Frame);
  EXPECT_NE(start.find("the blocks in view, rows 0 .. 1 and columns 0 .. 1 of 5 x 5, read"),
            std::string::npos)
      << start;
  ASSERT_TRUE(s.levels && s.levels->window);
  EXPECT_EQ(s.mesh_level, 0);
  EXPECT_EQ(s.mesh.n_vertices(), 129u * 129u);
  EXPECT_EQ(renderer::hold_views(s, {near}, w, h, style, renderer::HoldFor::StillView), "");
  EXPECT_EQ(renderer::hold_views(s, {near}, w, h, style, renderer::HoldFor::MovingView), "");
  const std::string left =
      renderer::hold_views(s, {over}, w, h, style, renderer::HoldFor::MovingView);
  EXPECT_NE(left.find("the view left the blocks held: mesh read at level 1"), std::string::npos)
      << left;
  EXPECT_FALSE(s.levels->window);
  EXPECT_EQ(s.mesh_level, 1);
  EXPECT_EQ(renderer::hold_views(s, {over}, w, h, style, renderer::HoldFor::StillView), "");
  EXPECT_EQ(renderer::hold_views(s, {over}, w, h, style, renderer::HoldFor::MovingView),
            "");  // whole: nothing to leave
  const std::string back =
      renderer::hold_views(s, {near}, w, h, style, renderer::HoldFor::StillView);
  EXPECT_NE(back.find("the view came nearer: mesh read at level 0"), std::string::npos) << back;
  ASSERT_TRUE(s.levels->window);
  EXPECT_EQ(s.mesh.n_vertices(), 129u * 129u);
}

// What a scene holds against the whole mesh (MeshHolding): the whole mesh, a coarser level
// of its pyramid and a window of it (blocks 1..2 x 2..3 of 5 x 5) answer the same whole
// extent, spacing and box; the window's extent is the whole's seen from the window's first
// vertex, and its blocks are the ones read.
TEST(Lod, AHeldPartAnswersForTheWholeMesh) {
  const terrain::GridMesh mesh = bumps(300, 271);
  terrain::test::ScratchDir dir;
  terrain::write_mesh_ply(mesh, dir.path("m.ply"));
  terrain::write_mesh_pyramid(mesh, dir.path("m.tpyr"));
  const auto read = [&](terrain::PyramidPart part) {
    std::string why;
    auto p = terrain::read_mesh_via_pyramid(dir.path("m.ply"), why,
                                            [&](const terrain::MeshPyramid&) { return part; });
    EXPECT_TRUE(p) << why;
    return std::move(*p);
  };
  const renderer::LodHierarchy own = renderer::build_lod(mesh);
  const renderer::MeshHolding whole(mesh, &own);
  const terrain::PyramidMesh coarse = read(1), window = read({0, 1, 2, 3, 4});
  const renderer::MeshHolding held_coarse(coarse.mesh, &coarse.levels),
      held_window(window.mesh, &window.levels);
  EXPECT_FALSE(whole.part());
  EXPECT_TRUE(held_coarse.part() && !held_coarse.window());
  EXPECT_TRUE(held_window.part() && held_window.window());
  const renderer::Box box = whole.box(2.0);
  for (const renderer::MeshHolding* h : {&held_coarse, &held_window}) {
    const terrain::GridMesh g = h->whole_grid();  // the whole's extent
    EXPECT_NEAR(double(g.topo.rows - 1) * g.geo.dy, double(mesh.topo.rows - 1) * mesh.geo.dy, 1e-9);
    EXPECT_NEAR(double(g.topo.cols - 1) * g.geo.dx, double(mesh.topo.cols - 1) * mesh.geo.dx, 1e-9);
    EXPECT_EQ(g.geo.origin_x, mesh.geo.origin_x);
    EXPECT_EQ(g.geo.origin_y, mesh.geo.origin_y);
    EXPECT_DOUBLE_EQ(h->fine_spacing().x(), mesh.geo.dx);
    EXPECT_DOUBLE_EQ(h->fine_spacing().y(), mesh.geo.dy);
    const renderer::Box b = h->box(2.0);
    EXPECT_LT((b.hi - b.lo - (box.hi - box.lo)).norm(), 1e-3);
  }
  const Eigen::Vector2d o = held_window.window_origin();
  EXPECT_DOUBLE_EQ(o.x(), 2.0 * renderer::kLodBlock * mesh.geo.dx);
  EXPECT_DOUBLE_EQ(o.y(), -1.0 * renderer::kLodBlock * mesh.geo.dy);
  const Eigen::Vector4f e = whole.local_extent(), w = held_window.local_extent();
  EXPECT_NEAR(w[0], e[0] - o.x(), 1e-2);
  EXPECT_NEAR(w[1], e[1] - o.y(), 1e-2);
  EXPECT_NEAR(w[2], e[2] - o.x(), 1e-2);
  EXPECT_NEAR(w[3], e[3] - o.y(), 1e-2);
  const renderer::BlockRange r = held_window.held_blocks(own);
  EXPECT_EQ(r.br0, 1u);
  EXPECT_EQ(r.bc0, 2u);
  EXPECT_EQ(r.br1, 3u);
  EXPECT_EQ(r.bc1, 4u);
  EXPECT_EQ(whole.held_blocks(own).br1, own.block_rows);
}
