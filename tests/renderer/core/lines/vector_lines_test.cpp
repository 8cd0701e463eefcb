// renderer/core/vector_lines.hpp on hand-made masks and segment lists whose lines are known: a
// ring, a T junction, a dashed line, a line along the frame's edge, a thick band; and the
// simplification the vector writer uses.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "renderer/core/vector_lines.hpp"

namespace renderer {
namespace {

struct Mask {
  int w, h;
  std::vector<std::uint8_t> m;
  Mask(int w_, int h_) : w(w_), h(h_), m(std::size_t(w_ * h_), 0) {}
  void set(int x, int y) { m[std::size_t(y * w + x)] = 1; }
};

double length(const Polyline& p) {
  double l = 0;
  for (std::size_t k = 1; k < p.points.size(); ++k) l += (p.points[k] - p.points[k - 1]).norm();
  if (p.closed && p.points.size() > 1) l += (p.points.front() - p.points.back()).norm();
  return l;
}

TEST(VectorLines, ARingIsOneClosedLine) {
  Mask m(64, 64);
  for (int a = 0; a < 3600; ++a) {
    const double t = a * std::numbers::pi / 1800;
    m.set(int(std::lround(32 + 20 * std::cos(t))), int(std::lround(32 + 20 * std::sin(t))));
  }
  const auto lines = chain_mask(m.m, m.w, m.h);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_TRUE(lines[0].closed);
  for (const auto& p : lines[0].points)
    EXPECT_NEAR((p - Eigen::Vector2f(32.5f, 32.5f)).norm(), 20.0f, 1.0f);
  // The pixel staircase is as long as the circle's L1 perimeter (8 r); simplified to within
  // a pixel, its chords are as long as the circle, to 3 %.
  EXPECT_NEAR(length(lines[0]), 8 * 20, 4.0);
  EXPECT_NEAR(length(simplify(lines[0], 1.0f)), 2 * std::numbers::pi * 20,
              0.03 * 2 * std::numbers::pi * 20);
}

TEST(VectorLines, ATJunctionIsThreeLinesMeetingThere) {
  Mask m(41, 41);
  for (int x = 5; x <= 35; ++x) m.set(x, 10);   // the bar
  for (int y = 11; y <= 35; ++y) m.set(20, y);  // the stem
  const auto lines = chain_mask(m.m, m.w, m.h);
  ASSERT_EQ(lines.size(), 3u);
  const Eigen::Vector2f junction(20.5f, 10.5f);
  double total = 0;
  for (const Polyline& l : lines) {
    EXPECT_FALSE(l.closed);
    const bool at_junction =
        (l.points.front() - junction).norm() < 1.5f || (l.points.back() - junction).norm() < 1.5f;
    EXPECT_TRUE(at_junction);
    total += length(l);
  }
  EXPECT_NEAR(total, 30 + 25, 2.0);
}

TEST(VectorLines, ADashedLineIsOneLineADash) {
  Mask m(100, 20);
  int dashes = 0;
  for (int x0 = 2; x0 + 5 < 100; x0 += 9, ++dashes)
    for (int x = x0; x < x0 + 5; ++x) m.set(x, 7);
  const auto lines = chain_mask(m.m, m.w, m.h);
  ASSERT_EQ(int(lines.size()), dashes);
  for (const Polyline& l : lines) EXPECT_NEAR(length(l), 4.0, 1e-4);
}

TEST(VectorLines, ALineAlongTheFrameEdgeKeepsItsEnds) {
  Mask m(50, 30);
  for (int x = 0; x < 50; ++x) m.set(x, 0);
  const auto lines = chain_mask(m.m, m.w, m.h);
  ASSERT_EQ(lines.size(), 1u);
  const auto& p = lines[0].points;
  EXPECT_FLOAT_EQ(std::min(p.front().x(), p.back().x()), 0.5f);
  EXPECT_FLOAT_EQ(std::max(p.front().x(), p.back().x()), 49.5f);
  for (const auto& q : p) EXPECT_FLOAT_EQ(q.y(), 0.5f);
}

TEST(VectorLines, AThickBandBecomesItsCentreLine) {
  Mask m(60, 20);
  for (int x = 5; x < 55; ++x)
    for (int y = 8; y <= 10; ++y) m.set(x, y);  // 3 px wide
  const auto lines = chain_mask(m.m, m.w, m.h);
  ASSERT_EQ(lines.size(), 1u);
  for (const auto& q : lines[0].points) EXPECT_NEAR(q.y(), 9.5f, 1.01f);
  EXPECT_GT(length(lines[0]), 40.0);
}

TEST(VectorLines, SegmentsChainWhereTheirEndsMeet) {
  using S = std::array<Eigen::Vector2f, 2>;
  const Eigen::Vector2f a(0, 0), b(10, 0), c(10, 10), d(0, 10), e(20, 0), f(10, -10);
  // A square (a ring), given out of order and with one segment reversed.
  auto square = chain_segments({S{a, b}, S{c, b}, S{c, d}, S{d, a}});
  ASSERT_EQ(square.size(), 1u);
  EXPECT_TRUE(square[0].closed);
  EXPECT_EQ(square[0].points.size(), 4u);
  // A T: three lines from the junction b.
  auto t = chain_segments({S{a, b}, S{b, e}, S{b, c}, S{b, f}});
  EXPECT_EQ(t.size(), 4u);  // four arms at b: a junction of four
  auto t3 = chain_segments({S{a, b}, S{b, e}, S{b, c}});
  EXPECT_EQ(t3.size(), 3u);
  // Dashes: segments whose ends do not meet stay apart; a path of three joins into one.
  auto dashes = chain_segments({S{a, b}, S{Eigen::Vector2f(11, 0), e}});
  EXPECT_EQ(dashes.size(), 2u);
  auto path = chain_segments({S{a, b}, S{b, c}, S{c, d}});
  ASSERT_EQ(path.size(), 1u);
  EXPECT_FALSE(path[0].closed);
  EXPECT_EQ(path[0].points.size(), 4u);
}

TEST(VectorLines, SimplifyStaysWithinItsTolerance) {
  Polyline zigzag;
  for (int k = 0; k <= 100; ++k) zigzag.points.emplace_back(float(k), (k % 2) ? 0.2f : 0.0f);
  const Polyline s = simplify(zigzag, 0.25f);
  EXPECT_EQ(s.points.size(), 2u);
  Polyline corner;
  for (int k = 0; k <= 10; ++k) corner.points.emplace_back(float(k), 0.0f);
  for (int k = 1; k <= 10; ++k) corner.points.emplace_back(10.0f, float(k));
  const Polyline c = simplify(corner, 0.25f);
  ASSERT_EQ(c.points.size(), 3u);
  EXPECT_EQ(c.points[1], Eigen::Vector2f(10, 0));
  // Every original point within the tolerance of the simplified line (a smooth curve).
  Polyline curve;
  for (int k = 0; k <= 200; ++k)
    curve.points.emplace_back(float(k) * 0.5f, 10.0f * std::sin(float(k) * 0.05f));
  const Polyline cs = simplify(curve, 0.25f);
  EXPECT_LT(cs.points.size(), curve.points.size() / 3);
  for (const auto& p : curve.points) {
    double best = 1e9;
    for (std::size_t k = 1; k < cs.points.size(); ++k) {
      const Eigen::Vector2d a = cs.points[k - 1].cast<double>(),
                            d = (cs.points[k] - cs.points[k - 1]).cast<double>();
      const double t = std::clamp((p.cast<double>() - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (p.cast<double>() - a - t * d).norm());
    }
    EXPECT_LE(best, 0.25 + 1e-5);
  }
}

TEST(VectorLines, SimplifiedPointsAreTheOnesSimplifyKeeps) {
  Polyline l;
  for (int k = 0; k < 9; ++k)
    l.points.emplace_back(float(k), k == 4 ? 3.0f : 0.0f);  // a spike at 4
  const auto keep = simplified_points(l, 0.25f);
  EXPECT_EQ(keep, (std::vector<std::size_t>{0, 3, 4, 5, 8}));
  const Polyline s = simplify(l, 0.25f);
  ASSERT_EQ(s.points.size(), keep.size());
  for (std::size_t i = 0; i < keep.size(); ++i) EXPECT_EQ(s.points[i], l.points[keep[i]]);
}

}  // namespace
}  // namespace renderer
