// renderer/core/src/lines/hachures.cpp (issue 51, the CPU reference): hachures follow the fall
// line, keep their spacing, leave flats white, stop at drawn lines, follow the tone; the
// field of a frame points down a cone's flanks.
#include "renderer/core/hachures.hpp"
#include "renderer/core/plan_map.hpp"
#include "renderer/scene/scene.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <set>

#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector2f;
using renderer::Hachure;
using renderer::HachureField;

// A field of w x h pixels falling along `fall` (unit), slope and tone given per pixel.
HachureField field(int w, int h, Vector2f fall, const std::function<float(int, int)>& slope,
                   const std::function<float(int, int)>& tone) {
  HachureField f;
  f.width = w, f.height = h;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      f.fall.push_back(fall);
      f.slope.push_back(slope(u, v));
      f.tone.push_back(tone(u, v));
    }
  return f;
}

// For every point of every hachure, the distance to the nearest point of another one.
std::vector<double> neighbour_distances(const std::vector<Hachure>& hs) {
  std::vector<double> out;
  for (std::size_t a = 0; a < hs.size(); ++a)
    for (const Vector2f& p : hs[a].points) {
      double best = 1e30;
      for (std::size_t b = 0; b < hs.size(); ++b)
        if (b != a)
          for (const Vector2f& q : hs[b].points) best = std::min(best, double((q - p).norm()));
      out.push_back(best);
    }
  return out;
}

// On a uniform slope every step of every hachure runs along the fall line (to float
// rounding), and >= 95 % of the points have their nearest other hachure between 0.5 and 2
// spacings away (issue 51's direction and spacing targets); the lines cover the field.
TEST(Hachures, FollowTheFallLineAtAnEvenSpacing) {
  const Vector2f fall(std::cos(0.5f), std::sin(0.5f));
  const HachureField f = field(
      160, 120, fall, [](int, int) { return 0.4f; }, [](int, int) { return 1.0f; });
  renderer::HachureRule rule;
  rule.spacing = 8;
  const auto hs = renderer::trace_hachures(f, rule);
  ASSERT_GE(hs.size(), 15u);
  double length = 0;
  for (const Hachure& h : hs)
    for (std::size_t k = 1; k < h.points.size(); ++k) {
      const Vector2f d = h.points[k] - h.points[k - 1];
      length += d.norm();
      EXPECT_GT(d.normalized().dot(fall), std::cos(1.0 * std::numbers::pi / 180))
          << "a step off the fall line";
    }
  const auto near = neighbour_distances(hs);
  std::size_t within = 0;
  for (double d : near) within += d >= 0.5 * rule.spacing && d <= 2 * rule.spacing;
  EXPECT_GE(double(within), 0.95 * double(near.size())) << within << " of " << near.size();
  std::cout << hs.size() << " hachures, " << length << " px; " << within << " of " << near.size()
            << " points 0.5 to 2 spacings from the next\n";
  // Lines 8 px apart over 160 x 120 px hold about 160 * 120 / 8 = 2400 px of ink.
  EXPECT_GT(length, 0.6 * 160 * 120 / 8);
  EXPECT_LT(length, 1.5 * 160 * 120 / 8);
}

// A fall line that loops (a field turning about the centre, as a surface steeper than the
// field resolves gives: issue 63's tracer ran to the 1e9-pixel cap, 9 GB in 4 minutes):
// every trace ends, none is longer than twice the frame's diagonal, and none comes back to
// where it was: it turns by at most about one turn each way from its seed (a trace that
// went on would turn once a lap).
TEST(Hachures, ALoopingFallLineEnds) {
  HachureField f = field(
      200, 160, Vector2f(1, 0), [](int, int) { return 1.2f; }, [](int, int) { return 1.0f; });
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      const Vector2f r(float(u) + 0.5f - 100.0f, float(v) + 0.5f - 80.0f);
      const Vector2f t(-r.y(), r.x());  // circles about the centre
      f.fall[std::size_t(v) * 200 + std::size_t(u)] =
          t.norm() > 0 ? Vector2f(t.normalized()) : Vector2f(1, 0);
    }
  renderer::HachureRule rule;
  rule.spacing = 1;  // one pixel: no other hachure stops a trace
  const auto hs = renderer::trace_hachures(f, rule);
  ASSERT_GT(hs.size(), 10u);
  const double diagonal = std::hypot(200.0, 160.0);
  double most = 0;
  for (const Hachure& h : hs) {
    EXPECT_LE(0.5 * double(h.points.size() - 1), 2 * 2 * diagonal + 1);  // two runs from its seed
    double turning = 0;
    for (std::size_t k = 2; k < h.points.size(); ++k) {
      const Vector2f a = h.points[k - 1] - h.points[k - 2], b = h.points[k] - h.points[k - 1];
      turning += std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)));
    }
    most = std::max(most, turning);
  }
  EXPECT_LE(most, 2 * (2 * std::numbers::pi + 1)) << "a hachure goes round more than once";
}

