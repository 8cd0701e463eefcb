// renderer/gl/src/terrain_renderer.cpp and its passes on the machine's OpenGL through EGL
// (llvmpipe in CI): the renderer against CPU references and synthetic scenes whose answers
// are known. (The GL-free parts' tests mirror their sources: view/, lines/, gl/.)
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include <map>
#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/pipeline.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/feature_edges.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/line_stats.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/core/pel.hpp"
#include "renderer/core/silhouette.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/timing.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/shader.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"
#include "terrain/pn_surface.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector3d;
using renderer::CreaseGeometry;
using renderer::FrameParams;
using renderer::TerrainRenderer;

// ---------------------------------------------------------------- scenes

// Hills of several wavelengths on a tilt, 299 x 270 cells of 10 m: 5 x 5 blocks of levels
// of detail, the last row and column of them partial.
terrain::GridMesh bumpy_blocks() {
  return terrain::test::function_mesh(300, 271, 10.0, [](double x, double y) {
    return 0.05 * x + 40 * std::sin(x / 90) * std::cos(y / 70) + 8 * std::sin(x / 23 + y / 31);
  });
}

// Pixel-exact lines: the tests below count pixels of exactly the line colour.
renderer::Style test_style() {
  renderer::Style s;
  s.antialias = false;
  // The score law alone: these tests count the segments the score accepts (the stroke
  // rule has its own tests below).
  s.crease_bridge = s.crease_bridge_px = 0;
  s.crease_min_stroke = s.crease_min_stroke_px = 0;
  s.page_min_area = 0;
  s.background = {1, 1, 1};
  s.crease_colour = {1, 0, 0};
  s.silhouette_colour = {0, 0, 0};
  // The Toward/Away rule alone (formulated silhouettes have tests of their own).
  s.formulated = false;
  return s;
}

std::size_t count_colour(const renderer::FrameResult& r, std::uint8_t red, std::uint8_t green,
                         std::uint8_t blue) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < r.rgba.size(); i += 4)
    n += r.rgba[i] == red && r.rgba[i + 1] == green && r.rgba[i + 2] == blue;
  return n;
}

// A crop of the Mount St. Helens DEM (real data) as a mesh, and its drainage at 5 m.
struct MshScene {
  terrain::GridMesh mesh;
  terrain::DrainageLinks links;  // of the .dv written and read back
};
const MshScene& msh_scene() {
  static const MshScene scene = [] {
    const terrain::Grid dem = terrain::read_dem(terrain::test::data("msh_2007_utm10n_10m.tif"));
    const std::size_t r0 = 150, c0 = 100, n = 64;
    terrain::Georef geo = dem.geo;
    geo.x0 += double(c0) * geo.dx;
    geo.y0 -= double(r0) * geo.dy;
    terrain::Grid crop(n, n, geo);
    for (std::size_t r = 0; r < n; ++r)
      for (std::size_t c = 0; c < n; ++c) crop.at(r, c) = dem.at(r0 + r, c0 + c);
    MshScene s;
    s.mesh = terrain::make_grid_mesh(crop, terrain::NormalWeighting::Uniform);
    const auto sampled = terrain::sample_pn_surface(s.mesh, 5.0);
    const auto result = drainage::compute_drainage(sampled.grid, {});
    terrain::test::ScratchDir dir;
    const auto header =
        drainage::make_dv_header(result.surface, result.net, result.dv_flags, "test");
    drainage::write_dv(dir.path("msh.dv"), header, result.surface, result.dirs, result.net);
    s.links = drainage::drainage_links(drainage::read_dv(dir.path("msh.dv")));
    return s;
  }();
  return scene;
}

// ---------------------------------------------------------------- on OpenGL

// What the renderer refuses before it allocates anything: a size outside the option
// table's frame limits, PELs without Voronoi weights. At the limits themselves it draws.
TEST(RendererGl, RefusesWhatItCannotDrawAndDrawsAtTheLimits) {
  const auto& mesh = msh_scene().mesh;
  renderer::GlContext ctx;
  auto message = [&](const terrain::GridMesh& m, int w, int h,
                     const renderer::Layers& layers) -> std::string {
    try {
      TerrainRenderer r(ctx, m, nullptr, w, h, layers, test_style());
      return {};
    } catch (const terrain::Error& e) {
      return e.what();
    }
  };
  const renderer::Layers plain{};
  for (const auto& [w, h] :
       {std::pair{renderer::kMinFrameSide - 1, 64}, std::pair{64, renderer::kMaxFrameSide + 1}})
    EXPECT_NE(message(mesh, w, h, plain).find("is outside"), std::string::npos) << w << " x " << h;
  EXPECT_EQ(message(mesh, renderer::kMinFrameSide, renderer::kMinFrameSide, plain), "");
  renderer::Layers pels = plain;
  pels.pels = true;
  ASSERT_TRUE(mesh.voronoi.empty());
  EXPECT_NE(message(mesh, 64, 64, pels).find("Voronoi"), std::string::npos);
}

TEST(RendererGl, GlslPnEvaluationMatchesCpu) {
  const auto& mesh = msh_scene().mesh;
  renderer::GlContext ctx;
  TerrainRenderer r(ctx, mesh, nullptr, 64, 64, renderer::Layers{}, test_style());
  std::vector<std::uint32_t> faces;
  for (std::uint32_t f = 0; f < mesh.n_faces(); f += 37) faces.push_back(f);
  const auto samples = r.capture_pn(faces, 3);
  ASSERT_GT(samples.size(), faces.size() * 9 * 3);  // level 3: at least 9 triangles per patch
  std::vector<int> per_face(mesh.n_faces());
  for (const auto& s : samples) ++per_face.at(s.face);
  for (const auto f : faces) EXPECT_EQ(per_face[f], int(samples.size() / faces.size()));
  // Scale of the positions: the mesh's extent (local coordinates, metres).
  double scale = 0;
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i)
    scale = std::max(scale, double(mesh.positions[i].norm()));
  double max_pos = 0, max_nrm = 0;
  for (const auto& s : samples) {
    ASSERT_LT(s.face, mesh.n_faces());
    ASSERT_NEAR(s.b1 + s.b2 + s.b3, 1.0, 1e-6);
    const terrain::PnPatch patch = terrain::face_patch(mesh, s.face);
    const Vector3d p = terrain::pn_position(patch, s.b1, s.b2, s.b3);
    const Vector3d n = terrain::pn_normal(patch, s.b1, s.b2, s.b3);
    max_pos = std::max(max_pos, (s.position.cast<double>() - p).norm() / scale);
    max_nrm = std::max(max_nrm, (s.normal.cast<double>() - n).norm());
  }
  EXPECT_LT(max_pos, 1e-5);
  EXPECT_LT(max_nrm, 1e-5);
}

// Ridge z = H exp(-(y - yr)^2 / 2 s^2) running east-west on a plain 4 km deep; the eye,
// 900 m south of the crest, looks north, level. The Toward/Away silhouette must sit where
// the tangent from the eye touches the ridge: image row = h/2 - f * max (z(y) - z_eye) /
// (y - y_eye) over the ridge, f = (h/2) / tan(fov/2), the same in every column (the ridge
// is uniform in x and the view is level). Below the crest that is the skyline; above it,
// the ridge's occluding edge against the plain behind (seen above the ridge up to the
// plain's far edge, which is no silhouette: no away surface there).
struct RidgeCase {
  double eye_z;
  bool adjacency;          // the Adjacency method instead of Toward/Away
  bool antialias = false;  // Toward/Away anti-aliased: gaps closed, specks dropped
};
class RidgeSilhouette : public ::testing::TestWithParam<RidgeCase> {};

// The ridge's silhouette lies where the tangent from the eye predicts: every image column
// has its silhouette pixel within 1.5 px (Toward/Away) or 2 px (Adjacency) of that row;
// Toward/Away has none elsewhere, Adjacency at most one per column on average.
TEST_P(RidgeSilhouette, WhereProjectionPredicts) {
  const double H = 200, s = 100, yr = -3000, h = 20;
  auto z = [&](double, double y) { return H * std::exp(-0.5 * (y - yr) * (y - yr) / (s * s)); };
  const auto mesh = terrain::test::function_mesh(201, 101, h, z);  // x 0..2000, y -4000..0
  renderer::GlContext ctx;
  renderer::Layers layers{false, true, false, true};
  layers.adjacency = GetParam().adjacency;
  renderer::Style style = test_style();
  style.antialias = GetParam().antialias;
  TerrainRenderer r(ctx, mesh, nullptr, 320, 240, layers, style);
  FrameParams fp;
  const Vector3d eye(1000, -3900, GetParam().eye_z);
  fp.camera.eye = eye;
  fp.camera.view_az = 0;
  fp.camera.view_alt = 0;
  fp.camera.fov = 30;
  r.render(fp);
  const auto b = r.read_buffers();
  double best = -1e9;
  for (double y = yr - 4 * s; y <= yr + 4 * s; y += 0.25)
    best = std::max(best, (z(0, y) - eye.z()) / (y - eye.y()));
  const double f = 120 / std::tan(15 * std::numbers::pi / 180);
  const double row = 120 - f * best;  // in pixel units from the top edge
  const double tolerance = GetParam().adjacency ? 2.0 : 1.5;
  std::size_t near_line = 0, elsewhere = 0, columns_hit = 0;
  for (int c = 0; c < 320; ++c) {
    bool hit = false;
    for (int rr = 0; rr < 240; ++rr) {
      if (!b.silhouette[std::size_t(rr) * 320 + std::size_t(c)]) continue;
      if (std::abs(rr + 0.5 - row) <= tolerance) {
        ++near_line;
        hit = true;
      } else {
        ++elsewhere;
      }
    }
    columns_hit += hit;
  }
  EXPECT_EQ(columns_hit, 320u) << "predicted row " << row;
  if (GetParam().adjacency) {
    // Spurious pixels where pixel neighbours skip thin tessellated triangles (the method's
    // known failure; docs/terrain-render.md): counted, bounded.
    std::printf("adjacency: %zu silhouette pixels off the predicted row\n", elsewhere);
    EXPECT_LE(elsewhere, 320u);
  } else {
    EXPECT_EQ(elsewhere, 0u);
  }
  EXPECT_LE(near_line, 2u * 320u);
}
INSTANTIATE_TEST_SUITE_P(
    SkylineAndOccludingEdge, RidgeSilhouette,
    ::testing::Values(RidgeCase{100.0, false},  // below the crest: the skyline
                      RidgeCase{400.0, false},  // above: the ridge against the plain behind
                      RidgeCase{100.0, true}, RidgeCase{400.0, true}, RidgeCase{100.0, false, true},
                      RidgeCase{400.0, false, true}),
    [](const auto& info) {
      return std::string(info.param.eye_z < 200 ? "Skyline" : "OccludingEdge") +
             (info.param.adjacency ? "Adjacency" : "TowardAway") +
             (info.param.antialias ? "Antialiased" : "");
    });

// The anti-aliased silhouette tests' terrain and view: ridges z = height exp(-(y - yr -
// k (x - 1000))^2 / 2 s^2), s = 100 m, k = 0.15 (crests about 8.5 degrees off the image's
// rows), summed, sampled every 20 m (x 0..2000, y -4000..0), seen level looking north from
// (1000, -3900, 100), fov 30, 320 x 240, silhouettes anti-aliased, black on white.
struct SlantedRidges {
  static constexpr int W = 320, H = 240;
  std::vector<std::pair<double, double>> ridges;  // (yr, height) of each
  const Vector3d eye{1000, -3900, 100};
  const double f = 120 / std::tan(15 * std::numbers::pi / 180);  // pixels per unit of slope

