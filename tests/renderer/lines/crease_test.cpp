// renderer/src/lines/crease.cpp: the crease score (hand-computed values, the distances across
// a scene) and the opacity that fades in over the band.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/pipeline.hpp"
#include "renderer/camera.hpp"
#include "renderer/crease.hpp"
#include "renderer/frames.hpp"
#include "renderer/gl_context.hpp"
#include "renderer/line_stats.hpp"
#include "renderer/shader.hpp"
#include "renderer/silhouette.hpp"
#include "renderer/stroke_visibility.hpp"
#include "renderer/terrain_renderer.hpp"
#include "renderer/timing.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/pn_surface.hpp"
#include "terrain/voronoi.hpp"
#include "renderer/pel.hpp"
#include <map>
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
  EXPECT_NEAR(renderer::crease_score(up, 0.6, up, outside.near_distance, outside), 0.2 - 0.2, 1e-12);
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
  for (float area : {5000.0f, 15000.0f, 30000.0f, 60000.0f}) {  // a chain from a channel head downstream
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
  EXPECT_EQ(drawn(60000), (std::vector<float>{0, 0, 0}));  // the outlet's own area, but its upstream end drains less
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