// Flats stay white: no hachure point where the slope is below the rule's least.
TEST(Hachures, FlatsStayWhite) {
  const HachureField f = field(
      160, 120, Vector2f(0, 1), [](int u, int) { return u < 80 ? 0.01f : 0.4f; },
      [](int, int) { return 0.5f; });
  const auto hs = renderer::trace_hachures(f, {});
  ASSERT_GT(hs.size(), 5u);
  for (const Hachure& h : hs)
    for (const Vector2f& p : h.points) EXPECT_GE(p.x(), 80.0f);
}

// Hachures stop at drawn lines and never cross them: a blocked column (a crease) across a
// slope falling east; no hachure has points on both sides, none lies on it.
TEST(Hachures, StopAtDrawnLines) {
  HachureField f = field(
      160, 120, Vector2f(1, 0), [](int, int) { return 0.4f; }, [](int, int) { return 0.5f; });
  f.blocked.assign(f.slope.size(), 0);
  for (int v = 0; v < 120; ++v) f.blocked[std::size_t(v) * 160 + 80] = 1;
  const auto hs = renderer::trace_hachures(f, {});
  std::size_t west = 0, east = 0;
  for (const Hachure& h : hs) {
    bool w = false, e = false;
    for (const Vector2f& p : h.points) {
      EXPECT_NE(int(p.x()), 80);
      (p.x() < 80 ? w : e) = true;
    }
    EXPECT_FALSE(w && e) << "a hachure crosses the line";
    west += w, east += e;
  }
  EXPECT_GT(west, 5u);
  EXPECT_GT(east, 5u);
}

// The tone sets the density: the black half of a slope holds about six times the ink of
// the white half (spacing / tone, the tone at least kMinTone: 6 px against 36 px).
TEST(Hachures, DarkerToneDrawsDenser) {
  const HachureField f = field(
      200, 120, Vector2f(0, 1), [](int, int) { return 0.4f; },
      [](int u, int) { return u < 100 ? 0.0f : 1.0f; });
  const auto hs = renderer::trace_hachures(f, {});
  double white = 0, black = 0;
  for (const Hachure& h : hs)
    for (std::size_t k = 1; k < h.points.size(); ++k)
      (h.points[k].x() < 100 ? white : black) += (h.points[k] - h.points[k - 1]).norm();
  ASSERT_GT(white, 0.0);
  EXPECT_GT(black / white, 4.0);
  EXPECT_LT(black / white, 8.0);
}

// No fans (issue 64): where the fall lines converge (a bowl, a valley head) a hachure ends
// when it comes within test_share of the spacing of another one, so no two hachures come
// nearer than that anywhere (less the tracer's half-pixel step), and the convergence
// thins out: the ink near the centre stays at most about what the spacing allows.
TEST(Hachures, ConvergingFallLinesThinOutInsteadOfFanning) {
  const int w = 160, h = 160;
  const Vector2f centre(80, 80);
  HachureField f = field(
      w, h, Vector2f(1, 0), [](int, int) { return 0.4f; }, [](int, int) { return 1.0f; });
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const Vector2f to = centre - Vector2f(float(u) + 0.5f, float(v) + 0.5f);
      f.fall[std::size_t(v * w + u)] = to.norm() > 1e-3f ? to.normalized() : Vector2f(1, 0);
    }
  renderer::HachureRule rule;
  rule.spacing = 6;
  const auto hs = renderer::trace_hachures(f, rule);
  ASSERT_GT(hs.size(), 30u);
  const auto near = neighbour_distances(hs);
  const double least = *std::min_element(near.begin(), near.end());
  EXPECT_GE(least, rule.test_share * rule.spacing - 0.5)
      << "two hachures closer than the stop share";
  // Within 20 px of the centre, a circle's circumference holds at most 2 pi r / (share x
  // spacing) hachures: count the hachures that reach inside it.
  std::size_t inside = 0;
  for (const Hachure& hh : hs)
    inside += std::any_of(hh.points.begin(), hh.points.end(),
                          [&](const Vector2f& p) { return (p - centre).norm() < 20; });
  EXPECT_LE(double(inside), 2 * std::numbers::pi * 20 / (rule.test_share * rule.spacing) + 1);
  std::cout << hs.size() << " hachures, " << inside << " reach 20 px of the centre, nearest pair "
            << least << " px\n";
}