  renderer::Style style() const {
    renderer::Style st = test_style();
    st.antialias = true;
    return st;
  }
  double z(double x, double y) const {
    double sum = 0;
    for (const auto& [yr, height] : ridges) {
      const double d = y - yr - 0.15 * (x - 1000);
      sum += height * std::exp(-0.5 * d * d / (100.0 * 100.0));
    }
    return sum;
  }
  // The row (from the top) of the tangent from the eye to the terrain in image column c,
  // over distances 100 m to t1 along the column's ray.
  double tangent_row(double c, double t1) const {
    const double a = (c + 0.5 - W / 2.0) / f;
    double best = -1e9;
    for (double t = 100; t <= t1; t += 0.25)
      best = std::max(best, (z(eye.x() + a * t, eye.y() + t) - eye.z()) / t);
    return H / 2.0 - f * best;
  }
  // The frame (RGBA) and its silhouette mask.
  std::pair<renderer::FrameResult, std::vector<std::uint8_t>> render() const {
    const auto mesh =
        terrain::test::function_mesh(201, 101, 20, [this](double x, double y) { return z(x, y); });
    renderer::GlContext ctx;
    TerrainRenderer r(ctx, mesh, nullptr, W, H, renderer::Layers{false, true, false, true},
                      style());
    FrameParams fp;
    fp.camera.eye = eye;
    fp.camera.view_az = 0;
    fp.camera.view_alt = 0;
    fp.camera.fov = 30;
    auto res = r.render(fp);
    return {std::move(res), r.read_buffers().silhouette};
  }
};

// Anti-aliased silhouettes are drawn as a band of even width, not as the pixel staircase
// of the mask: a ridge whose crest runs about 8.5 degrees off the image's rows (z = H
// exp(-(y - yr - k (x - 1000))^2 / 2 s^2), k = 0.15), seen level from the south below its
// crest, in black on white. Per column, the coverage-weighted centre of the drawn
// silhouette lies within 1.5 px of the row the tangent from the eye predicts (as
// RidgeSilhouette, per column: row = h/2 - f max_t (z(x_eye + a t, y_eye + t) - z_eye) / t,
// a = the column's offset over f), and the column's coverage is the band's ideal area
// there, (width + 0.8) / cos(slope of the predicted row): within 5 % on average and 15 % in
// every column (the dilation and ring drawn before gave 2.8 px in the columns where the
// mask steps, 1.85 px on average).
TEST(RendererGl, AntialiasedSilhouetteIsABandOfEvenWidth) {
  const SlantedRidges view{.ridges = {{-3000, 200}}};
  const renderer::FrameResult res = view.render().first;
  const int W = view.W, Hh = view.H;
  auto predicted_row = [&](double c) { return view.tangent_row(c, 3000); };
  const renderer::Style style = view.style();
  const double width = style.silhouette_width + 0.8;
  double sum_ratio = 0, worst = 0;
  int n = 0;
  for (int c = 20; c < W - 20; ++c) {  // away from the ridge's ends at the mesh's sides
    const double predicted = predicted_row(c),
                 slope = (predicted_row(c + 1) - predicted_row(c - 1)) / 2;
    double cover = 0, moment = 0;
    for (int rr = 0; rr < Hh; ++rr) {
      const double cov = 1.0 - res.rgba[4 * (std::size_t(rr) * W + std::size_t(c))] / 255.0;
      cover += cov;
      moment += cov * (rr + 0.5);
    }
    ASSERT_GT(cover, 0.5) << "column " << c;
    EXPECT_NEAR(moment / cover, predicted, 1.5) << "column " << c;
    const double ratio = cover / (width * std::sqrt(1 + slope * slope));
    sum_ratio += ratio;
    worst = std::max(worst, std::abs(ratio - 1));
    ++n;
  }
  std::printf("silhouette band: coverage / ideal area %.3f on average, %.1f %% off at worst\n",
              sum_ratio / n, 100 * worst);
  EXPECT_NEAR(sum_ratio / n, 1.0, 0.05);
  EXPECT_LT(worst, 0.15);
}

// Two silhouettes a few pixels apart are two bands, not one grey blur: ridge A (as in
// AntialiasedSilhouetteIsABandOfEvenWidth) and behind it a higher ridge B, parallel, whose
// skyline the eye sees 2.5 to 3.5 px above A's occluding edge. In every column the mask
// holds the two lines, B's pixels above A's with a gap of one or two rows, each within 2 px
// of the row the tangent from the eye predicts (B lies 1900 m away, where a pixel is 4 m
// and the tessellated crest sags below the analytic one); so does each side's ink-weighted
// centre. The column's ink is two bands' ideal area, 2 (width + 0.8) / cos(slope): within
// 15 % in every column and 5 % on average. A 7 x 7 window there holds both lines, and a
// line fitted to all its pixels is no line: before lines were told apart, the pixels
// between got a disc about the nearest pixel, or a band about a line through both, and the
// columns carried 0.87 of the ink on average, 27 % off at worst (the sliver dotted).
TEST(RendererGl, AntialiasedSilhouettesCloseTogetherAreTwoBands) {
  const SlantedRidges view{.ridges = {{-3000, 200}, {-2000, 323}}};  // A, and B behind it
  const auto [res, mask] = view.render();
  const int W = view.W, Hh = view.H;
  const renderer::Style style = view.style();
  const double width = style.silhouette_width + 0.8;
  double sum_ratio = 0, worst = 0;
  int n = 0;
  for (int c = 20; c < W - 20; ++c) {
    // A's occluding edge in front of the saddle between the ridges (t < 1400), the skyline over
    // all.
    const double row_a = view.tangent_row(c, 1400), row_b = view.tangent_row(c, 3000);
    ASSERT_GT(row_a - row_b, 2.5) << "column " << c;
    ASSERT_LT(row_a - row_b, 3.5) << "column " << c;
    std::vector<int> rows;
    for (int rr = 0; rr < Hh; ++rr)
      if (mask[std::size_t(rr) * W + std::size_t(c)]) rows.push_back(rr);
    // The two lines: the mask's pixels in the column either side of its one gap.
    std::size_t gaps = 0, split = 0;
    for (std::size_t i = 1; i < rows.size(); ++i)
      if (rows[i] - rows[i - 1] > 1) ++gaps, split = i;
    ASSERT_EQ(gaps, 1u) << "column " << c;
    ASSERT_LE(rows[split] - rows[split - 1], 3) << "column " << c;
    for (std::size_t i = 0; i < rows.size(); ++i)
      EXPECT_NEAR(rows[i] + 0.5, i < split ? row_b : row_a, 2.0)
          << "column " << c << " row " << rows[i];
    const double mid =
        0.5 * (rows[split - 1] + rows[split]);  // the gap's middle, a row or a border
    const double slope = (view.tangent_row(c + 1, 1400) - view.tangent_row(c - 1, 1400)) / 2;
    // The column's ink against two bands' ideal area; each line's ink-weighted centre (the
    // gap's middle row, shared, left out) within 2 px of its predicted row.
    double ink = 0, cover[2] = {0, 0}, moment[2] = {0, 0};
    for (int rr = 0; rr < Hh; ++rr) {
      const double cov = 1.0 - res.rgba[4 * (std::size_t(rr) * W + std::size_t(c))] / 255.0;
      ink += cov;
      if (rr == mid) continue;
      cover[rr < mid ? 0 : 1] += cov;
      moment[rr < mid ? 0 : 1] += cov * (rr + 0.5);
    }
    EXPECT_NEAR(moment[0] / cover[0], row_b, 2.0) << "column " << c;
    EXPECT_NEAR(moment[1] / cover[1], row_a, 2.0) << "column " << c;
    const double ratio = ink / (2 * width * std::sqrt(1 + slope * slope));
    sum_ratio += ratio;
    worst = std::max(worst, std::abs(ratio - 1));
    ++n;
  }
  std::printf("two silhouettes: band coverage / ideal area %.3f on average, %.1f %% off at worst\n",
              sum_ratio / n, 100 * worst);
  EXPECT_NEAR(sum_ratio / n, 1.0, 0.05);
  EXPECT_LT(worst, 0.15);
}

TEST(RendererGl, FlatPlaneFromAboveHasNoSilhouette) {
  const auto mesh = terrain::test::function_mesh(41, 41, 25, [](double, double) { return 100.0; });
  renderer::GlContext ctx;
  for (const bool adjacency : {true, false}) {  // the Adjacency method first; then the checks below
    renderer::Layers layers{false, true, false, true};
    layers.adjacency = adjacency;
    TerrainRenderer adj(ctx, mesh, nullptr, 200, 200, layers, test_style());
    FrameParams top;
    top.camera.view_alt = 90;
    adj.render(top);
    const auto ab = adj.read_buffers();
    EXPECT_EQ(std::count(ab.silhouette.begin(), ab.silhouette.end(), 1), 0)
        << "adjacency " << adjacency;
  }
  TerrainRenderer r(ctx, mesh, nullptr, 200, 200, renderer::Layers{false, true, false, true},
                    test_style());
  FrameParams fp;
  fp.camera.view_alt = 90;
  const auto res = r.render(fp);
  const auto b = r.read_buffers();
  EXPECT_EQ(std::count(b.silhouette.begin(), b.silhouette.end(), 1), 0);
  EXPECT_GT(count_colour(res, 255, 255, 255), 0u);
  // The plane covers most of the image (framed) and is toward-facing everywhere.
  std::size_t covered = 0;
  for (float d : b.toward_depth) covered += d > 0.0f;
  EXPECT_GT(covered, 200u * 200u / 3);
}

// Level from the south of a 201 x 101 mesh at 20 m (function_mesh: x 0..4000, y -2000..0),
// 250 m up, every crease accepted (min score 0, no distance term).
// A line's ink at pixel (u, v) of a W-wide frame: how far the line moved the green channel
// from the frame drawn without it.
double ink_at(const renderer::FrameResult& res, const renderer::FrameResult& bare, int W, int u,
              int v) {
  const std::size_t i = 4 * (std::size_t(v) * std::size_t(W) + std::size_t(u));
  return std::abs(double(res.rgba[i + 1]) - double(bare.rgba[i + 1]));
}

FrameParams level_view_from_the_south() {
  FrameParams fp;
  fp.camera.eye = Vector3d(1000, -3800, 250);
  fp.camera.view_az = 0;
  fp.camera.view_alt = 0;
  fp.camera.fov = 40;
  fp.score.min_score = 0;
  fp.score.falloff = 0;
  return fp;
}

