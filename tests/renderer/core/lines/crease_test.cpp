// renderer/core/src/lines/crease.cpp: the crease score (hand-computed values, the distances across
// a scene) and the opacity that fades in over the band.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>

#include <map>
#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/pipeline.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/line_stats.hpp"
#include "renderer/core/pel.hpp"
#include "renderer/core/silhouette.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/timing.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/shader.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "renderer/scene/scene.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/pn_surface.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector3d;
using renderer::CreaseGeometry;
using renderer::FrameParams;
using renderer::TerrainRenderer;

TEST(CreaseScore, HandComputedValues) {
  renderer::CreaseScoreParams p;
  p.sw = 0.1, p.iw = 0.3, p.fw = 0.6;  // the paper's Table 5 weights
  p.min_score = 0.2;
  p.falloff = 0.0;
  p.far_distance = 1000;
  const Vector3d up(0, 0, 1);
  // Flat ground lit from straight above: sc = 0, ic = 0, raw = 0.6 * 0.6 / 1.0 = 0.36.
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, 0, p), 0.16, 1e-12);
  p.literal_divisor = true;  // 0.36 / 3
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, 0, p), 0.12 - 0.2, 1e-12);
  p.literal_divisor = false;
  // A 60-degree slope facing away from a light at 45 degrees: n = (sin60, 0, cos60),
  // l = (-cos45, 0, sin45): sc = 0.5, ic = 1 - (-0.6124 + 0.3536).
  const Vector3d n(std::sin(std::numbers::pi / 3), 0, 0.5), l(-std::sqrt(0.5), 0, std::sqrt(0.5));
  const double ic = 1 - n.dot(l);
  EXPECT_NEAR(renderer::crease_score(n, 0.0, l, 0, p), (0.1 * 0.5 + 0.3 * ic) / 1.0 - 0.2, 1e-12);
  // Distance law: rs_min(d) = 0.2 + 0.8 * k * clamp(d / far): k = 0.5 at d = far / 2 -> 0.4.
  p.falloff = 0.5;
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, 500, p), 0.36 - 0.4, 1e-12);
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, 5000, p), 0.36 - 0.6, 1e-12);  // clamped at far
}

TEST(CreaseScore, DistancesAcrossTheScene) {
  renderer::CreaseScoreParams p;
  p.min_score = 0.2;
  p.falloff = 0.5;
  const Vector3d lo(0, 0, 0), hi(100, 200, 50);
  const auto outside = renderer::resolve_distances(p, lo, hi, Vector3d(300, 100, 25));
  EXPECT_NEAR(outside.near_distance, 200, 1e-9);
  EXPECT_NEAR(outside.far_distance, std::sqrt(300.0 * 300 + 100 * 100 + 25 * 25), 1e-9);
  const Vector3d up(0, 0, 1);  // raw score 0.6 * 1/3 = 0.2 with flow 0.6 and equal weights
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, outside.near_distance, outside), 0.2 - 0.2,
              1e-12);
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, outside.far_distance, outside), 0.2 - 0.6, 1e-12);
  const auto inside = renderer::resolve_distances(p, lo, hi, Vector3d(50, 50, 25));
  EXPECT_EQ(inside.near_distance, 0.0);
  EXPECT_NEAR(inside.far_distance, std::sqrt(50.0 * 50 + 150 * 150 + 25 * 25), 1e-9);
  p.far_distance = 1000;
  const auto given = renderer::resolve_distances(p, lo, hi, Vector3d(300, 100, 25));
  EXPECT_EQ(given.far_distance, 1000.0);
  EXPECT_EQ(given.near_distance, 0.0);
}

// Fading: a segment's opacity is the lower score of its ends over the fade band, clamped
// to 1; 0 below the threshold; 1 above it when the band is 0.
TEST(CreaseScore, OpacityFadesInOverTheBand) {
  CreaseGeometry g;
  const Vector3d up(0, 0, 1);
  for (float flow : {0.3f, 0.45f, 0.9f, 0.1f}) {  // scores flow / 3 - 0.1: 0, 0.05, 0.2, -0.0667
    g.positions.push_back(Eigen::Vector3f(0, 0, 0));
    g.normals.push_back(Eigen::Vector3f(0, 0, 1));
    g.flow.push_back(flow);
  }
  g.segments = {0, 1, 1, 2, 2, 2, 2, 3};
  renderer::CreaseScoreParams p;
  p.min_score = 0.1;
  p.falloff = 0;
  p.far_distance = 1;
  const auto a = renderer::segment_opacity(g, Vector3d(0, 0, 10), up, 1.0, p, 0.1);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_NEAR(a[0], 0.0, 1e-6);  // the lower end scores 0: at the threshold, invisible
  EXPECT_NEAR(a[1], 0.5, 1e-6);  // 0.05 / 0.1
  EXPECT_NEAR(a[2], 1.0, 1e-6);  // 0.2 / 0.1, clamped
  EXPECT_EQ(a[3], 0.0f);         // below the threshold
  const auto cut = renderer::segment_opacity(g, Vector3d(0, 0, 10), up, 1.0, p, 0.0);
  EXPECT_EQ(cut, (std::vector<float>{1, 1, 1, 0}));
}