// Every point of a hachure keeps the stop share of the smaller local spacing (spacing /
// tone) from every point of every other hachure, where the tone, and so the spacing, swings
// from 6 to 36 px over a few pixels and the fall lines converge: the tracer tests a point
// only where it may have come that near since its last test (the room it then had, and how
// much the spacing may have grown), so a rule that skipped too much would show here.
TEST(Hachures, EveryPointKeepsTheStopShareOfTheSmallerSpacing) {
  const int w = 200, h = 150;
  const Vector2f centre(100, 75);
  HachureField f = field(
      w, h, Vector2f(1, 0), [](int, int) { return 0.4f; },
      [](int u, int v) { return float(0.6 + 0.45 * std::sin(0.21 * u) * std::cos(0.17 * v)); });
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const Vector2f to = centre - Vector2f(float(u) + 0.5f, float(v) + 0.5f);
      f.fall[std::size_t(v * w + u)] =
          to.norm() > 1e-3f
              ? Vector2f(to.normalized() + 0.6f * Vector2f(-to.y(), to.x()).normalized())
                    .normalized()
              : Vector2f(1, 0);
    }
  renderer::HachureRule rule;
  rule.spacing = 6;
  const auto hs = renderer::trace_hachures(f, rule);
  ASSERT_GT(hs.size(), 40u);
  const auto spacing = [&](const Vector2f& p) {
    const std::size_t i = std::size_t(long(p.y())) * std::size_t(w) + std::size_t(long(p.x()));
    return rule.spacing / std::clamp(double(f.tone[i]), renderer::kMinTone, 1.0);
  };
  std::size_t pairs = 0, close = 0;
  double least_margin = 1e30;
  for (std::size_t a = 0; a < hs.size(); ++a)
    for (std::size_t b = a + 1; b < hs.size(); ++b)
      for (const Vector2f& p : hs[a].points)
        for (const Vector2f& q : hs[b].points) {
          const double d = rule.test_share * std::min(spacing(p), spacing(q));
          if ((q - p).squaredNorm() > 4 * d * d) continue;
          ++pairs;
          const double margin = double((q - p).norm()) - d;
          least_margin = std::min(least_margin, margin);
          close += margin < -1e-4;
        }
  EXPECT_EQ(close, 0u) << "of " << pairs << " pairs within twice the share; least margin "
                       << least_margin << " px";
  EXPECT_GT(pairs, 1000u);  // the test looked at near pairs
  std::cout << hs.size() << " hachures, " << pairs << " near pairs, least margin " << least_margin
            << " px\n";
}

// The field of a frame: a cone seen from straight above (the renderer's TFT depth), every
// pixel's fall line points away from the apex in the image (>= 95 % of the cone's pixels
// within 10 degrees), and the slope is the cone's, atan(0.5).
TEST(Hachures, TheFieldOfAConePointsDownItsFlanks) {
  const double size = 1000;
  const auto cone = terrain::test::function_mesh(101, 101, 10, [&](double x, double y) {
    return 600 - 0.5 * std::hypot(x - size / 2, y + size / 2);
  });
  renderer::GlContext ctx;
  renderer::Style style;
  style.antialias = false;
  renderer::TerrainRenderer r(ctx, cone, nullptr, 200, 200, renderer::Layers{}, style);
  renderer::FrameParams fp;
  fp.camera.view_alt = 90;
  fp.camera.view_az = 0;
  const auto res = r.render(fp);
  const auto buffers = r.read_buffers();
  const HachureField f = renderer::hachure_field(cone, res.view, 1.0, buffers.toward_depth);
  const renderer::Projected apex =
      renderer::project(res.view, Eigen::Vector3d(size / 2, -size / 2, 600));
  std::size_t flank = 0, along = 0, slope_ok = 0;
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      const Vector2f away(float(u + 0.5 - apex.u), float(v + 0.5 - apex.v));
      const std::size_t i = std::size_t(v) * std::size_t(f.width) + std::size_t(u);
      if (!f.terrain(u, v) || away.norm() < 10 || away.norm() > 80)
        continue;  // the flanks, away from apex and foot
      ++flank;
      along += f.fall[i].dot(away.normalized()) > std::cos(10 * std::numbers::pi / 180);
      slope_ok += std::abs(f.slope[i] - std::atan(0.5)) < 0.02;
    }
  ASSERT_GT(flank, 1000u);
  EXPECT_GE(double(along), 0.95 * double(flank));
  EXPECT_GE(double(slope_ok), 0.95 * double(flank));
  const auto hs = renderer::trace_hachures(f, {});
  EXPECT_GT(hs.size(), 20u);
}