// A channel along the floor of an east-west valley; a higher ridge between the eye and
// the valley hides it; without the ridge, or from above, it shows. The line statistics
// count none of the hidden channel's pixels, pixel-exact or anti-aliased: each segment is
// tested by its own depth (visible_fraction). With a line drawn up the ridge's face across
// where the hidden channel projects (k = 3), the channel still counts nothing, although
// that line's ink covers the channel's pixels there: the rule before stop 33 counted a
// segment's pixels wherever crease ink lay within a pixel of them, and for pixel-exact
// lines that ink was the whole layer, hidden lines and all (the composite removes them),
// which the renderer before issue 13 measured.
TEST(RendererGl, RidgeHidesTheValleyCreases) {
  auto terrain_fn = [](double ridge) {
    return [ridge](double, double y) {
      return ridge * std::exp(-0.5 * std::pow((y + 3000) / 100, 2)) -
             50 * std::exp(-0.5 * std::pow((y + 2000) / 400, 2));
    };
  };
  // The channel (x from 300 to 1700 along y = -2000), and with `crossing` a line up the
  // ridge's face at x = 1000 after it.
  auto creases_on = [](const terrain::GridMesh& mesh, bool crossing) {
    CreaseGeometry g;
    auto line = [&](Vector3d from, Vector3d step, int n) {
      const std::uint32_t first = std::uint32_t(g.positions.size());
      for (int i = 0; i < n; ++i) {
        const Vector3d q = from + double(i) * step;
        const auto sp = terrain::pn_point_above(mesh, q.x(), q.y());
        g.positions.push_back(sp->position.cast<float>());
        g.normals.push_back(sp->normal.cast<float>());
        g.flow.push_back(float(i + 1) / float(n));
        g.share.push_back(g.flow.back());
        if (i > 0)
          g.segments.insert(g.segments.end(),
                            {first + std::uint32_t(i) - 1, first + std::uint32_t(i)});
      }
    };
    line(Vector3d(300, -2000, 0), Vector3d(20, 0, 0), 71);
    if (crossing) line(Vector3d(1000, -3400, 0), Vector3d(0, 10, 0), 41);
    return g;
  };
  constexpr std::size_t kChannel = 70;  // its segments come first
  // The share of the pixels of segments [first, last) that show, weighted by length.
  auto shown = [](const CreaseGeometry& g, const renderer::View& view, const std::vector<double>& f,
                  std::size_t first, std::size_t last) {
    const auto px = renderer::segment_pixels(g, view, 1.0);
    double all = 0, seen = 0;
    for (std::size_t s = first; s < last; ++s) all += px[s], seen += px[s] * f[s];
    return all > 0 ? seen / all : -1.0;
  };
  const FrameParams fp = level_view_from_the_south();
  renderer::GlContext ctx;
  const renderer::Layers layers{false, true, true, false};
  for (const bool antialias : {false, true}) {
    renderer::Style style = test_style();
    style.antialias = antialias;
    style.lod_error = 0;  // the lines' own segments, not a coarser level's (kChannel counts them)
    std::size_t pixels[3] = {};
    for (int k = 0; k < 4; ++k) {
      const auto mesh =
          terrain::test::function_mesh(201, 101, 20, terrain_fn(k == 0 || k == 3 ? 500.0 : 0.0));
      const auto g = creases_on(mesh, k == 3);
      TerrainRenderer r(ctx, mesh, &g, 320, 240, layers, style);
      FrameParams f = fp;
      if (k == 2) {  // from above
        f.camera.eye.reset();
        f.camera.view_alt = 90;
      }
      const auto res = r.render(f);
      EXPECT_EQ(res.crease_segments, g.n_segments());       // all drawn by DM ...
      if (k < 3) pixels[k] = count_colour(res, 255, 0, 0);  // ... but visible only where not hidden
      const auto fraction =
          renderer::visible_fraction(g, res.view, 1.0, renderer::crease_lift(style, mesh),
                                     r.read_buffers().toward_depth, antialias);
      const double channel = shown(g, res.view, fraction, 0, kChannel);
      if (antialias && (k == 0 || k == 3)) {  // nor drawn by the samples along its stroke
        const auto samples = r.read_crease_samples();
        for (std::size_t s = 0; s < kChannel; ++s)
          EXPECT_EQ(samples[s].shown, 0u) << "view " << k << " segment " << s;
      }
      if (k == 0 || k == 3) {
        EXPECT_EQ(channel, 0.0) << "antialias " << antialias << " view " << k
                                << ": hidden creases measured as drawn";
      } else {
        EXPECT_GT(channel, 0.95) << "antialias " << antialias << " view " << k;
      }
      if (k != 3) continue;
      EXPECT_GT(shown(g, res.view, fraction, kChannel, g.n_segments()), 0.95)
          << "antialias " << antialias;
      // The crossing line's ink lies on the hidden channel's projection.
      const auto q = renderer::project(res.view, g.positions[35].cast<double>());  // x = 1000
      int ink = 0;  // the most, of the pixel and its neighbours in the row
      for (int du = -1; du <= 1; ++du)
        ink = std::max(
            ink,
            255 - int(res.rgba[4 * (std::size_t(q.v) * 320 + std::size_t(int(q.u) + du)) + 1]));
      EXPECT_GT(ink, 200) << "antialias " << antialias
                          << ": no crease ink where the channel projects";
    }
    if (antialias) continue;  // the pixel counts below are of exactly the line colour
    EXPECT_EQ(pixels[0], 0u) << "creases behind the ridge are visible";
    EXPECT_GT(pixels[1], 100u);
    EXPECT_GT(pixels[2], 100u);
  }
}

// Lines are drawn where they lie on the surface: the lift (crease_lift) moves a line's
// points towards the eye along their lines of sight, so it changes only their depth, so
// that the tessellated surface does not hide them, not where they show. A level plane seen
// from its south at a grazing angle with a line across it: lifted 1 m or 150 m, its ink
// lies on the projection of its points (row centroid within 0.6 px in
// every column, anti-aliased; before the anti-aliased lines took their depth test at
// their spine, the surface in front hid their near half on this grazing view, 0.94 px off,
// as it still does for pixel-exact lines lifted 1 m, which take it per pixel: within 1
// px), and anti-aliased, it is the same at both lifts (within 2 of 255). Lifted along the
// normal as before stop 31, 150 m carried every pixel of the line past the plane's far
// edge into the sky. Where no surface lies behind a line (a second line past the far edge)
// nothing is drawn: no pixel off the surface changes.
TEST(RendererGl, CreasesAreDrawnWhereTheyLieOnTheSurface) {
  const auto mesh = terrain::test::function_mesh(201, 101, 20, [](double, double) { return 0.0; });
  CreaseGeometry g;
  const double far_y = -1000;
  for (const double y : {far_y, 400.0})  // the second past the far edge (y = 0)
    for (double x = 300; x <= 1700; x += 20) {
      g.positions.emplace_back(float(x), float(y), 0.0f);
      g.normals.emplace_back(0.0f, 0.0f, 1.0f);
      g.flow.push_back(1.0f);
      g.share.push_back(1.0f);
    }
  const std::uint32_t per_line = std::uint32_t(g.positions.size() / 2);
  for (std::uint32_t i = 0; i + 1 < g.positions.size(); ++i)
    if ((i + 1) % per_line != 0) g.segments.insert(g.segments.end(), {i, i + 1});
  const FrameParams fp = level_view_from_the_south();
  const int W = 320, H = 240;
  renderer::GlContext ctx;
  for (const bool antialias : {false, true}) {
    renderer::Style style = test_style();
    style.antialias = antialias;
    style.mask = {0.5f, 0.5f, 0.5f};
    const auto bare = TerrainRenderer(ctx, mesh, nullptr, W, H,
                                      renderer::Layers{false, true, false, false}, style)
                          .render(fp);
    std::vector<std::uint8_t> first;
    for (const double lift : {1.0, 150.0}) {
      style.crease_lift = lift;
      TerrainRenderer r(ctx, mesh, &g, W, H, renderer::Layers{false, true, true, false}, style);
      const auto res = r.render(fp);
      EXPECT_EQ(res.crease_segments, g.n_segments());  // all selected by DM
      std::size_t sky_changed = 0, surface_changed = 0;
      for (std::size_t i = 0; i < res.rgba.size(); i += 4) {
        const bool sky = bare.rgba[i] == 255, changed = res.rgba[i + 1] != bare.rgba[i + 1];
        (sky ? sky_changed : surface_changed) += changed;
      }
      EXPECT_EQ(sky_changed, 0u) << "antialias " << antialias << " lift " << lift;
      EXPECT_GT(surface_changed, 100u) << "antialias " << antialias << " lift " << lift;
      // The line's ink, column by column, about the projection of its points.
      const auto p0 = renderer::project(res.view, Vector3d(300, far_y, 0));
      const auto p1 = renderer::project(res.view, Vector3d(1700, far_y, 0));
      int columns = 0;
      std::vector<std::uint8_t> window;  // the line's rows, anti-aliased
      for (int u = int(std::ceil(p0.u)) + 2; u + 2 < int(p1.u); ++u) {
        const double row = p0.v + (p1.v - p0.v) * (u + 0.5 - p0.u) / (p1.u - p0.u);
        double ink = 0, moment = 0;
        for (int v = int(row) - 8; v <= int(row) + 8; ++v) {
          const double a = ink_at(res, bare, W, u, v);
          ink += a, moment += a * (v + 0.5);
          if (antialias) window.push_back(res.rgba[4 * (std::size_t(v) * W + std::size_t(u)) + 1]);
        }
        ASSERT_GT(ink, 0) << "column " << u << " antialias " << antialias << " lift " << lift;
        EXPECT_NEAR(moment / ink, row, antialias ? 0.6 : 1.0)
            << "column " << u << " antialias " << antialias << " lift " << lift;
        ++columns;
      }
      EXPECT_GT(columns, 50);
      if (!antialias) continue;
      if (first.empty()) {
        first = window;
        continue;
      }
      ASSERT_EQ(window.size(), first.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < first.size(); ++i)
        differ += std::abs(int(first[i]) - int(window[i])) > 2;
      EXPECT_EQ(differ, 0u);
    }
  }
}

// The lift is a depth tolerance towards the eye, whatever the angle of view. A channel on
// the floor of a parabolic valley (z = 0.01 (x - 410)^2, mesh spacing 20 m, the axis
// between two vertex columns), seen up the valley from 100 m above its floor, 500 to 700
// m away (8 to 11 degrees below the horizon), with the coarsest tessellation: the
// triangles of the axis' cell column are flat at the height of their vertices, 1 m above
// the PN floor the line lies on. The default lift (10 m) keeps every row of the line
// drawn, its ink centred on the projection of its points. Lifted along the normal as
// before stop 32, the depth came nearer by 10 sin^2(g) = 0.2 to 0.4 m only, and the chord
// hid 33 of the line's 71 rows. The tolerance stays bounded: the same line 20 m under the
// floor is hidden.
TEST(RendererGl, ALineOnAValleyFloorSeenAtAGrazingAngleIsNotHiddenByTheChords) {
  const double axis = 410;
  const auto mesh = terrain::test::function_mesh(
      61, 41, 20, [axis](double x, double) { return 0.01 * (x - axis) * (x - axis); });
  FrameParams fp;
  fp.camera.eye = Vector3d(axis, -1300, 100);
  fp.camera.view_az = 0;
  fp.camera.view_alt = 9.5;
  fp.camera.fov = 10;
  fp.score.min_score = 0;
  fp.score.falloff = 0;
  const int W = 320, H = 240;
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.antialias = true;
  style.mask = {0.5f, 0.5f, 0.5f};
  style.pixels_per_edge = 100;  // tessellation level 1: the flat triangles
  const auto bare =
      TerrainRenderer(ctx, mesh, nullptr, W, H, renderer::Layers{false, true, false, false}, style)
          .render(fp);
  for (const double below : {0.0, 20.0}) {
    CreaseGeometry g;
    for (double y = -800; y <= -600; y += 10) {
      const auto sp = terrain::pn_point_above(mesh, axis, y);
      ASSERT_TRUE(sp);
      ASSERT_LT(sp->position.z(), 0.05)
          << sp->position.z();  // the PN floor; the flat triangles lie 1 m higher
      g.positions.emplace_back(float(axis), float(y), float(sp->position.z() - below));
      g.normals.push_back(sp->normal.cast<float>());
      g.flow.push_back(1.0f);
      g.share.push_back(1.0f);
    }
    for (std::uint32_t i = 0; i + 1 < g.positions.size(); ++i)
      g.segments.insert(g.segments.end(), {i, i + 1});
    TerrainRenderer r(ctx, mesh, &g, W, H, renderer::Layers{false, true, true, false}, style);
    const auto res = r.render(fp);
    EXPECT_EQ(res.crease_segments, g.n_segments());
    const auto near = renderer::project(res.view, g.positions.front().cast<double>());
    const auto far = renderer::project(res.view, g.positions.back().cast<double>());
    ASSERT_GT(near.v - far.v, 40);  // the line runs up the image
    int rows = 0, inked = 0;
    for (int v = int(std::ceil(far.v)) + 2; v + 2 < int(near.v); ++v, ++rows) {
      const double column = far.u + (near.u - far.u) * (v + 0.5 - far.v) / (near.v - far.v);
      double ink = 0, moment = 0;
      for (int u = int(column) - 5; u <= int(column) + 5; ++u) {
        const double a = ink_at(res, bare, W, u, v);
        ink += a, moment += a * (u + 0.5);
      }
      if (ink == 0) continue;
      ++inked;
      EXPECT_NEAR(moment / ink, column, 0.6) << "row " << v;
    }
    EXPECT_GT(rows, 40);
    EXPECT_EQ(inked, below == 0 ? rows : 0) << below << " m under the floor";
  }
}