// Channels selected by the page (StrokeRule::min_area, Style::page_min_area): a vertex
// draining less than the page's area scores -1, so a segment with such an end is not drawn,
// whatever its score; the rule grows as the square root of the page scale (4 ha at 10 m a
// pixel: 2 ha at 2.5 m, 8 ha at 40 m).
TEST(CreaseScore, ChannelsBeginAtThePagesArea) {
  CreaseGeometry g;
  const Vector3d up(0, 0, 1);
  for (float area :
       {5000.0f, 15000.0f, 30000.0f, 60000.0f}) {  // a chain from a channel head downstream
    g.positions.push_back(Eigen::Vector3f(0, 0, 0));
    g.normals.push_back(Eigen::Vector3f(0, 0, 1));
    g.flow.push_back(0.9f);  // scores 0.2 everywhere
    g.area.push_back(area);
  }
  g.segments = {0, 1, 1, 2, 2, 3};
  renderer::CreaseScoreParams p;
  p.min_score = 0.1;
  p.falloff = 0;
  p.far_distance = 1;
  auto drawn = [&](double min_area) {
    return renderer::segment_opacity(g, Vector3d(0, 0, 10), up, 1.0, p, 0.0, {0, 0, min_area});
  };
  EXPECT_EQ(drawn(0), (std::vector<float>{1, 1, 1}));
  EXPECT_EQ(drawn(10000), (std::vector<float>{0, 1, 1}));
  EXPECT_EQ(drawn(20000), (std::vector<float>{0, 0, 1}));
  EXPECT_EQ(
      drawn(60000),
      (std::vector<float>{0, 0, 0}));  // the outlet's own area, but its upstream end drains less
  renderer::Style style;
  style.page_min_area = 40000;
  EXPECT_DOUBLE_EQ(renderer::stroke_rule(style, 10.0).min_area, 40000.0);
  EXPECT_DOUBLE_EQ(renderer::stroke_rule(style, 2.5).min_area, 20000.0);
  EXPECT_DOUBLE_EQ(renderer::stroke_rule(style, 40.0).min_area, 80000.0);
}

// The default view on an analytic volcano: a cone in the north-east of a plain with a
// crater breached to the north. The relief window holds the cone, the eye looks into the
// breach (from the north, bearing 180), the cone's centre falls in the middle third of the
// image and the eye is above the terrain; the light comes from the left of the view.

}  // namespace

namespace {

// A main stem of 17 vertices along an arc (radius 100 m, 0.05 rad apart) from a channel
// head (0) to an outlet (16), and a straight tributary 17 -> 18 -> 19 joining it at 8.
CreaseGeometry branching_network() {
  CreaseGeometry g;
  auto add = [&](const Eigen::Vector3f& p) {
    g.source.push_back(std::uint32_t(g.positions.size()));
    g.positions.push_back(p);
    g.normals.push_back(Eigen::Vector3f(0, 0, 1));
    g.flow.push_back(0.05f * float(g.flow.size()));
    g.share.push_back(0.01f * float(g.share.size()));
    g.area.push_back(100.0f * float(g.area.size()));
  };
  for (int i = 0; i <= 16; ++i)
    add(Eigen::Vector3f(100 * std::cos(0.05 * i), 100 * std::sin(0.05 * i), 0));
  for (int i = 0; i < 16; ++i)
    g.segments.insert(g.segments.end(), {std::uint32_t(i), std::uint32_t(i + 1)});
  const Eigen::Vector3f junction = g.positions[8];
  for (int i = 3; i >= 1; --i) add(junction + Eigen::Vector3f(10.0f * float(i), 0, 0));
  g.segments.insert(g.segments.end(), {17, 18, 18, 19, 19, 8});
  return g;
}

}  // namespace