// The field on the GPU (TerrainRenderer::hachure_field, hachure_field.comp.glsl) against
// the CPU reference (hachure_field: the PN surface above each unprojected pixel) on MSH at
// 50 m, the patches tessellated finely, at exaggeration 1 and 2, the light's tone and the
// slope's: the same terrain pixels, and on >= 95 % of the steep ones the fall line within
// 5 degrees, the slope within 0.02 rad, the tone within 0.03 and the height within 1 m. At
// exaggeration 2 the slope within 0.04 and the tone within 0.05: the GPU draws the PN
// patches of the exaggerated mesh, the reference exaggerates the true PN surface (they
// differ a little; at e = 1 they are the same surface).
TEST(Hachures, GpuFieldMatchesTheCpuReference) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  renderer::GlContext ctx;
  for (const double e : {1.0, 2.0})
    for (const bool light_tone : {true, false}) {
      SCOPED_TRACE(::testing::Message()
                   << "exaggeration " << e << (light_tone ? ", light" : ", slope"));
      renderer::Style style;
      style.exaggeration = e;
      style.pixels_per_edge =
          1;  // the patches tessellated finely: the drawn surface is the PN surface
      renderer::TerrainRenderer r(ctx, mesh, nullptr, 320, 180, renderer::Layers{}, style);
      renderer::FrameParams fp;
      fp.camera.view_az = 250;
      fp.camera.view_alt = 40;
      const auto res = r.render(fp);
      const Eigen::Vector3d light = terrain::light_direction(fp.light.azimuth, fp.light.altitude);
      const HachureField gpu = r.hachure_field(res.view, light_tone);
      const HachureField cpu = renderer::hachure_field(
          mesh, res.view, e, r.read_buffers().toward_depth, light_tone ? &light : nullptr);
      std::size_t both = 0, either = 0, steep = 0, fall = 0, slope = 0, tone = 0, height = 0;
      for (std::size_t i = 0; i < gpu.slope.size(); ++i) {
        const bool g = !std::isnan(gpu.slope[i]), c = !std::isnan(cpu.slope[i]);
        either += g || c, both += g && c;
        if (!(g && c) || cpu.slope[i] < 0.05f) continue;
        ++steep;
        fall += gpu.fall[i].dot(cpu.fall[i]) > std::cos(5 * std::numbers::pi / 180);
        slope += std::abs(gpu.slope[i] - cpu.slope[i]) < (e == 1 ? 0.02f : 0.04f);
        tone += std::abs(gpu.tone[i] - cpu.tone[i]) < (e == 1 ? 0.03f : 0.05f);
        height += std::abs(gpu.elevation[i] - cpu.elevation[i]) < 1.0f;
      }
      ASSERT_GT(steep, 10000u);
      EXPECT_GE(double(both), 0.99 * double(either));
      EXPECT_GE(double(fall), 0.95 * double(steep));
      EXPECT_GE(double(slope), 0.95 * double(steep));
      EXPECT_GE(double(tone), 0.95 * double(steep));
      EXPECT_GE(double(height), 0.95 * double(steep));
      std::cout << "e " << e << (light_tone ? " light" : " slope") << ": terrain " << both << " of "
                << either << ", fall " << double(fall) / double(steep) << ", slope "
                << double(slope) / double(steep) << ", tone " << double(tone) / double(steep)
                << ", height " << double(height) / double(steep) << "\n";
    }
}