// Anti-aliased creases: on a plane seen from straight above, a segment's coverage (black
// on white, summed over the image) equals the ideal area of its capsule, L w + pi w^2 / 4,
// within 5 %, for widths of 1 and 3 pixels and any direction; a faded segment covers its
// opacity times that; consecutive segments of a polyline join without overlap (MAX blend).
TEST(RendererGl, AntialiasedCoverageEqualsTheLineArea) {
  const auto mesh =
      terrain::test::function_mesh(101, 101, 10, [](double, double) { return 100.0; });
  renderer::GlContext ctx;
  renderer::Style style;
  style.background = {1, 1, 1};
  style.mask = {1, 1, 1};
  style.crease_colour = {0, 0, 0};
  style.crease_lift = 1;
  style.crease_fade = 0.2;
  FrameParams fp;
  fp.camera.view_alt = 90;
  fp.score.sw = 0, fp.score.iw = 0, fp.score.fw = 1;  // the score is the flow ...
  fp.score.falloff = 0;
  const Eigen::Vector3f up(0, 0, 1);
  // A polyline of n segments from a to b at height 100 (flow 1: full opacity), its basin
  // share `share`.
  auto polyline = [&](Eigen::Vector2f a, Eigen::Vector2f b, int n, float share) {
    CreaseGeometry g;
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector2f p = a + (b - a) * float(i) / float(n);
      g.positions.push_back(Eigen::Vector3f(p.x(), p.y(), 100));
      g.normals.push_back(up);
      g.flow.push_back(1.0f);
      g.share.push_back(share);
    }
    for (std::uint32_t i = 0; i < std::uint32_t(n); ++i)
      g.segments.insert(g.segments.end(), {i, i + 1});
    return g;
  };
  // Widths 1 and 3, and 1 + (3 - 1) sqrt(0.25) = 2 from the basin share.
  for (const auto& [w0, w1, share] :
       {std::tuple{1.0, 1.0, 1.0f}, std::tuple{3.0, 3.0, 1.0f}, std::tuple{1.0, 3.0, 0.25f}}) {
    style.crease_width = w0, style.crease_width_max = w1;
    const double width = w0 + (w1 - w0) * std::sqrt(double(share));
    for (const auto& [a, b, n] :
         {std::tuple{Eigen::Vector2f(200, -500), Eigen::Vector2f(800, -500), 1},
          std::tuple{Eigen::Vector2f(200, -200), Eigen::Vector2f(750, -700), 1},
          std::tuple{Eigen::Vector2f(200, -200), Eigen::Vector2f(750, -700), 7}}) {
      for (double opacity : {1.0, 0.5}) {
        fp.score.min_score = 1.0 - 0.2 * opacity;  // ... so the opacity is (1 - min) / fade
        const auto g = polyline(a, b, n, share);
        TerrainRenderer r(ctx, mesh, &g, 400, 400, renderer::Layers{false, true, true, false},
                          style);
        const auto res = r.render(fp);
        double covered = 0;
        for (std::size_t i = 0; i < res.rgba.size(); i += 4) covered += 1.0 - res.rgba[i] / 255.0;
        const auto p0 = renderer::project(res.view, g.positions.front().cast<double>());
        const auto p1 = renderer::project(res.view, g.positions.back().cast<double>());
        const double length = std::hypot(p1.u - p0.u, p1.v - p0.v);
        const double ideal = opacity * (length * width + std::numbers::pi * width * width / 4);
        EXPECT_NEAR(covered, ideal, 0.05 * ideal) << "width " << width << " segments " << n
                                                  << " opacity " << opacity << " length " << length;
      }
    }
  }
}

// On real data: the GPU's DM selection equals the CPU reference for every min score;
// min score 1 draws nothing, 0 (no distance term) draws every segment, and the count
// never grows with the min score.
TEST(RendererGl, CreaseSelectionMatchesCpuAndIsMonotone) {
  const auto& sc = msh_scene();
  const auto g = renderer::build_crease_geometry(sc.mesh, sc.links,
                                                 {.min_area = 0,
                                                  .min_width = 0,
                                                  .off_edge_runs = false,
                                                  .valley_branches = false,
                                                  .smooth_spacings = 0});
  ASSERT_GT(g.n_segments(), 10000u);
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.lod_error = 0;  // the creases as given, not a coarser level's (CPU references of g)
  TerrainRenderer r(ctx, sc.mesh, &g, 160, 120, renderer::Layers{false, true, true, false}, style);
  const Vector3d light = terrain::light_direction(315, 45);
  for (const double signed_falloff :
       {0.0, 0.5, -0.5}) {  // -0.5: 0.5 orthographic (distance from the eye plane)
    const double falloff = std::abs(signed_falloff);
    std::size_t previous = g.n_segments() + 1;
    for (int i = 0; i <= 10; ++i) {
      FrameParams fp;
      fp.camera.orthographic = signed_falloff < 0;
      fp.score.sw = fp.score.iw = fp.score.fw = 1.0 / 3;
      fp.score.min_score = i / 10.0;
      fp.score.falloff = falloff;
      fp.score.far_distance = 600;
      const auto res = r.render(fp);
      const std::size_t cpu =
          renderer::count_accepted_segments(g, res.view.viewpoint(), light, 1.0, fp.score);
      const double tol = std::max(2.0, 1e-3 * double(g.n_segments()));
      EXPECT_NEAR(double(res.crease_segments), double(cpu), tol)
          << "min " << fp.score.min_score << " falloff " << falloff;
      EXPECT_LE(res.crease_segments, previous);
      previous = res.crease_segments;
      if (i == 0 && falloff == 0) {
        EXPECT_EQ(res.crease_segments, g.n_segments());
      }
      if (i == 10) {
        EXPECT_EQ(res.crease_segments, 0u);
      }
    }
  }
}

// The stroke rule on the GPU (crease_bridge, crease_select) equals its CPU reference
// (segment_opacity with the style's rule at the frame's page scale) on real data, and it
// changes the selection: gaps bridged, short strokes left out. The bridge is in metres,
// the shortest stroke in pixels at the page scale, and channels begin at the page's area
// (Style::page_min_area), so every term runs on the GPU.
TEST(RendererGl, StrokeRuleMatchesCpu) {
  const auto& sc = msh_scene();
  const auto g = renderer::build_crease_geometry(sc.mesh, sc.links,
                                                 {.min_area = 0,
                                                  .min_width = 0,
                                                  .off_edge_runs = false,
                                                  .valley_branches = false,
                                                  .smooth_spacings = 0});
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.crease_bridge = 10.0;
  style.crease_min_stroke_px = 6.0;
  style.page_min_area = 20000.0;
  style.lod_error = 0;  // the creases as given, not a coarser level's (CPU references of g)
  TerrainRenderer r(ctx, sc.mesh, &g, 160, 120, renderer::Layers{false, true, true, false}, style);
  const Vector3d light = terrain::light_direction(315, 45);
  std::size_t changed = 0;
  for (double min_score : {0.2, 0.3, 0.4, 0.5}) {
    FrameParams fp;
    fp.score.min_score = min_score;
    fp.score.far_distance = 600;
    const auto res = r.render(fp);
    const double scale = renderer::page_scale(res.view, r.box());
    const renderer::StrokeRule rule = renderer::stroke_rule(style, scale);
    EXPECT_DOUBLE_EQ(rule.bridge, 10.0);
    EXPECT_DOUBLE_EQ(rule.min_length, 6.0 * scale);
    EXPECT_DOUBLE_EQ(rule.min_area, 20000.0 * std::sqrt(scale / renderer::kPageAreaScale));
    const auto opacity =
        renderer::segment_opacity(g, res.view.viewpoint(), light, 1.0, fp.score, 0.0, rule);
    const auto cpu =
        std::size_t(std::count_if(opacity.begin(), opacity.end(), [](float o) { return o > 0; }));
    const double tol = std::max(2.0, 1e-3 * double(g.n_segments()));
    EXPECT_NEAR(double(res.crease_segments), double(cpu), tol) << "min score " << min_score;
    changed +=
        cpu != renderer::count_accepted_segments(g, res.view.viewpoint(), light, 1.0, fp.score);
  }
  EXPECT_GT(changed, 0u);
}

// Hidden-line removal along strokes (stroke_visibility.hpp): the DM pass's samples are
// the CPU reference's, on real terrain seen at a grazing angle, where gullies' near walls
// hide their floors a few pixels at a time. Every drawn segment has the same sample count
// (within 0.5 %: a screen length at a whole pixel rounds either way in floats), and all
// but 0.01 % of the samples of those agree on each mask (none differs here on llvmpipe, nor
// in bench/gpu_strokes on an H100 and an H200; a rule left out of the shader flips more:
// the peek rule's junctions, 15 of 32405).
// Both rules do something here, and a hidden sample the GPU draws has crease ink at its
// pixel.
TEST(RendererGl, StrokeVisibilityMatchesCpu) {
  const auto& sc = msh_scene();
  const auto g = renderer::build_crease_geometry(sc.mesh, sc.links,
                                                 {.min_area = 0,
                                                  .min_width = 0,
                                                  .off_edge_runs = false,
                                                  .valley_branches = false,
                                                  .smooth_spacings = 0});
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.antialias = true;
  style.lod_error = 0;  // the creases as given, not a coarser level's (CPU references of g)
  const int w = 480, h = 270;
  TerrainRenderer r(ctx, sc.mesh, &g, w, h, renderer::Layers{false, true, true, false}, style);
  for (const bool orthographic :
       {false, true}) {  // depth linear from the eye plane, the lift along the sight
    SCOPED_TRACE(orthographic ? "orthographic" : "perspective");
    FrameParams fp;
    fp.camera.view_az = 200;
    fp.camera.view_alt = 12;
    fp.camera.orthographic = orthographic;
    fp.score.min_score = 0.05;
    const auto res = r.render(fp);
    const auto gpu = r.read_crease_samples();
    ASSERT_EQ(gpu.size(), g.n_segments());
    const auto buffers = r.read_buffers();
    const Vector3d light = terrain::light_direction(fp.light.azimuth, fp.light.altitude);
    const auto score =
        renderer::resolve_distances(fp.score, r.box().lo, r.box().hi, res.view.viewpoint());
    const auto drawn = renderer::segment_opacity(
        g, res.view.viewpoint(), light, 1.0, score, style.crease_fade,
        renderer::stroke_rule(style, renderer::page_scale(res.view, r.box())));
    const auto rule = renderer::stroke_visibility_rule(style, sc.mesh);
    EXPECT_DOUBLE_EQ(rule.gap_depth, 1.5 * 10.0);
    const auto cpu = renderer::stroke_visibility(g, renderer::segment_chains(g), drawn, res.view,
                                                 1.0, renderer::crease_lift(style, sc.mesh),
                                                 buffers.toward_depth, rule);
    const renderer::SampleComparison c = renderer::compare_samples(cpu, gpu);
    // Where the GPU draws a hidden sample, the crease layer has ink.
    std::size_t inked = 0;
    for (std::size_t s = 0; s < g.n_segments(); ++s) {
      const std::uint32_t hidden_drawn = gpu[s].shown & ~gpu[s].visible;
      if (!hidden_drawn) continue;
      const auto p0 = renderer::project(res.view, g.positions[g.segments[2 * s]].cast<double>());
      const auto p1 =
          renderer::project(res.view, g.positions[g.segments[2 * s + 1]].cast<double>());
      for (std::uint32_t k = 0; k < gpu[s].n; ++k) {
        if (!(hidden_drawn >> k & 1u)) continue;
        const double t = (k + 0.5) / gpu[s].n;
        const int u = int(std::floor(p0.u + t * (p1.u - p0.u))),
                  v = int(std::floor(p0.v + t * (p1.v - p0.v)));
        inked += u >= 0 && v >= 0 && u < w && v < h && buffers.crease[std::size_t(v * w + u)];
      }
    }
    EXPECT_GT(c.segments, 1000u);
    EXPECT_LE(double(c.other_count), 0.005 * double(c.segments));
    for (int j = 0; j < 4; ++j)
      EXPECT_LE(double(c.differ[j]), 1e-4 * double(c.samples))
          << "mask " << j << " of " << c.samples;
    EXPECT_GT(c.hidden_drawn, 20u);
    EXPECT_GT(c.peeks, 5u);
    EXPECT_GE(double(inked), 0.95 * double(c.hidden_drawn));
    std::cout << c.segments << " segments drawn, " << c.other_count
              << " with another sample count; of " << c.samples << " samples: " << c.differ[0]
              << " / " << c.differ[1] << " / " << c.differ[2] << " / " << c.differ[3]
              << " differ (visible, bridgeable, closed, shown); " << c.hidden_drawn
              << " hidden drawn, " << c.peeks << " peek samples left out, " << inked
              << " of the first inked\n";
  }
}