// Levels of detail for the creases: with no tolerance to stop it, a level keeps the breaks
// (heads, junctions, outlets) and every step-th vertex along each run, at their own
// positions, each scored (normal, flow, area) as the middle vertex of the run its leaving
// segment replaces; its segments cover every fine segment once, in the order of the fine
// segments they begin with; its error is the arc's sagitta over the merged chord
// (R (1 - cos(step theta / 2))), 0 on the straight tributary. A tolerance between the
// sagittas of 3 and 4 segments merges the arc's segments 3 at a time.
TEST(CreaseLevels, MergedRunsKeepTheBreaksAndVerticesWithinTheTolerance) {
  const CreaseGeometry g = branching_network();
  const double none = std::numeric_limits<double>::infinity();
  const renderer::CreaseLevel l4 = renderer::merge_crease_runs(g, 4, none);
  EXPECT_EQ(l4.geometry.n_segments(), 5u);
  EXPECT_EQ(l4.first, (std::vector<std::uint32_t>{0, 4, 8, 12, 16}));
  EXPECT_EQ(l4.last, (std::vector<std::uint32_t>{3, 7, 11, 15, 18}));
  ASSERT_EQ(l4.geometry.positions.size(),
            6u);  // 0, 4, 8, 12, 16 on the stem, 17 (the tributary's head)
  // The fine vertex downstream of fine segment t, and the middle one of a merged segment's run.
  const auto below = [&](std::uint32_t t) { return g.segments[2 * t + 1]; };
  const auto next = [&](std::uint32_t t) {
    std::uint32_t u = 0;
    while (g.segments[2 * u] != below(t)) ++u;
    return u;
  };
  for (std::size_t s = 0; s < 5; ++s) {
    const std::uint32_t a = l4.geometry.segments[2 * s], b = l4.geometry.segments[2 * s + 1];
    const std::uint32_t fa = g.segments[2 * l4.first[s]], fb = below(l4.last[s]);
    EXPECT_EQ(l4.geometry.positions[a], g.positions[fa]);
    EXPECT_EQ(l4.geometry.positions[b], g.positions[fb]);
    EXPECT_EQ(l4.geometry.source[a], g.source[fa]);
    EXPECT_EQ(l4.geometry.share[a], g.share[fa]);
    std::vector<std::uint32_t> dropped;
    for (std::uint32_t t = l4.first[s]; t != l4.last[s]; t = next(t)) dropped.push_back(below(t));
    const std::uint32_t m = dropped[(dropped.size() - 1) / 2];
    EXPECT_EQ(l4.geometry.flow[a], g.flow[m]) << s;
    EXPECT_EQ(l4.geometry.area[a], g.area[m]) << s;
    EXPECT_EQ(l4.geometry.normals[a], g.normals[m]) << s;
  }
  const std::uint32_t outlet = l4.geometry.segments[2 * 3 + 1];  // no segment leaves it: its own
  EXPECT_EQ(l4.geometry.flow[outlet], g.flow[16]);
  EXPECT_NEAR(l4.error_metres, 100 * (1 - std::cos(0.1)), 1e-4);
  // Every fine segment is in exactly one merged run (first .. last along the links).
  for (const int step : {1, 2, 3, 4, 8, 32})
    for (const double tolerance : {none, 0.3, 0.0}) {
      const renderer::CreaseLevel l = renderer::merge_crease_runs(g, step, tolerance);
      std::vector<int> covered(g.n_segments(), 0);
      for (std::size_t s = 0; s < l.first.size(); ++s)
        for (std::uint32_t t = l.first[s];; t = next(t)) {
          ++covered[t];
          if (t == l.last[s]) break;
        }
      EXPECT_EQ(covered, std::vector<int>(g.n_segments(), 1))
          << "step " << step << " tolerance " << tolerance;
      EXPECT_LE(l.error_metres, tolerance);
      if (step == 1 || tolerance == 0) {  // nothing on the arc merged
        EXPECT_EQ(l.error_metres, 0.0);
        EXPECT_GE(l.geometry.n_segments(), 17u);
      }
    }
  EXPECT_EQ(renderer::merge_crease_runs(g, 32, none).geometry.n_segments(), 3u);  // one a run
  EXPECT_EQ(renderer::merge_crease_runs(g, 32, 0.0).geometry.n_segments(),
            17u);  // the straight tributary merged
  const renderer::CreaseLevel l3 = renderer::merge_crease_runs(g, 4, 0.3);
  EXPECT_EQ(l3.first, (std::vector<std::uint32_t>{0, 3, 6, 8, 11, 14, 16}));
  EXPECT_NEAR(l3.error_metres, 100 * (std::cos(0.025) - std::cos(0.075)), 1e-4);
  EXPECT_THROW(renderer::merge_crease_runs(g, 0, none), terrain::Error);
}