// Frame-to-frame coherence (issue 51): MSH at 50 m seen from a camera and from the same
// camera moved 40 m sideways. Hachures seeded on the ground (surface_seeds) move with it:
// >= 60 % of the first frame's hachure points, carried to the second frame on the surface,
// land within 1 px of its hachures, more than with seeds on the pixel grid alone; a frame
// against itself gives 1.
TEST(Hachures, SurfaceSeedsKeepHachuresOnTheGround) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  renderer::GlContext ctx;
  renderer::Style style;
  renderer::TerrainRenderer r(ctx, mesh, nullptr, 480, 270, renderer::Layers{}, style);
  const Eigen::Vector3d origin(mesh.geo.origin_x, mesh.geo.origin_y, mesh.geo.origin_z);
  struct Frame {
    renderer::View view;
    std::vector<float> depth;
    HachureField field;
  };
  auto frame = [&](double dx) {
    renderer::FrameParams fp;
    fp.camera.eye = origin + Eigen::Vector3d(1500 + dx, -6000, 3500);
    fp.camera.view_az = 0;
    fp.camera.view_alt = 35;
    const auto res = r.render(fp);
    return Frame{res.view, r.read_buffers().toward_depth, r.hachure_field(res.view, true)};
  };
  const Frame a = frame(0), b = frame(40);
  const renderer::HachureRule rule;
  const double cell = 2.0 * renderer::page_scale(a.view, r.box()) * rule.spacing;
  auto coherence = [&](bool on_ground) {
    const auto ha = renderer::trace_hachures(
        a.field, rule,
        on_ground ? renderer::surface_seeds(a.view, a.depth, rule.spacing, cell)
                  : std::vector<Vector2f>{});
    const auto hb = renderer::trace_hachures(
        b.field, rule,
        on_ground ? renderer::surface_seeds(b.view, b.depth, rule.spacing, cell)
                  : std::vector<Vector2f>{});
    std::vector<Eigen::Vector3f> points;
    const Eigen::Matrix4d inverse = a.view.view_projection().inverse();
    for (const Hachure& h : ha)
      for (const Vector2f& p : h.points)
        if (const auto q = renderer::surface_point(a.view, inverse, a.depth, p.x(), p.y()))
          points.push_back(q->cast<float>());
    const auto self = renderer::hachure_coherence(points, a.view, a.depth,
                                                  renderer::hachure_stats(a.field, ha, rule).ink);
    EXPECT_EQ(self.share(), 1.0);
    const auto c = renderer::hachure_coherence(points, b.view, b.depth,
                                               renderer::hachure_stats(b.field, hb, rule).ink);
    EXPECT_GT(c.counted, points.size() / 2);
    return c.share();
  };
  const double ground = coherence(true), grid = coherence(false);
  std::cout << "coherence: seeds on the ground " << ground << ", on the pixel grid " << grid
            << "\n";
  EXPECT_GE(ground, 0.6);
  EXPECT_GT(ground, grid);
}

// Imhof's rows: on a uniform slope whose height falls along the fall line, every hachure
// lies within one band between two form lines and ends short of them; the rows abut (at
// least 4 bands drawn) and each still keeps its spacing.
TEST(Hachures, RowsEndAtFormLines) {
  const Vector2f fall(0.0f, 1.0f);  // downhill = down the image
  HachureField f = field(
      120, 160, fall, [](int, int) { return 0.4f; }, [](int, int) { return 1.0f; });
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) f.elevation.push_back(float(1000 - v));  // a metre a pixel
  renderer::HachureRule rule;
  rule.spacing = 6;
  rule.row_interval = 30;
  const auto hs = renderer::trace_hachures(f, rule);
  ASSERT_GE(hs.size(), 40u);
  std::set<long> rows;
  for (const Hachure& h : hs) {
    rows.insert(h.row);
    for (const Vector2f& p : h.points) {
      const double z = 1000 - std::floor(p.y());  // the elevation of the pixel the point is in
      EXPECT_EQ(long(std::floor(z / 30)), h.row) << p.transpose();
    }
    // A hachure that spans its band ends at least half a pixel from the form lines.
    const double top = 1000 - double(h.row + 1) * 30,
                 bottom = 1000 - double(h.row) * 30;  // image v of the lines
    EXPECT_GE(h.points.front().y() - top, 0.49) << h.row;
    EXPECT_GE(bottom + 1 - h.points.back().y(), 0.49) << h.row;
  }
  EXPECT_GE(rows.size(), 4u);
  // Without heights, rows are refused.
  HachureField no_heights = f;
  no_heights.elevation.clear();
  EXPECT_THROW(renderer::trace_hachures(no_heights, rule), terrain::Error);
}