// From straight above nothing is hidden: at min score 0 every drainage vertex that starts
// a segment lies on a crease pixel of the composite (within 1 pixel of its projection; the
// lift moves only the depth), unless it lies within 1.5 pixels of the mesh's edge, where
// no surface may lie under its pixels and creases are not drawn
// (CreasesAreDrawnWhereTheyLieOnTheSurface).
TEST(RendererGl, MinScoreZeroDrawsEveryVisibleVertex) {
  const auto& sc = msh_scene();
  const auto g = renderer::build_crease_geometry(sc.mesh, sc.links,
                                                 {.min_area = 0,
                                                  .min_width = 0,
                                                  .off_edge_runs = false,
                                                  .valley_branches = false,
                                                  .smooth_spacings = 0});
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.pixels_per_edge = 2;
  TerrainRenderer r(ctx, sc.mesh, &g, 400, 400, renderer::Layers{false, true, true, false}, style);
  FrameParams fp;
  fp.camera.view_alt = 90;
  fp.score.min_score = 0;
  fp.score.falloff = 0;
  const auto res = r.render(fp);
  std::size_t missing = 0, checked = 0;
  const auto p0 = renderer::project(res.view, Vector3d(0, 0, 1800)),
             p1 = renderer::project(res.view, Vector3d(100, 0, 1800));
  const double margin = 1.5 * 100 / std::hypot(p1.u - p0.u, p1.v - p0.v);  // metres
  const double east = double(sc.mesh.topo.cols - 1) * sc.mesh.geo.dx,
               south = -double(sc.mesh.topo.rows - 1) * sc.mesh.geo.dy;
  for (std::size_t s = 0; s < g.n_segments(); ++s) {
    const Eigen::Vector3f p = g.positions[g.segments[2 * s]];
    if (p.x() < margin || p.y() > -margin || p.x() > east - margin || p.y() < south + margin)
      continue;  // at the edge: no surface under some of its pixels
    const auto q = renderer::project(res.view, p.cast<double>());
    const int u = int(std::floor(q.u)), v = int(std::floor(q.v));
    if (u < 1 || v < 1 || u >= 399 || v >= 399) continue;
    bool found = false;
    for (int dv = -1; dv <= 1 && !found; ++dv)
      for (int du = -1; du <= 1 && !found; ++du) {
        const std::size_t i = 4 * (std::size_t(v + dv) * 400 + std::size_t(u + du));
        found = res.rgba[i] == 255 && res.rgba[i + 1] == 0;
      }
    if (!found)
      ADD_FAILURE() << "vertex " << g.segments[2 * s] << " at pixel " << q.u << " " << q.v
                    << " flow " << g.flow[g.segments[2 * s]] << " pos "
                    << g.positions[g.segments[2 * s]].transpose();
    missing += !found;
    ++checked;
  }
  EXPECT_GT(checked, 10000u);
  EXPECT_EQ(missing, 0u);
}

}  // namespace

namespace {

// The MSH test mesh with its Voronoi weights, and the layers that draw its PELs alone.
terrain::GridMesh msh_pel_mesh() {
  terrain::GridMesh mesh = msh_scene().mesh;
  mesh.voronoi = terrain::voronoi_weights(mesh);
  return mesh;
}
renderer::Layers pel_layers() {
  renderer::Layers layers{false, true, false, false};
  layers.pels = true;
  return layers;
}

// The GPU PEL passes produce the CPU reference's segments: the same count (within 0.5%)
// and, face by face, the same end points within 1e-4 of the mesh's extent.
TEST(RendererGl, PelSegmentsMatchCpu) {
  const terrain::GridMesh mesh = msh_pel_mesh();
  renderer::GlContext ctx;
  TerrainRenderer r(ctx, mesh, nullptr, 160, 120, pel_layers(), test_style());
  double scale = 0;
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i)
    scale = std::max(scale, double(mesh.positions[i].norm()));
  for (double tau : {0.05, 0.2}) {
    FrameParams fp;
    fp.pel.headlight = false;
    fp.light = {135, 40};
    fp.pel.threshold = tau;
    const auto res = r.render(fp);
    const auto gpu = r.read_pels();
    EXPECT_EQ(gpu.size(), res.pel_segments);
    const auto fields = renderer::pel_fields(mesh, terrain::light_direction(135, 40));
    const auto cpu = renderer::extract_pels(mesh, fields, tau);
    ASSERT_GT(cpu.size(), 100u);
    EXPECT_NEAR(double(gpu.size()), double(cpu.size()), 0.005 * double(cpu.size()))
        << "tau " << tau;
    std::map<std::uint32_t, std::size_t> by_face;
    for (std::size_t i = 0; i < cpu.size(); ++i) by_face[cpu.faces[i]] = i;
    std::size_t matched = 0;
    for (const auto& s : gpu) {
      const auto it = by_face.find(s.face);
      if (it == by_face.end()) continue;
      const Eigen::Vector3f a = cpu.points[2 * it->second], b = cpu.points[2 * it->second + 1];
      const double d = std::min(std::max((s.a - a).norm(), (s.b - b).norm()),
                                std::max((s.a - b).norm(), (s.b - a).norm()));
      matched += d <= 1e-4 * scale;
    }
    EXPECT_GE(double(matched), 0.995 * double(gpu.size())) << "tau " << tau;
    for (const auto& sg : gpu) EXPECT_EQ(sg.opacity, 1.0f);  // pixel-exact lines: no piece rule
  }
}

// With anti-aliased lines the GPU smooths the PELs (smooth_pels, 3 iterations) and its
// pieces give each segment the opacity of the CPU rule (pel_pieces, pel_piece_opacity) on
// the CPU's smoothed segments, face by face; the smoothed ends are the CPU's within 1e-4 of
// the mesh's extent, and they moved (the zigzag is gone).
TEST(RendererGl, PelPiecesFollowTheCpuRule) {
  const terrain::GridMesh mesh = msh_pel_mesh();
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.antialias = true;
  style.pel_min_length = 8;
  TerrainRenderer r(ctx, mesh, nullptr, 160, 120, pel_layers(), style);
  FrameParams fp;
  fp.pel.headlight = false;
  fp.light = {135, 40};
  r.render(fp);
  const auto gpu = r.read_pels();
  const auto fields = renderer::pel_fields(mesh, terrain::light_direction(135, 40));
  const auto raw = renderer::extract_pels(mesh, fields, fp.pel.threshold);
  auto cpu = raw;
  ASSERT_EQ(style.pel_smooth, 3);
  renderer::smooth_pels(mesh.topo, fields, cpu, style.pel_smooth);
  const auto cpu_opacity = renderer::pel_piece_opacity(renderer::pel_pieces(mesh.topo, fields, cpu),
                                                       8 * std::min(mesh.geo.dx, mesh.geo.dy));
  double scale = 0;
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i)
    scale = std::max(scale, double(mesh.positions[i].norm()));
  std::map<std::uint32_t, std::size_t> by_face;
  std::size_t dropped = 0, faded = 0, full = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    by_face[cpu.faces[i]] = i;
    dropped += cpu_opacity[i] == 0.0f, full += cpu_opacity[i] == 1.0f;
  }
  faded = cpu.size() - dropped - full;
  std::size_t matched = 0, same = 0, at = 0, moved = 0;
  for (const auto& sg : gpu) {
    const auto it = by_face.find(sg.face);
    if (it == by_face.end()) continue;
    const std::size_t i = it->second;
    ++matched;
    same += std::abs(sg.opacity - cpu_opacity[i]) <= 0.01f;
    at += std::max((sg.a - cpu.points[2 * i]).norm(), (sg.b - cpu.points[2 * i + 1]).norm()) <=
          1e-4 * scale;
    moved += std::max((sg.a - raw.points[2 * i]).norm(), (sg.b - raw.points[2 * i + 1]).norm()) >
             1e-3 * scale;
  }
  EXPECT_GE(double(matched), 0.995 * double(gpu.size()));
  EXPECT_GE(double(at), 0.995 * double(matched));
  EXPECT_GT(double(moved), 0.5 * double(matched));
  EXPECT_GE(double(same), 0.99 * double(matched))
      << "dropped " << dropped << " faded " << faded << " full " << full;
  EXPECT_GT(dropped, 20u);
  EXPECT_GT(faded, 20u);
  EXPECT_GT(full, cpu.size() / 2);
}

}  // namespace

namespace {

// Share of the pixels of mask `a` that have a pixel of mask `b` within 1 px (8-neighbourhood).
double covered_within_one(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                          int w, int h, std::size_t& uncovered) {
  std::size_t total = 0, covered = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!a[std::size_t(y) * std::size_t(w) + std::size_t(x)]) continue;
      ++total;
      bool hit = false;
      for (int dy = -1; dy <= 1 && !hit; ++dy)
        for (int dx = -1; dx <= 1 && !hit; ++dx) {
          const int xx = x + dx, yy = y + dy;
          hit = xx >= 0 && yy >= 0 && xx < w && yy < h &&
                b[std::size_t(yy) * std::size_t(w) + std::size_t(xx)];
        }
      covered += hit;
    }
  uncovered = total - covered;
  return total ? double(covered) / double(total) : 1.0;
}

}  // namespace

// Real terrain (Mount St. Helens at 50 m, the default view): the Adjacency method finds
// >= 90 % of the Toward/Away silhouette pixels within 1 px; its pixels that Toward/Away does
// not have (spurious: pixel neighbours across thin triangles near patch borders) are
// counted and reported.
TEST(RendererGl, AdjacencyAgreesWithTowardAwayOnRealTerrain) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  renderer::GlContext ctx;
  const int w = 640, h = 360;
  for (const bool orthographic :
       {false, true}) {  // the orthographic view: the pixel's size in metres
    auto mask = [&](bool adjacency) {
      renderer::Layers layers{false, true, false, true};
      layers.adjacency = adjacency;
      TerrainRenderer r(ctx, mesh, nullptr, w, h, layers, test_style());
      FrameParams fp;
      fp.camera.orthographic = orthographic;
      if (orthographic)
        fp.camera.view_alt = 15;  // parallel rays graze less: lower, for as many silhouettes
      r.render(fp);
      return r.read_buffers().silhouette;
    };
    const auto toward_away = mask(false), adjacency = mask(true);
    std::size_t missed = 0, spurious = 0;
    const double found = covered_within_one(toward_away, adjacency, w, h, missed);
    covered_within_one(adjacency, toward_away, w, h, spurious);
    const auto n_ta = std::count(toward_away.begin(), toward_away.end(), 1);
    const auto n_adj = std::count(adjacency.begin(), adjacency.end(), 1);
    std::printf(
        "%s: Toward/Away %ld px, Adjacency %ld px; found %.1f %% of Toward/Away within 1 px; "
        "spurious %zu px\n",
        orthographic ? "orthographic" : "perspective", long(n_ta), long(n_adj), 100 * found,
        spurious);
    EXPECT_GT(n_ta, 500);
    EXPECT_GE(found, 0.90);
  }
}

namespace {

// 8-connected pieces of a 0/1 mask.
std::size_t pieces(const std::vector<std::uint8_t>& m, int w, int h) {
  return renderer::mask_pieces(m, w, h).size.size();
}

}  // namespace

