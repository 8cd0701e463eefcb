// Hidden-line removal along strokes (renderer/core/stroke_visibility.hpp), GL-free, on a line
// seen from straight above across toward depths laid out by hand.
#include "renderer/core/stroke_visibility.hpp"

#include <gtest/gtest.h>

#include "renderer/top_view.hpp"

#include <bit>
#include <string>

namespace renderer {
namespace {

constexpr int kW = 64, kH = 16;

View top_view(bool reversed) { return test::top_view(kW, kH, reversed); }

// A stroke along the image's middle row (y = 0, z = 0): `n` segments of 1.98 px from
// u = 0.2, so that its two samples a segment (0.99 px each) fall in columns 2j and 2j + 1.
CreaseGeometry row_stroke(const View& view, int n) {
  const Projected a = project(view, Eigen::Vector3d(0, 0, 0)),
                  b = project(view, Eigen::Vector3d(1, 0, 0));
  const double per_px = 1.0 / (b.u - a.u);  // metres per pixel along x
  CreaseGeometry g;
  for (int i = 0; i <= n; ++i) {
    g.positions.emplace_back(float((0.2 + 1.98 * i - a.u) * per_px), 0.0f, 0.0f);
    g.normals.emplace_back(0.0f, 0.0f, 1.0f);
    g.flow.push_back(float(i + 1) / float(n + 1));
    g.source.push_back(std::uint32_t(i));
  }
  for (std::uint32_t i = 0; i < std::uint32_t(n); ++i)
    g.segments.insert(g.segments.end(), {i, i + 1});
  return g;
}

using test::toward_of;

// Sample i of the stroke (segment i / 2, bit i % 2) as '1' when `mask` of it is set.
std::string bits(const std::vector<SegmentSamples>& m, std::uint32_t SegmentSamples::*mask) {
  std::string s;
  for (const SegmentSamples& x : m)
    for (std::uint32_t k = 0; k < x.n; ++k) s += ((x.*mask >> k) & 1u) ? '1' : '0';
  return s;
}

// Line.frag's test sees the farthest surface of a sample's 3 x 3 pixels, so a wall hides
// the samples of its columns but the first and last. With a 8 px gap, walls within 20 m and
// peeks up to 6 px:
//   columns 10-14, a near wall: samples 11-13 hidden, 3 px between visible ones: drawn;
//   20-24, a ridge 50 m above the line: 21-23 stay hidden;
//   30-43, a near wall 14 columns wide: 31-42 hidden, 12 px, more than the gap: hidden;
//   44-46, ground between that wall and a ridge: 43-47 show, a 5 px peek: left out;
//   47-54, a ridge: 48-53 hidden.
TEST(StrokeVisibility, ShortHiddenRunsNearTheSurfaceAreDrawnAndPeeksLeftOut) {
  const std::string columns = "GGGGGGGGGGNNNNNGGGGGRRRRRGGGGGNNNNNNNNNNNNNNGGGRRRRRRRRGGGGGGGGG";
  ASSERT_EQ(columns.size(), std::size_t(kW));
  for (const bool reversed : {false, true}) {
    const View view = top_view(reversed);
    const CreaseGeometry g = row_stroke(view, kW / 2);
    const std::vector<float> toward = toward_of(view, columns);
    const std::vector<float> drawn(g.n_segments(), 1.0f);
    const StrokeVisibilityRule rule{8.0, 20.0, 6.0};
    // Lifted 1 m towards the eye, the line is in front of the ground it lies on.
    const auto m = stroke_visibility(g, segment_chains(g), drawn, view, 1.0, 1.0, toward, rule);
    ASSERT_EQ(m.size(), g.n_segments());
    for (const SegmentSamples& x : m) {
      ASSERT_EQ(x.n, 2u);
      EXPECT_NEAR(x.step, 0.99, 1e-6);
    }
    // clang-format off
    EXPECT_EQ(bits(m, &SegmentSamples::visible),
              "1111111111100011111110001111111000000000000111110000001111111111") << reversed;
    EXPECT_EQ(bits(m, &SegmentSamples::bridgeable),
              "0000000000011100000000000000000111111111111000000000000000000000") << reversed;
    EXPECT_EQ(bits(m, &SegmentSamples::closed),
              "1111111111111111111110001111111000000000000111110000001111111111") << reversed;
    EXPECT_EQ(bits(m, &SegmentSamples::shown),
              "1111111111111111111110001111111000000000000000000000001111111111") << reversed;
    // clang-format on
    double px = 0;
    for (const double p : shown_pixels(m)) px += p;
    EXPECT_NEAR(px, 38 * 0.99, 1e-4);
    // The rules off: what is shown is line.frag's own test.
    const auto off = stroke_visibility(g, segment_chains(g), drawn, view, 1.0, 1.0, toward, {});
    EXPECT_EQ(bits(off, &SegmentSamples::shown), bits(m, &SegmentSamples::visible));
    // Walls up to 5 m behind the surface only: the near wall's run is not drawn either.
    const auto shallow =
        stroke_visibility(g, segment_chains(g), drawn, view, 1.0, 1.0, toward, {8.0, 5.0, 0.0});
    EXPECT_EQ(bits(shallow, &SegmentSamples::shown), bits(m, &SegmentSamples::visible));
  }
}

// A short stroke that shows whole is not a peek, however short (its length is the stroke
// rule's business, in metres); one that leaves the image is cut where it leaves, and what
// shows of it beside the edge is a peek. Segments not drawn have no samples.
TEST(StrokeVisibility, StrokeEndsAndTheImagesEdge) {
  const View view = top_view(true);
  const CreaseGeometry g = row_stroke(view, kW / 2);
  const std::vector<float> ground = toward_of(view, std::string(kW, 'G'));
  std::vector<float> drawn(g.n_segments(), 0.0f);
  drawn[10] = drawn[11] = 1.0f;  // 4 samples, 3.96 px
  const StrokeVisibilityRule rule{8.0, 20.0, 6.0};
  auto m = stroke_visibility(g, segment_chains(g), drawn, view, 1.0, 1.0, ground, rule);
  EXPECT_EQ(m[9].n, 0u);
  EXPECT_EQ(m[12].n, 0u);
  EXPECT_EQ(m[10].shown, 3u);
  EXPECT_EQ(m[11].shown, 3u);
  // Moved 23 px to the left, its samples lie at u = -2.5, -1.5, -0.5 and 0.5: the last one
  // alone is on the image, a 1 px piece beside its edge, left out.
  CreaseGeometry shifted = g;
  const double per_px = double(g.positions[1].x() - g.positions[0].x()) / 1.98;  // metres per pixel
  for (auto& p : shifted.positions) p.x() -= float(23.0 * per_px);
  m = stroke_visibility(shifted, segment_chains(shifted), drawn, view, 1.0, 1.0, ground, rule);
  EXPECT_EQ(std::popcount(m[10].visible) + std::popcount(m[11].visible), 1);
  EXPECT_EQ(m[10].shown | m[11].shown, 0u);
  m = stroke_visibility(shifted, segment_chains(shifted), drawn, view, 1.0, 1.0, ground,
                        {8.0, 20.0, 0.0});
  EXPECT_EQ(std::popcount(m[10].shown) + std::popcount(m[11].shown), 1);
}

// A tributary joins the stroke from the north at its vertex 20 (u = 39.8), in 4 segments
// of 1.98 px (rows 0 to 7, column 39). Its run ends where it joins a line that goes on past
// the peek length, as its stroke does (crease_strokes):
//   - under a ridge 50 m above it in rows 0 to 3, its samples in rows 0 to 2 are hidden and
//     those in rows 3 to 7 (5 px) show: a peek, left out; the stroke it joins stays;
//   - where it is the larger inflow the stroke goes on up it, and the stub is the stroke's
//     own upper end: shown;
//   - its lower 2 segments alone drawn (4 px, whole): shown, a whole stroke; with a ridge
//     over the stroke it joins from the junction on (rows 7 to 9, columns 39 on), a peek.
TEST(StrokeVisibility, ATributaryStubHiddenUpstreamIsAPeek) {
  for (const bool reversed : {false, true}) {
    const View view = top_view(reversed);
    CreaseGeometry g = row_stroke(view, kW / 2);
    const std::uint32_t junction = 20, trunk_in = junction - 1, trunk_out = junction;  // segments
    const Projected o = project(view, Eigen::Vector3d(0, 0, 0)),
                    n = project(view, Eigen::Vector3d(0, 1, 0));
    const double per_px =
        1.0 / (n.v - o.v);  // metres per pixel down the image (negative: north is up)
    const auto first = std::uint32_t(g.positions.size());
    for (int k = 4; k >= 1; --k) {  // upstream first
      g.positions.emplace_back(g.positions[junction].x(), float(-1.98 * k * per_px), 0.0f);
      g.normals.emplace_back(0.0f, 0.0f, 1.0f);
      g.flow.push_back(0.01f * float(5 - k));
      g.source.push_back(std::uint32_t(1000 + k));
    }
    for (std::uint32_t i = first; i + 1 < first + 4; ++i)
      g.segments.insert(g.segments.end(), {i, i + 1});
    g.segments.insert(g.segments.end(), {first + 3, junction});
    const std::uint32_t stub = std::uint32_t(g.n_segments()) - 1;
    const float ridge = float(project(view, Eigen::Vector3d(0, 0, 50)).depth);
    const std::vector<float> ground = toward_of(view, std::string(kW, 'G'));
    auto with_ridge = [&](int v0, int v1, int u0, int u1) {
      std::vector<float> t = ground;
      for (int v = v0; v <= v1; ++v)
        for (int u = u0; u <= u1; ++u) t[std::size_t(v * kW + u)] = ridge;
      return t;
    };
    const std::vector<float> head_hidden = with_ridge(0, 3, 37, 41),
                             trunk_hidden = with_ridge(7, 9, 39, kW - 1);
    std::vector<float> drawn(g.n_segments(), 1.0f);
    const StrokeVisibilityRule rule{8.0, 20.0, 6.0};
    auto tributary = [&](const std::vector<SegmentSamples>& m,
                         std::uint32_t SegmentSamples::*mask) {
      return bits({m.begin() + stub - 3, m.begin() + stub + 1}, mask);
    };
    const SegmentChains chains = segment_chains(g);
    ASSERT_EQ(chains.prev[trunk_out], trunk_in);
    auto m = stroke_visibility(g, chains, drawn, view, 1.0, 1.0, head_hidden, rule);
    EXPECT_EQ(tributary(m, &SegmentSamples::visible), "00011111") << reversed;
    EXPECT_EQ(tributary(m, &SegmentSamples::shown), "00000000") << reversed;
    for (std::uint32_t s = 0; s < kW / 2; ++s)
      EXPECT_EQ(m[s].shown, 3u) << "trunk segment " << s << " " << reversed;
    // The peek rule off: the stub shows.
    m = stroke_visibility(g, chains, drawn, view, 1.0, 1.0, head_hidden, {8.0, 20.0, 0.0});
    EXPECT_EQ(tributary(m, &SegmentSamples::shown), "00011111") << reversed;
    // Its lower 2 segments alone: a whole stroke, unless the stroke it joins is hidden there.
    drawn[stub - 3] = drawn[stub - 2] = 0.0f;
    m = stroke_visibility(g, chains, drawn, view, 1.0, 1.0, ground, rule);
    EXPECT_EQ(tributary(m, &SegmentSamples::shown), "1111") << reversed;
    m = stroke_visibility(g, chains, drawn, view, 1.0, 1.0, trunk_hidden, rule);
    EXPECT_EQ(tributary(m, &SegmentSamples::visible), "1111") << reversed;
    EXPECT_EQ(m[trunk_out].visible, 0u) << reversed;
    EXPECT_EQ(tributary(m, &SegmentSamples::shown), "0000") << reversed;
    // The tributary the larger inflow: the stroke goes on up it.
    drawn.assign(g.n_segments(), 1.0f);
    for (std::uint32_t i = first; i < first + 4; ++i) g.flow[i] += 1.0f;
    const SegmentChains up_the_tributary = segment_chains(g);
    ASSERT_EQ(up_the_tributary.prev[trunk_out], stub);
    m = stroke_visibility(g, up_the_tributary, drawn, view, 1.0, 1.0, head_hidden, rule);
    EXPECT_EQ(tributary(m, &SegmentSamples::shown), "00011111") << reversed;
  }
}

}  // namespace
}  // namespace renderer