// Plan view: the hachures of a cone from straight above carry map coordinates. Their steps
// run away from the apex in the world (>= 95 % within 10 degrees), their slope is the
// cone's, and the plan's corner and scale are the mesh's extent.
TEST(Hachures, PlanViewOfAConeRunsDownItInMapCoordinates) {
  const double size = 1000;
  auto cone = terrain::test::function_mesh(101, 101, 10, [&](double x, double y) {
    return 600 - 0.5 * std::hypot(x - size / 2, y + size / 2);
  });
  const renderer::PlanView plan = renderer::plan_view(cone, 4);
  EXPECT_EQ(plan.width, 250);
  EXPECT_EQ(plan.height, 250);
  EXPECT_NEAR(plan.x0, 0, 1e-9);
  EXPECT_NEAR(plan.y0, 0, 1e-9);
  const renderer::HachureField f = renderer::plan_hachure_field(cone, plan, nullptr);
  const auto hs = renderer::trace_hachures(f, {});
  ASSERT_GT(hs.size(), 30u);
  std::size_t steps = 0, along = 0, slope_ok = 0, points = 0;
  for (const Hachure& h : hs)
    for (std::size_t k = 0; k < h.points.size(); ++k) {
      const Eigen::Vector2d q = renderer::plan_to_local(plan, h.points[k]);
      const Eigen::Vector2d away = q - Eigen::Vector2d(size / 2, -size / 2);
      if (away.norm() < 40 || away.norm() > 460) continue;  // off the apex and the foot
      ++points;
      slope_ok += std::abs(h.slope[k] - std::atan(0.5)) < 0.02;
      if (k == 0) continue;
      const Eigen::Vector2d step = q - renderer::plan_to_local(plan, h.points[k - 1]);
      ++steps;
      along += step.normalized().dot(away.normalized()) > std::cos(10 * std::numbers::pi / 180);
    }
  ASSERT_GT(steps, 1000u);
  EXPECT_GE(double(along), 0.95 * double(steps));
  EXPECT_GE(double(slope_ok), 0.95 * double(points));
  EXPECT_THROW(renderer::plan_view(cone, 0), terrain::Error);
}

// Figure and ground on a plan map (issue 64): a valley side whose slope grows across it,
// z = a x^2 (x east, 0 .. 1000 m: 0 to 45 degrees), mapped with no option. No hachure
// reaches ground flatter than the relative threshold (PlanHachureOptions::min_slope_share
// of the 99th-percentile slope), and the ink per area grows with the slope (Lehmann's
// rule, the plan map's default): the steepest fifth carries at least 3 times the ink of the
// fifth just above the threshold.
// A plan map of a mesh with no-data around a disc of data (docs/dem2mesh.md, "No-data"):
// a cone, its ring outside the data; hachures only on the disc (within a cell of its edge),
// and there, many of them; the outline, one ring along the disc's edge.
TEST(Hachures, PlanMapsStopAtTheDatasOutline) {
  auto cone = terrain::test::function_mesh(
      101, 101, 10, [](double x, double y) { return 800 - std::hypot(x - 500, y + 500); });
  cone.filled.assign(cone.n_vertices(), terrain::kFromData);
  for (std::size_t r = 0; r < 101; ++r)
    for (std::size_t c = 0; c < 101; ++c)
      if (std::hypot(double(r) - 50, double(c) - 50) > 35)
        cone.filled[r * 101 + c] = terrain::kOutside;
  const renderer::PlanHachures h = renderer::plan_hachures(cone, {});
  ASSERT_GT(h.hachures.size(), 50u);
  for (const Hachure& hh : h.hachures)
    for (const Eigen::Vector2f& p : hh.points) {
      const Eigen::Vector2d q = renderer::plan_to_local(h.plan, p);
      ASSERT_LE(std::hypot(q.x() - 500, q.y() + 500), 360.0) << q.transpose();
    }
  // The outline: one closed ring on the disc's edge (the data's vertices within 35 cells),
  // a staircase of cell edges and diagonals, no shorter than the circle.
  ASSERT_EQ(h.outline.size(), 1u);
  const auto& ring = h.outline[0];
  EXPECT_EQ(ring.front(), ring.back());
  double length = 0;
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const Eigen::Vector2d q = renderer::plan_to_local(h.plan, ring[k]);
    EXPECT_NEAR(std::hypot(q.x() - 500, q.y() + 500), 345.0, 11.0) << q.transpose();
    if (k) length += double((ring[k] - ring[k - 1]).norm()) * h.plan.scale;
  }
  EXPECT_GT(length, 2 * std::numbers::pi * 340);
  EXPECT_LT(length, 1.35 * 2 * std::numbers::pi * 350);
}