// Toward/Away silhouettes on Mount St. Helens at 50 m, seen low from the south-south-west:
// the SIL pass gives exactly the CPU rule (renderer::toward_away_silhouettes) applied to
// the frame's own TFT and AFT depths, pixel-exact and anti-aliased. Anti-aliased, the gaps
// where an away-facing band is thinner than a pixel are closed: the lines fall into fewer
// pieces, and nearly every pixel added lies beside a pixel of the paper's mask.
TEST(RendererGl, SilhouettesFollowTheCpuRuleAndCloseGaps) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  renderer::GlContext ctx;
  const int w = 640, h = 360;
  auto mask = [&](bool antialias) {
    renderer::Style style = test_style();
    style.antialias = antialias;
    TerrainRenderer r(ctx, mesh, nullptr, w, h, renderer::Layers{false, true, false, true}, style);
    FrameParams fp;
    fp.camera.view_az = 200;
    fp.camera.view_alt = 15;
    const auto res = r.render(fp);
    const auto b = r.read_buffers();
    const auto cpu = renderer::toward_away_silhouettes(b.toward_depth, b.away_depth, w, h,
                                                       res.view.reversed_z, antialias);
    EXPECT_EQ(std::count(cpu.begin(), cpu.end(), 1),
              std::count(b.silhouette.begin(), b.silhouette.end(), 1));
    std::size_t differ = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i) differ += cpu[i] != b.silhouette[i];
    EXPECT_EQ(differ, 0u) << (antialias ? "anti-aliased" : "pixel-exact");
    return b.silhouette;
  };
  const auto exact = mask(false), soft = mask(true);
  const auto n_exact = std::count(exact.begin(), exact.end(), 1),
             n_soft = std::count(soft.begin(), soft.end(), 1);
  const std::size_t p_exact = pieces(exact, w, h), p_soft = pieces(soft, w, h);
  std::size_t apart = 0;
  const double beside = covered_within_one(soft, exact, w, h, apart);
  std::printf("silhouette pixels %ld -> %ld, pieces %zu -> %zu, %.1f %% beside the paper's\n",
              long(n_exact), long(n_soft), p_exact, p_soft, 100 * beside);
  EXPECT_GT(n_exact, 500);
  EXPECT_GT(n_soft, n_exact);
  // 61 -> 20 pieces; dropping the specks alone (the rule before the gaps were closed) left 39.
  EXPECT_LT(double(p_soft), 0.5 * double(p_exact));
  EXPECT_GE(beside, 0.95);
}

// Formulated silhouettes on Mount St. Helens at 50 m (the eye lowered to 5 degrees, a
// strength of 5 degrees), seen obliquely and from straight above: the SIL pass's mask is exactly
// the CPU rules applied to the frame's own buffers, Toward/Away's on its depths united with
// renderer::formulated_silhouettes on its drawn normals. From above there is no Toward/Away
// silhouette at all, and the formulated ones are there.
TEST(RendererGl, FormulatedSilhouettesFollowTheCpuRule) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  renderer::GlContext ctx;
  const int w = 640, h = 360;
  renderer::Style style = test_style();
  style.formulated = true;
  style.formulated_altitude = style.formulated_strength = 5;  // enough lines on this view
  // One renderer for the three frames: the facing is drawn only near the tiles that may
  // hold a formulated pixel, and what an earlier frame drew elsewhere must not count.
  TerrainRenderer r(ctx, mesh, nullptr, w, h, renderer::Layers{false, true, false, true}, style);
  for (const double alt : {30.0, 90.0, 30.0}) {
    SCOPED_TRACE(alt);
    FrameParams fp;
    fp.camera.view_az = 200;
    fp.camera.view_alt = alt;
    const auto res = r.render(fp);
    const auto b = r.read_buffers(true);
    ASSERT_EQ(b.surface_normal.size(), 4u * w * h);
    const auto ta = renderer::toward_away_silhouettes(b.toward_depth, b.away_depth, w, h,
                                                      res.view.reversed_z, false);
    const auto f = renderer::formulated_silhouettes(
        b.surface_normal, w, h,
        renderer::formulated_view(res.view, style.formulated_altitude, style.formulated_strength));
    std::size_t differ = 0, n_ta = 0, n_f = 0;
    for (std::size_t i = 0; i < f.size(); ++i) {
      differ += std::uint8_t(ta[i] || f[i]) != b.silhouette[i];
      n_ta += ta[i], n_f += f[i];
    }
    std::printf("view altitude %.0f: Toward/Away %zu px, formulated %zu px\n", alt, n_ta, n_f);
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(n_f, alt == 90.0 ? 300u : 50u);  // 544 and 71 px
    if (alt == 90.0) {
      EXPECT_EQ(n_ta, 0u);
    }
  }
}

// The piece rule on a mask whose pieces are known: pixels within kSilhouetteJoin (5)
// pixels join (a diagonal line is one piece, two pieces touching at a corner are one, two
// runs 4 pixels apart are one, 5 apart two), and a piece of n pixels gets
// piece_opacity(n, m, kSilhouetteFade) = clamp((n - 3m/4) / (m/4), 0, 1).
TEST(SilhouettePieces, OpacityFromThePieceSize) {
  const int w = 48, h = 30;
  std::vector<std::uint8_t> m(std::size_t(w * h), 0);
  auto set = [&](int x, int y) { m[std::size_t(y * w + x)] = 1; };
  for (int x = 0; x < 30; ++x) set(x, 1);                   // 30 px: in full
  for (int k = 0; k < 8; ++k) set(2 + k, 7 + k);            // diagonal, 8 px...
  for (int k = 0; k < 10; ++k) set(10 + k, 14);             // ...and 10 px from its corner: 18 px
  set(35, 6), set(36, 6), set(35, 7);                       // 3 px: gone
  for (int x = 0; x < 8; ++x) set(x, 20), set(x + 12, 20);  // 8 + 8 px, a gap of 4: one piece of 16
  for (int x = 0; x < 8; ++x) set(x + 22, 26), set(x + 35, 26);  // a gap of 5: two pieces of 8
  const std::vector<float> o = renderer::silhouette_piece_opacity(m, w, h, 20.0);
  auto at = [&](int x, int y) { return o[std::size_t(y * w + x)]; };
  EXPECT_FLOAT_EQ(at(0, 1), 1.0f);
  EXPECT_FLOAT_EQ(at(29, 1), 1.0f);
  EXPECT_FLOAT_EQ(at(2, 7), 0.6f);  // (18 - 15) / 5
  EXPECT_FLOAT_EQ(at(19, 14), 0.6f);
  EXPECT_FLOAT_EQ(at(35, 7), 0.0f);
  EXPECT_FLOAT_EQ(at(0, 20), 0.2f);  // (16 - 15) / 5
  EXPECT_FLOAT_EQ(at(19, 20), 0.2f);
  EXPECT_FLOAT_EQ(at(22, 26), 0.0f);
  EXPECT_FLOAT_EQ(at(42, 26), 0.0f);
  EXPECT_EQ(renderer::mask_pieces(m, w, h, 1).size.size(), 7u);
  EXPECT_EQ(renderer::mask_pieces(m, w, h, renderer::kSilhouetteJoin).size.size(), 6u);
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!m[i]) {
      EXPECT_EQ(o[i], 0.0f) << i;
    }
  }
  // Off: every silhouette pixel in full.
  const std::vector<float> all = renderer::silhouette_piece_opacity(m, w, h, 0.0);
  for (std::size_t i = 0; i < m.size(); ++i) EXPECT_EQ(all[i], float(m[i])) << i;
  EXPECT_FLOAT_EQ(renderer::piece_opacity(10, 20.0),
                  0.0f);  // the PELs' rule: fading over half the minimum
  EXPECT_FLOAT_EQ(renderer::piece_opacity(15, 20.0), 0.5f);
  EXPECT_FLOAT_EQ(renderer::piece_opacity(20, 20.0), 1.0f);
  EXPECT_FLOAT_EQ(renderer::piece_opacity(17.5, 20.0, renderer::kSilhouetteFade), 0.5f);
  EXPECT_FLOAT_EQ(renderer::piece_opacity(1, 1.0), 1.0f);
}

// The SIL pass's piece rule (union-find on the GPU over the listed silhouette pixels)
// gives the CPU rule applied to the pass's own mask, to the 8-bit step, for both
// silhouette methods; on this view some pieces are dropped, some fade and some stay.
TEST(RendererGl, SilhouettePiecesFollowTheCpuRule) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  renderer::GlContext ctx;
  const int w = 640, h = 360;
  for (const bool adjacency : {false, true}) {
    SCOPED_TRACE(adjacency ? "Adjacency" : "Toward/Away");
    renderer::Style style = test_style();
    style.antialias = true;
    style.silhouette_min_length = 0.15;  // 54 px in full, gone below 40.5
    renderer::Layers layers{false, true, false, true};
    layers.adjacency = adjacency;
    TerrainRenderer r(ctx, mesh, nullptr, w, h, layers, style);
    // Two views with one renderer: the second frame's pieces owe nothing to the first's
    // (the labels are set as pixels are listed, not cleared).
    for (const double az : {200.0, 110.0}) {
      FrameParams fp;
      fp.camera.view_az = az;
      fp.camera.view_alt = 15;
      r.render(fp);
      const auto b = r.read_buffers();
      const std::vector<float> cpu =
          renderer::silhouette_piece_opacity(b.silhouette, w, h, 0.15 * h);
      std::size_t differ = 0, dropped = 0, faded = 0, full = 0;
      for (std::size_t i = 0; i < cpu.size(); ++i) {
        const int gpu = b.silhouette_opacity[i], want = int(std::lround(255.0 * cpu[i]));
        differ += std::abs(gpu - want) > 1;
        if (b.silhouette[i]) (gpu == 0 ? dropped : gpu == 255 ? full : faded) += 1;
      }
      std::printf("view azimuth %.0f: silhouette pixels %zu in full, %zu faded, %zu dropped\n", az,
                  full, faded, dropped);
      EXPECT_EQ(differ, 0u);
      EXPECT_GT(full, 300u);
      EXPECT_GT(faded, 0u);
      EXPECT_GT(dropped, 0u);
    }
  }
}

// Levels of detail (renderer/core/lod.hpp) join without cracks on the GPU: on a bumpy analytic
// surface of 4 x 4 blocks drawn at a large error bound (so the blocks mix several levels),
// no background pixel is enclosed by the terrain (every pixel where nothing was drawn
// reaches the image's border through such pixels: a crack between two blocks, or a coarse
// patch whose fine normals turn from the eye where its geometry faces it, would be an
// enclosed one; before coarse patches faced by their geometry, 20 to 98 such pixels at
// bounds 1 to 16 px), seen from straight above (orthographic) and obliquely. The patches
// drawn are far fewer than the mesh's faces, and bound 0 draws them all.
TEST(RendererGl, LevelsOfDetailLeaveNoCrack) {
  const terrain::GridMesh mesh =
      terrain::test::function_mesh(257, 257, 10.0, [](double x, double y) {
        return 0.05 * x + 40 * std::sin(x / 90) * std::cos(y / 70) + 8 * std::sin(x / 23 + y / 31);
      });
  renderer::GlContext ctx;
  const int w = 480, h = 360;
  renderer::Style style = test_style();
  style.lod_error = 4;  // 16 px where a level faces the eye throughout (kFacingLodFactor)
  // Without the cells' cap (coarse levels, tessellated), then with it (flat patches).
  for (const double cell : {0.0, -1.0}) {
    style.lod_cell = cell;
    TerrainRenderer r(ctx, mesh, nullptr, w, h, renderer::Layers{false, true, false, false}, style);
    for (const bool orthographic : {true, false}) {
      FrameParams fp;
      fp.camera.orthographic = orthographic;
      fp.camera.view_az = orthographic ? 0 : 200;
      fp.camera.view_alt = orthographic ? 90 : 35;
      const auto res = r.render(fp);
      EXPECT_LT(res.patches, cell == 0 ? mesh.n_faces() / 8 : mesh.n_faces() / 2) << orthographic;
      EXPECT_GT(res.patches, 32u) << orthographic;
      const auto depth = r.read_buffers().toward_depth;
      std::vector<std::uint8_t> outside(depth.size(), 0);
      std::vector<std::size_t> stack;
      auto empty = [&](std::size_t i) {
        return renderer::far_depth(res.view.reversed_z, depth[i]) >= 1.0f;
      };
      for (int x = 0; x < w; ++x)
        for (int y : {0, h - 1}) stack.push_back(std::size_t(y * w + x));
      for (int y = 0; y < h; ++y)
        for (int x : {0, w - 1}) stack.push_back(std::size_t(y * w + x));
      while (!stack.empty()) {
        const std::size_t i = stack.back();
        stack.pop_back();
        if (outside[i] || !empty(i)) continue;
        outside[i] = 1;
        const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
        if (x > 0) stack.push_back(i - 1);
        if (x + 1 < w) stack.push_back(i + 1);
        if (y > 0) stack.push_back(i - std::size_t(w));
        if (y + 1 < h) stack.push_back(i + std::size_t(w));
      }
      std::size_t enclosed = 0, terrain = 0;
      for (std::size_t i = 0; i < depth.size(); ++i)
        enclosed += empty(i) && !outside[i], terrain += !empty(i);
      EXPECT_EQ(enclosed, 0u) << (orthographic ? "orthographic" : "oblique") << " patches "
                              << res.patches << " cell " << cell;
      EXPECT_GT(terrain, depth.size() / 4);
    }
  }
  renderer::Style full = style;
  full.lod_error = 0;
  TerrainRenderer f(ctx, mesh, nullptr, w, h, renderer::Layers{false, true, false, false}, full);
  EXPECT_EQ(f.render(FrameParams{}).patches, mesh.n_faces());
}