// The levels a renderer holds halve the segments while they shrink by a quarter at least
// (19 -> 10 -> 5 -> 3; 16 would leave 3; the tolerances, 0.625 m a step, hold the arc's
// sagittas), their errors grow, and a frame draws the coarsest whose error spans at most
// the bound in pixels at the nearest surface.
TEST(CreaseLevels, HeldWhileTheyShrinkAndChosenByTheirErrorOnScreen) {
  const auto levels = renderer::coarser_crease_levels(branching_network());
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[0].step, 2);
  EXPECT_EQ(levels[2].step, 8);
  EXPECT_EQ(levels[0].geometry.n_segments(), 10u);
  EXPECT_EQ(levels[1].geometry.n_segments(), 5u);
  EXPECT_EQ(levels[2].geometry.n_segments(), 3u);
  EXPECT_LT(levels[0].error_metres, levels[1].error_metres);
  EXPECT_LT(levels[1].error_metres, levels[2].error_metres);
  const std::vector<double> errors{0.5, 2, 8};
  EXPECT_EQ(renderer::select_crease_level(errors, 10, 0.5), 2);  // 5 m allowed
  EXPECT_EQ(renderer::select_crease_level(errors, 4, 0.5), 2);   // 2 m: at the bound
  EXPECT_EQ(renderer::select_crease_level(errors, 3.9, 0.5), 1);
  EXPECT_EQ(renderer::select_crease_level(errors, 0.5, 0.5), 0);
  EXPECT_EQ(renderer::select_crease_level(errors, 100, 0.5), 3);
  EXPECT_EQ(renderer::select_crease_level(errors, 0, 0.5), 0);  // the surface reaches the eye
  EXPECT_EQ(renderer::select_crease_level({}, 100, 0.5), 0);
}

// A merged segment's traits: where it begins (boundary, flat, valley), where it ends (open_end).
TEST(CreaseLevels, MergedTraitsFollowTheirFineSegments) {
  const CreaseGeometry g = branching_network();
  renderer::SegmentTraits fine;
  for (std::size_t s = 0; s < g.n_segments(); ++s) {
    fine.boundary.push_back(std::uint8_t(s % 2)), fine.flat.push_back(s % 3 == 0),
        fine.valley.push_back(s % 4 == 0);
    fine.open_end.push_back(s == 15);
  }
  const renderer::CreaseLevel l =
      renderer::merge_crease_runs(g, 4, std::numeric_limits<double>::infinity());
  const renderer::SegmentTraits t = renderer::merged_traits(fine, l);
  for (std::size_t s = 0; s < l.first.size(); ++s) {
    EXPECT_EQ(t.boundary[s], fine.boundary[l.first[s]]);
    EXPECT_EQ(t.flat[s], fine.flat[l.first[s]]);
    EXPECT_EQ(t.valley[s], fine.valley[l.first[s]]);
  }
  EXPECT_EQ(t.open_end, (std::vector<std::uint8_t>{0, 0, 0, 1, 0}));
}

// A flight compares its frames' lines segment by segment whatever level each drew
// (fine_lines): a merged segment's opacity goes to each fine segment it replaces and its
// pixels are shared among them by their lengths, so a frame's drawn length is conserved.
TEST(CreaseLevels, AFramesLinesOnTheFineSegments) {
  renderer::Scene scene;
  scene.creases = branching_network();
  scene.chains = renderer::segment_chains(*scene.creases);
  scene.crease_levels = std::make_shared<const std::vector<renderer::CreaseLevel>>(
      1, renderer::merge_crease_runs(*scene.creases, 4, std::numeric_limits<double>::infinity()));
  const renderer::CreaseLevel& l = (*scene.crease_levels)[0];
  renderer::FrameResult res;
  res.crease_level = 1;
  const renderer::FrameLines merged{{1.0f, 0.5f, 0.0f, 1.0f, 0.25f}, {8.0, 4.0, 0.0, 2.0, 6.0}};
  const renderer::FrameLines fine = renderer::fine_lines(scene, res, merged);
  ASSERT_EQ(fine.drawn.size(), scene.creases->n_segments());
  double merged_ink = 0, fine_ink = 0;
  for (std::size_t s = 0; s < 5; ++s) merged_ink += merged.drawn[s] * merged.pixels[s];
  for (std::size_t t = 0; t < fine.drawn.size(); ++t) fine_ink += fine.drawn[t] * fine.pixels[t];
  EXPECT_NEAR(fine_ink, merged_ink, 1e-9);
  const std::vector<double> metres = renderer::segment_metres(*scene.creases);
  for (std::size_t s = 0; s < 5; ++s) {
    EXPECT_EQ(fine.drawn[l.first[s]], merged.drawn[s]);
    EXPECT_EQ(fine.drawn[l.last[s]], merged.drawn[s]);
  }
  EXPECT_NEAR(fine.pixels[16] / fine.pixels[18], metres[16] / metres[18],
              1e-9);  // the tributary, 6 px over 3 links
  EXPECT_NEAR(fine.pixels[16] + fine.pixels[17] + fine.pixels[18], 6.0, 1e-9);
  res.crease_level = 0;
  EXPECT_EQ(renderer::fine_lines(scene, res, merged).drawn, merged.drawn);  // as given
}