TEST(Hachures, PlanMapsLeaveGentleGroundWhiteAndInkTheSteep) {
  auto side =
      terrain::test::function_mesh(101, 101, 10, [](double x, double) { return 0.0005 * x * x; });
  const renderer::PlanHachures h = renderer::plan_hachures(side, {});
  ASSERT_GT(h.hachures.size(), 20u);
  // The threshold: 0.3 of the 99th percentile of slopes (atan(2 a x) at x = 990 m: 44.7 deg).
  EXPECT_NEAR(h.min_slope, 0.3 * std::atan(0.001 * 990), 0.01);
  const double x_min = std::tan(h.min_slope) / 0.001;  // where the slope reaches it
  std::vector<double> ink(5, 0.0);                     // length in each fifth of x_min .. 1000
  for (const Hachure& hh : h.hachures)
    for (std::size_t k = 0; k < hh.points.size(); ++k) {
      const Eigen::Vector2d q = renderer::plan_to_local(h.plan, hh.points[k]);
      EXPECT_GE(q.x(), x_min - 2 * h.plan.scale) << "a hachure on ground under the threshold";
      if (k == 0) continue;
      const double len = (q - renderer::plan_to_local(h.plan, hh.points[k - 1])).norm();
      const int fifth = std::clamp(int((q.x() - x_min) / (1000 - x_min) * 5), 0, 4);
      ink[std::size_t(fifth)] += len;
    }
  EXPECT_GE(ink[4], 3 * ink[0]) << ink[0] << " " << ink[4];
}

// Figure and ground in a frame (issue 64): the same valley side, z = a x^2, seen obliquely
// with the default hachures: the frame's threshold is a fifth of its 99th-percentile drawn
// slope, no hachure point lies on flatter ground, and none reaches the terrain's outline
// (every point three quarters of a pen's width inside it).
TEST(Hachures, FramesLeaveGentleGroundWhiteAndStayInsideTheOutline) {
  auto side =
      terrain::test::function_mesh(101, 101, 10, [](double x, double) { return 0.0005 * x * x; });
  renderer::GlContext ctx;
  renderer::Style style;
  renderer::Layers layers;
  layers.hachures = true;
  renderer::TerrainRenderer r(ctx, side, nullptr, 480, 270, layers, style);
  renderer::FrameParams fp;
  fp.camera.view_az = 90;  // looking east, up the side
  fp.camera.view_alt = 40;
  const auto res = r.render(fp);
  const renderer::FrameBuffers buffers = r.read_buffers();
  renderer::Scene scene;
  scene.mesh = side;
  const renderer::TracedHachures t = renderer::trace_frame_hachures(scene, r, res, buffers, style);
  ASSERT_GT(t.hachures.size(), 20u);
  EXPECT_NEAR(t.rule.min_slope, 0.2 * renderer::slope_percentile(t.field, 0.99), 0.02);
  EXPECT_GT(t.rule.min_slope, 0.1);  // well above the absolute 3 degrees (0.05)
  const int margin = int(std::ceil(0.75 * style.hachure_width));
  std::size_t below = 0, near_outline = 0, points = 0;
  for (const Hachure& h : t.hachures)
    for (std::size_t k = 0; k < h.points.size(); ++k) {
      ++points;
      below += h.slope[k] < t.rule.min_slope - 1e-4f;
      const long u = long(h.points[k].x()), v = long(h.points[k].y());
      bool outline = false;
      for (long dv = -margin; dv <= margin; ++dv)
        for (long du = -margin; du <= margin; ++du) {
          const long x = u + du, y = v + dv;
          const bool sky = x < 0 || y < 0 || x >= 480 || y >= 270 ||
                           renderer::far_depth(res.view.reversed_z,
                                               buffers.toward_depth[std::size_t(y * 480 + x)]) >= 1;
          outline = outline || sky;
        }
      near_outline += outline;
    }
  EXPECT_EQ(below, 0u) << "of " << points;
  EXPECT_EQ(near_outline, 0u) << "of " << points;
}

}  // namespace