// AFT looks only at the patches that may face away (SceneGpu::n_away_patches): those of
// the blocks whose level faces the eye throughout (facing_blocks) come last and are
// skipped. Skipping them changes nothing: on hills that grow from gentle to steep, seen
// 20 degrees down from three sides, at a bound that draws every block at its coarsest
// either way, the away depth and the silhouettes are the same, pixel for pixel, as with
// the levels' slopes taken away (no block facing, AFT over every patch), while 102 to 111
// of the 256 blocks face and 576 to 1506 pixels face away.
TEST(RendererGl, AftSkipsOnlyPatchesThatFaceTheEye) {
  // Hills that grow from the west (gentle) to the east (steep).
  const terrain::GridMesh mesh =
      terrain::test::function_mesh(257, 257, 10.0, [](double x, double y) {
        const double grow = x / 2560 * x / 2560;
        return 80 * grow * std::sin(x / 90) * std::cos(y / 70) +
               16 * grow * std::sin(x / 23 + y / 31);
      });
  auto levels = std::make_shared<const renderer::LodHierarchy>(renderer::build_lod(mesh, 16));
  renderer::LodHierarchy plain = *levels;
  for (auto& b : plain.blocks) b.slope.clear();
  auto no_slopes = std::make_shared<const renderer::LodHierarchy>(std::move(plain));
  renderer::GlContext ctx;
  const int w = 480, h = 360;
  renderer::Style style = test_style();
  style.lod_error = 1e6;  // every block at its coarsest, facing or not
  style.lod_cell = 0;
  const renderer::Layers layers{false, true, false, true};  // the mask and the silhouettes
  TerrainRenderer a(ctx, mesh, nullptr, w, h, layers, style, levels);
  TerrainRenderer b(ctx, mesh, nullptr, w, h, layers, style, no_slopes);
  for (const double az : {0.0, 120.0, 240.0}) {
    FrameParams fp;
    fp.camera.view_az = az;
    fp.camera.view_alt = 20;
    const auto ra = a.render(fp);
    const auto fa = a.read_buffers();
    const auto rb = b.render(fp);
    const auto fb = b.read_buffers();
    ASSERT_EQ(ra.patches, rb.patches) << az;
    const auto facing = renderer::facing_blocks(
        *levels, ra.view, style.exaggeration,
        renderer::select_lod(*levels, ra.view, style.exaggeration, style.lod_error));
    const auto marked = std::count(facing.begin(), facing.end(), std::uint8_t(1));
    EXPECT_GT(marked, 0) << az;
    EXPECT_LT(marked, std::ptrdiff_t(facing.size())) << az;
    std::size_t away = 0, away_differ = 0, silhouette_differ = 0;
    for (std::size_t i = 0; i < fa.away_depth.size(); ++i) {
      away += renderer::far_depth(ra.view.reversed_z, fa.away_depth[i]) < 1.0f;
      away_differ += fa.away_depth[i] != fb.away_depth[i];
    }
    for (std::size_t i = 0; i < fa.silhouette_opacity.size(); ++i)
      silhouette_differ += fa.silhouette_opacity[i] != fb.silhouette_opacity[i];
    EXPECT_GT(away, 100u) << az;
    EXPECT_EQ(away_differ, 0u) << az;
    EXPECT_EQ(silhouette_differ, 0u) << az;
  }
}

// A coarser level of the mesh's pyramid held in the mesh's place (terrain-render --memory;
// read_mesh_via_pyramid's level, LodHierarchy::base) draws the same frame as the whole
// mesh wherever the view draws no block finer than that level: the same patches, depth and
// silhouettes, pixel for pixel. The mesh (299 x 270 cells: partial blocks at the right and
// bottom, whose last row and column the level grid keeps closer) is read back at level 2,
// a sixteenth of its vertices; seen from straight above and obliquely from far, at a bound
// that draws every block at level 2 or coarser (the coarse patches, which face by their
// geometry, are found by the mesh's own spacing, not the held level's). Seen obliquely from near,
// where the whole mesh draws finer blocks, the held level is drawn instead (fewer patches), and
// without a crack.
TEST(RendererGl, ACoarserLevelHeldDrawsTheSameFrame) {
  const terrain::GridMesh mesh = bumpy_blocks();
  terrain::test::ScratchDir dir;
  terrain::write_mesh_ply(mesh, dir.path("m.ply"));
  terrain::write_mesh_pyramid(mesh, dir.path("m.tpyr"));
  std::string why;
  const auto whole = terrain::read_mesh_via_pyramid(dir.path("m.ply"), why);
  const auto coarse = terrain::read_mesh_via_pyramid(dir.path("m.ply"), why,
                                                     [](const terrain::MeshPyramid&) { return 2; });
  ASSERT_TRUE(whole && coarse) << why;
  ASSERT_EQ(coarse->levels.base, 2);
  EXPECT_EQ(coarse->mesh.topo.rows, 76u);  // 299 cells: rows 0, 4, ..., 296 and 299
  EXPECT_EQ(coarse->mesh.topo.cols, 69u);  // 270 cells: 0, 4, ..., 268 and 270
  EXPECT_EQ(coarse->mesh.positions[75 * 69 + 68], mesh.positions[299 * 271 + 270]);
  EXPECT_EQ(coarse->mesh.positions[74 * 69 + 67], mesh.positions[296 * 271 + 268]);
  auto fine_levels = std::make_shared<const renderer::LodHierarchy>(whole->levels);
  auto held_levels = std::make_shared<const renderer::LodHierarchy>(coarse->levels);

  renderer::GlContext ctx;
  const int w = 480, h = 360;
  renderer::Style style = test_style();
  style.lod_error = 16;
  style.lod_cell = 0;  // no cap on the cells: every block at level 2 or coarser from far
  const renderer::Layers layers{false, true, false, true};  // the mask and the silhouettes
  TerrainRenderer a(ctx, whole->mesh, nullptr, w, h, layers, style, fine_levels);
  TerrainRenderer b(ctx, coarse->mesh, nullptr, w, h, layers, style, held_levels);
  FrameParams top, far;
  top.camera.orthographic = true;
  top.camera.view_az = 0;
  top.camera.view_alt = 90;
  far.camera.eye = Vector3d(1350, 5000, 700);  // far to the north, looking south over the surface
  far.camera.view_az = 180;
  far.camera.view_alt = 8;
  for (const FrameParams& fp : {top, far}) {
    const auto ra = a.render(fp);
    const auto levels = renderer::select_lod(*fine_levels, ra.view, style.exaggeration,
                                             style.lod_error, renderer::lod_cell_px(style));
    ASSERT_GE(*std::min_element(levels.begin(), levels.end()), 2)
        << "the view draws a block finer than the held level";
    const auto fa = a.read_buffers();
    const auto rb = b.render(fp);
    const auto fb = b.read_buffers();
    EXPECT_EQ(ra.patches, rb.patches);
    std::size_t depth_differ = 0, silhouette_differ = 0, silhouette = 0, drawn = 0;
    for (std::size_t i = 0; i < fa.toward_depth.size(); ++i) {
      depth_differ += fa.toward_depth[i] != fb.toward_depth[i];
      drawn += renderer::far_depth(ra.view.reversed_z, fa.toward_depth[i]) < 1.0f;
    }
    for (std::size_t i = 0; i < fa.silhouette_opacity.size(); ++i) {
      silhouette_differ += fa.silhouette_opacity[i] != fb.silhouette_opacity[i];
      silhouette += fa.silhouette_opacity[i] > 0;
    }
    EXPECT_EQ(depth_differ, 0u) << fp.camera.view_alt;
    EXPECT_EQ(silhouette_differ, 0u) << fp.camera.view_alt;
    EXPECT_GT(drawn, fa.toward_depth.size() / 40) << fp.camera.view_alt;
    if (!fp.camera.orthographic) {
      EXPECT_GT(silhouette, 100u);  // the far view's ridges
    }
  }

  FrameParams near;
  near.camera.eye = Vector3d(1350, -200, 400);
  near.camera.view_az = 180;
  near.camera.view_alt = 30;
  const auto na = a.render(near);
  const auto near_levels = renderer::select_lod(*fine_levels, na.view, style.exaggeration,
                                                style.lod_error, renderer::lod_cell_px(style));
  ASSERT_LT(*std::min_element(near_levels.begin(), near_levels.end()), 2);
  const auto nb = b.render(near);
  EXPECT_LT(nb.patches, na.patches);
  const auto depth = b.read_buffers().toward_depth;
  std::size_t terrain = 0;
  for (const float d : depth) terrain += renderer::far_depth(nb.view.reversed_z, d) < 1.0f;
  EXPECT_GT(terrain, depth.size() / 4);
}

// A window of the mesh's blocks held in its place (terrain-render frame under --memory:
// hold_views reads the blocks in view and one more around them, LodHierarchy::window)
// draws the frame of the whole mesh: the terrain outside cannot show, for what hides a
// point of the view lies between it and the eye, in view too, and the scene's box (the
// view's planes, the page scale) stays the mesh's. A near view past the north-west corner
// of a 5 x 5-block mesh needs at most 3 x 3 blocks (2 x 2 here); at level 0 and at level 2
// held, the window covers the same pixels at the same depth (to 1e-4) and draws the same
// silhouettes as the whole level. Not asserted bit for bit: the window's local frame is
// moved, so the GPU's float rounding may differ (a pixel or two).
TEST(RendererGl, AWindowOfBlocksInViewDrawsTheSameFrame) {
  const terrain::GridMesh mesh = bumpy_blocks();
  terrain::test::ScratchDir dir;
  terrain::write_mesh_ply(mesh, dir.path("m.ply"));
  terrain::write_mesh_pyramid(mesh, dir.path("m.tpyr"));
  renderer::GlContext ctx;
  const int w = 480, h = 360;
  renderer::Style style = test_style();
  const renderer::Layers layers{false, true, false, true};  // the mask and the silhouettes
  FrameParams near;
  near.camera.eye = Vector3d(500, -500, 200);  // over the north-west corner, looking past it
  near.camera.view_az = 315;
  near.camera.view_alt = 15;
  near.camera.fov = 40;
  for (const int level : {0, 2}) {
    SCOPED_TRACE(::testing::Message() << "level " << level);
    std::string why;
    const auto whole = terrain::read_mesh_via_pyramid(
        dir.path("m.ply"), why, [&](const terrain::MeshPyramid&) { return level; });
    ASSERT_TRUE(whole) << why;
    auto whole_levels = std::make_shared<const renderer::LodHierarchy>(whole->levels);
    TerrainRenderer a(ctx, whole->mesh, nullptr, w, h, layers, style, whole_levels);
    const auto ra = a.render(near);
    const auto fa = a.read_buffers();
    const renderer::BlockRange r =
        renderer::blocks_in_view(*whole_levels, {ra.view}, style.exaggeration);
    ASSERT_FALSE(r.empty());
    EXPECT_EQ(r.br0, 0u);
    EXPECT_EQ(r.bc0, 0u);
    EXPECT_LE((r.br1 - r.br0) * (r.bc1 - r.bc0), 9u)
        << "the view needs more than 3 x 3 of the 5 x 5 blocks";
    const auto part =
        terrain::read_mesh_via_pyramid(dir.path("m.ply"), why, [&](const terrain::MeshPyramid&) {
          return terrain::PyramidPart{level, r.br0, r.bc0, r.br1, r.bc1};
        });
    ASSERT_TRUE(part && part->levels.window) << why;
    auto part_levels = std::make_shared<const renderer::LodHierarchy>(part->levels);
    TerrainRenderer b(ctx, part->mesh, nullptr, w, h, layers, style, part_levels);
    EXPECT_EQ(b.box().lo,
              a.box().lo - Vector3d(part->mesh.geo.origin_x - whole->mesh.geo.origin_x,
                                    part->mesh.geo.origin_y - whole->mesh.geo.origin_y, 0));
    const auto rb = b.render(near);
    const auto fb = b.read_buffers();
    std::size_t drawn_a = 0, drawn_b = 0, covered_differ = 0, depth_differ = 0, sil_a = 0,
                sil_b = 0, sil_differ = 0;
    for (std::size_t i = 0; i < fa.toward_depth.size(); ++i) {
      const bool da = renderer::far_depth(ra.view.reversed_z, fa.toward_depth[i]) < 1.0f;
      const bool db = renderer::far_depth(rb.view.reversed_z, fb.toward_depth[i]) < 1.0f;
      drawn_a += da, drawn_b += db, covered_differ += da != db;
      depth_differ +=
          da && db &&
          std::abs(fa.toward_depth[i] - fb.toward_depth[i]) > 1e-4f * std::abs(fa.toward_depth[i]);
    }
    for (std::size_t i = 0; i < fa.silhouette_opacity.size(); ++i) {
      const bool sa = fa.silhouette_opacity[i] > 0, sb = fb.silhouette_opacity[i] > 0;
      sil_a += sa, sil_b += sb, sil_differ += sa != sb;
    }
    EXPECT_GT(drawn_a, fa.toward_depth.size() / 4);
    EXPECT_LT(drawn_a,
              fa.toward_depth.size() * 9 / 10);  // the mesh's corner against the background
    EXPECT_LE(covered_differ, 2u) << drawn_a << " " << drawn_b;
    EXPECT_LE(depth_differ, 2u);
    EXPECT_GT(sil_a, 50u);
    EXPECT_LE(sil_differ, 4u) << sil_a << " " << sil_b;
  }
}

// TFT's flat patches (drawn as triangles without the tessellation stages) against every
// patch tessellated (Style::flat_patches false): on a bumpy analytic surface seen obliquely
// from near, so that near patches tessellate finer and far ones into their own triangle,
// with levels of detail (coarse patches, which face by their geometry) and without, the
// terrain covers the same pixels, its depth is the same to float rounding (a pixel or two
// seen edge on aside), its shading
// within 1/255, and the silhouettes are the same, pixel for pixel.
TEST(RendererGl, FlatPatchesDrawWhatTheTessellatorDraws) {
  const terrain::GridMesh mesh = bumpy_blocks();
  renderer::GlContext ctx;
  const int w = 480, h = 360;
  FrameParams near;
  near.camera.eye = Vector3d(1350, 300, 500);
  near.camera.view_az = 180;
  near.camera.view_alt = 25;
  for (const double lod : {0.0, 4.0}) {
    renderer::Style style = test_style();
    style.lod_error = lod;
    renderer::Style tessellated = style;
    tessellated.flat_patches = false;
    const renderer::Layers layers{false, true, false, true};  // the mask and the silhouettes
    TerrainRenderer a(ctx, mesh, nullptr, w, h, layers, style);
    TerrainRenderer b(ctx, mesh, nullptr, w, h, layers, tessellated);
    const auto ra = a.render(near), rb = b.render(near);
    const auto fa = a.read_buffers(), fb = b.read_buffers();
    EXPECT_EQ(ra.patches, rb.patches);
    std::size_t coverage = 0, terrain = 0, silhouettes = 0, grazing = 0;
    float depth = 0;
    int colour = 0;
    for (std::size_t i = 0; i < fa.toward_depth.size(); ++i) {
      const bool in_a = renderer::far_depth(ra.view.reversed_z, fa.toward_depth[i]) < 1.0f;
      const bool in_b = renderer::far_depth(rb.view.reversed_z, fb.toward_depth[i]) < 1.0f;
      coverage += in_a != in_b;
      terrain += in_a;
      if (in_a && in_b) depth = std::max(depth, std::abs(fa.toward_depth[i] - fb.toward_depth[i]));
      grazing += in_a && in_b && std::abs(fa.toward_depth[i] - fb.toward_depth[i]) > 1e-6f;
      for (int k = 0; k < 3; ++k)
        colour = std::max(colour, std::abs(int(fa.surface_rgba[4 * i + std::size_t(k)]) -
                                           int(fb.surface_rgba[4 * i + std::size_t(k)])));
    }
    for (std::size_t i = 0; i < fa.silhouette_opacity.size(); ++i)
      silhouettes += fa.silhouette_opacity[i] != fb.silhouette_opacity[i];
    EXPECT_EQ(coverage, 0u) << "lod " << lod;
    EXPECT_GT(terrain, fa.toward_depth.size() / 3) << "lod " << lod;
    // Float rounding, but for a pixel or two where the surface is seen edge on (a ridge
    // against the one behind it), whose steep depth gradient magnifies it.
    EXPECT_LE(grazing, 2u) << "lod " << lod;
    EXPECT_LE(depth, 1e-4f) << "lod " << lod;
    EXPECT_LE(colour, 1) << "lod " << lod;
    EXPECT_EQ(silhouettes, 0u) << "lod " << lod;
    EXPECT_GT(std::count_if(fa.silhouette_opacity.begin(), fa.silhouette_opacity.end(),
                            [](std::uint8_t o) { return o > 0; }),
              100)
        << "lod " << lod;
  }
}

// The creases' levels of detail (merge_crease_runs): on a map of MSH at 7.6 m a pixel, its
// creases (a network sampled at 5 m) are drawn at a coarser level (--lod-error 0.5); the
// DM pass draws that level's segments as its CPU reference scores them (samples and all),
// and its lines lie where the full-detail lines do (>= 95 % of each one's crease pixels
// within 1 px of the other's; 100 % here). Seen from near, the creases as given.
TEST(RendererGl, MergedCreasesDrawWhereTheFullDetailLinesLie) {
  const auto& sc = msh_scene();
  const auto g = renderer::build_crease_geometry(
      sc.mesh, sc.links,
      {.min_area = 0, .min_width = 0, .off_edge_runs = false, .valley_branches = false});
  const auto levels = renderer::coarser_crease_levels(g);
  ASSERT_GE(levels.size(), 2u);
  renderer::GlContext ctx;
  renderer::Style style = test_style();
  style.antialias = true;
  style.lod_error = 0.5;  // merged runs within a pixel of the line
  renderer::Style full = style;
  full.lod_error = 0;
  const int w = 160, h = 120;
  const renderer::Layers layers{false, true, true, false};
  TerrainRenderer merged(ctx, sc.mesh, &g, w, h, layers, style),
      whole(ctx, sc.mesh, &g, w, h, layers, full);
  FrameParams fp;  // a map: one scale throughout
  fp.camera.orthographic = true;
  fp.camera.view_alt = 90;
  fp.score.min_score = 0.05;
  const auto res = merged.render(fp);
  const auto m_buffers = merged.read_buffers();
  const auto res0 = whole.render(fp);
  const auto w_buffers = whole.read_buffers();
  EXPECT_EQ(res0.crease_level, 0);
  ASSERT_GE(res.crease_level, 1);
  const CreaseGeometry& lg = levels[std::size_t(res.crease_level - 1)].geometry;
  EXPECT_LT(lg.n_segments(), g.n_segments() / 2);
  const Vector3d light = terrain::light_direction(fp.light.azimuth, fp.light.altitude);
  const auto score =
      renderer::resolve_distances(fp.score, merged.box().lo, merged.box().hi, res.view.viewpoint());
  const auto drawn = renderer::segment_opacity(
      lg, res.view.viewpoint(), light, 1.0, score, style.crease_fade,
      renderer::stroke_rule(style, renderer::page_scale(res.view, merged.box())));
  const auto cpu =
      std::size_t(std::count_if(drawn.begin(), drawn.end(), [](float o) { return o > 0; }));
  EXPECT_NEAR(double(res.crease_segments), double(cpu),
              std::max(2.0, 1e-3 * double(lg.n_segments())));
  const auto gpu = merged.read_crease_samples();
  ASSERT_EQ(gpu.size(), lg.n_segments());
  const renderer::SampleComparison c = renderer::compare_samples(
      renderer::stroke_visibility(lg, renderer::segment_chains(lg), drawn, res.view, 1.0,
                                  renderer::crease_lift(style, sc.mesh), m_buffers.toward_depth,
                                  renderer::stroke_visibility_rule(style, sc.mesh)),
      gpu);
  EXPECT_GT(c.segments, 100u);
  EXPECT_LE(double(c.other_count), 0.005 * double(c.segments));
  for (int j = 0; j < 4; ++j)
    EXPECT_LE(double(c.differ[j]), 1e-3 * double(c.samples)) << "mask " << j;
  std::size_t missing = 0, extra = 0;
  const double found = covered_within_one(w_buffers.crease, m_buffers.crease, w, h, missing);
  const double placed = covered_within_one(m_buffers.crease, w_buffers.crease, w, h, extra);
  EXPECT_GE(found, 0.95);
  EXPECT_GE(placed, 0.95);
  std::printf(
      "level %d (%zu of %zu segments): %.1f %% of the full-detail crease pixels within 1 px, %.1f "
      "%% of the "
      "merged ones\n",
      res.crease_level, lg.n_segments(), g.n_segments(), 100 * found, 100 * placed);
  FrameParams near = fp;  // 50 m above its highest point, over its south edge, looking north
  near.camera.orthographic = false;
  near.camera.eye = Vector3d(sc.mesh.geo.origin_x + 320, sc.mesh.geo.origin_y - 630,
                             sc.mesh.geo.origin_z + merged.box().hi.z() + 50);
  near.camera.view_az = 0;
  near.camera.view_alt = 10;
  EXPECT_EQ(merged.render(near).crease_level, 0);
}

// A shaded frame on an opaque background composites its creases over a copy of the surface
// TFT drew, only on the 8 x 8 tiles their fragments covered (CompositePass::surface_is_base,
// CreasePass::tiles). With
// the edges layer on (here with no edge to draw: only creases of more than 180 degrees),
// the composite is drawn over every pixel instead: the two frames are the same to the
// byte, with the creases and silhouettes, pixel-exact and anti-aliased, from a low eye
// and from above.
TEST(RendererGl, CreasesOverTheCopiedSurfaceAreTheFullComposite) {
  const auto& sc = msh_scene();
  // With the runs along the grid's edge: lines there reach over the background.
  const auto g = renderer::build_crease_geometry(
      sc.mesh, sc.links,
      {.min_area = 0, .min_width = 0, .off_edge_runs = true, .valley_branches = false});
  renderer::GlContext ctx;
  const int w = 480, h = 270;
  const renderer::Layers copied{true, false, true, true};
  renderer::Layers whole = copied;
  whole.edges = true;
  for (const bool antialias : {false, true}) {
    renderer::Style style = test_style();
    style.antialias = antialias;
    style.formulated = true;
    style.background = {0.5f, 0.3f, 0.7f};  // between two 8-bit values: drawn as they round
    style.edge_kinds = renderer::kCreaseEdge;
    style.crease_angle = 180;
    TerrainRenderer a(ctx, sc.mesh, &g, w, h, copied, style),
        b(ctx, sc.mesh, &g, w, h, whole, style);
    for (const double alt : {12.0, 90.0}) {
      SCOPED_TRACE(std::string(antialias ? "anti-aliased" : "pixel-exact") + ", view altitude " +
                   std::to_string(alt));
      FrameParams fp;
      fp.camera.view_az = 200;
      fp.camera.view_alt = alt;
      fp.score.min_score = 0.05;
      const auto ra = a.render(fp), rb = b.render(fp);
      EXPECT_EQ(rb.edges, 0u);
      EXPECT_GT(ra.crease_segments, 500u);
      ASSERT_EQ(ra.rgba.size(), rb.rgba.size());
      std::size_t differ = 0, inked = 0;
      const auto surface = a.read_buffers().surface_rgba;
      for (std::size_t i = 0; i < ra.rgba.size(); i += 4) {
        differ += !std::equal(&ra.rgba[i], &ra.rgba[i] + 4, &rb.rgba[i]);
        inked += !std::equal(&ra.rgba[i], &ra.rgba[i] + 3, &surface[i]);  // a line over it
      }
      EXPECT_EQ(differ, 0u);
      EXPECT_GT(inked, std::size_t(w * h / 50));
    }
  }
}
