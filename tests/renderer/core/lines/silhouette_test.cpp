// Formulated silhouettes (GL-free reference, renderer/core/silhouette.hpp) on analytic surfaces
// seen from above, whose lowered-eye silhouettes are known: a tent's crest across the view's
// bearing, none along it or where the far side is too gentle, and a cone's two generators.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>

#include "renderer/core/silhouette.hpp"
#include "renderer/core/vector_art.hpp"
#include "renderer/top_view.hpp"

namespace renderer {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Per pixel of a w x h image (rows from the top, x east, y north about the centre), the
// unit normal `n(X, Y)` of the surface drawn there.
std::vector<float> normals_of(int w, int h,
                              const std::function<Eigen::Vector3d(double, double)>& n) {
  std::vector<float> out(4 * std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d v = n(x + 0.5 - 0.5 * w, 0.5 * h - (y + 0.5)).normalized();
      float* o = &out[4 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
      o[0] = float(v.x()), o[1] = float(v.y()), o[2] = float(v.z()), o[3] = 1;
    }
  return out;
}

std::size_t on(const std::vector<std::uint8_t>& m) {
  return std::size_t(std::count(m.begin(), m.end(), 1));
}

// The top view (north up) looks towards the image's top: the lowered eye looks north,
// `altitude` below the horizon, and "behind" a pixel is the pixel above it.
TEST(FormulatedSilhouettes, TheTopViewLowersItsEyeTowardsTheTop) {
  const FormulatedView f = formulated_view(test::top_view(64, 48), 5, 5);
  EXPECT_EQ(f.step_x, 0);
  EXPECT_EQ(f.step_up, 1);
  EXPECT_NEAR(f.direction.x(), 0, 1e-6);
  EXPECT_NEAR(f.direction.y(), std::cos(5 * kDeg), 1e-6);
  EXPECT_NEAR(f.direction.z(), -std::sin(5 * kDeg), 1e-6);
  EXPECT_NEAR(f.strength, std::sin(5 * kDeg), 1e-6);
}

// A tent whose crest runs east-west through the centre: from an eye lowered towards the
// north its crest is a silhouette when the north flank falls more steeply than the sight
// line plus the strength (5 + 5 degrees): then exactly the row of the crest's south side,
// every column, and nothing else. A flank of 8 degrees hides nothing; the same tent turned
// to run north-south has no crest across the bearing.
TEST(FormulatedSilhouettes, ATentIsDrawnAlongItsCrestOnly) {
  const int w = 64, h = 48;
  const FormulatedView f = formulated_view(test::top_view(w, h), 5, 5);
  auto tent = [&](double slope_deg, bool east_west) {
    const double s = std::tan(slope_deg * kDeg);
    return normals_of(w, h, [=](double X, double Y) {
      const double across = east_west ? Y : X;  // > 0: the flank that falls north (east)
      const Eigen::Vector3d n(0, across > 0 ? s : -s, 1);
      return east_west ? n : Eigen::Vector3d(n.y(), 0, 1);
    });
  };
  const auto steep = formulated_silhouettes(tent(20, true), w, h, f);
  EXPECT_EQ(on(steep), std::size_t(w));
  for (int x = 0; x < w; ++x) EXPECT_EQ(steep[std::size_t(h / 2 * w + x)], 1) << x;
  EXPECT_EQ(on(formulated_silhouettes(tent(12, true), w, h, f)), std::size_t(w));
  EXPECT_EQ(on(formulated_silhouettes(tent(8, true), w, h, f)), 0u);
  EXPECT_EQ(on(formulated_silhouettes(tent(30, false), w, h, f)), 0u);
  // A crest 2 pixels from the image's near (bottom) edge: the ground in front of it ends
  // there (the cut edge of the data, as a DEM's near edge that rises to its cut), and it is
  // not drawn; 6 pixels in, it is.
  auto crest_at = [&](double Y0) {
    const double s = std::tan(20 * kDeg);
    return normals_of(w, h,
                      [=](double, double Y) { return Eigen::Vector3d(0, Y > Y0 ? s : -s, 1); });
  };
  EXPECT_EQ(on(formulated_silhouettes(crest_at(2.0 - 0.5 * h), w, h, f)), 0u);
  EXPECT_EQ(on(formulated_silhouettes(crest_at(6.0 - 0.5 * h), w, h, f)), std::size_t(w));
  // Off the terrain (the normals' 4th component 0) nothing is drawn.
  auto none = tent(20, true);
  for (std::size_t i = 3; i < none.size(); i += 4) none[i] = 0;
  EXPECT_EQ(on(formulated_silhouettes(none, w, h, f)), 0u);
}

// A cone of 45 degrees with its apex at the centre, eye lowered to 5 degrees towards the
// north: its lowered-eye silhouettes are the two generators where the slope along the
// bearing equals the sight line, at azimuths +-acos(tan 5 / tan 45) = +-85 degrees from
// north. Every formulated pixel lies on the facing side next to one of them (both are
// drawn), none on the near (south) half of the cone, none deep in the sector between.
TEST(FormulatedSilhouettes, AConeIsDrawnAlongItsTwoGenerators) {
  const int w = 161, h = 161;
  const FormulatedView f = formulated_view(test::top_view(w, h), 5, 5);
  const auto n = normals_of(w, h, [](double X, double Y) {
    const double r = std::hypot(X, Y);
    return r > 0 ? Eigen::Vector3d(X / r, Y / r, 1) : Eigen::Vector3d(0, 0, 1);
  });
  const auto m = formulated_silhouettes(n, w, h, f);
  const double generator = std::acos(std::tan(5 * kDeg)) / kDeg;
  std::size_t east = 0, west = 0, off = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!m[std::size_t(y * w + x)]) continue;
      const double X = x + 0.5 - 0.5 * w, Y = 0.5 * h - (y + 0.5), r = std::hypot(X, Y);
      if (r < 4) continue;                        // the apex
      const double az = std::atan2(X, Y) / kDeg;  // from north, clockwise
      const double tolerance = std::asin(std::min(1.0, 3 / r)) / kDeg + 2;
      if (std::abs(std::abs(az) - generator) > tolerance) ++off;
      (X > 0 ? east : west) += 1;
    }
  EXPECT_EQ(off, 0u);
  EXPECT_GE(east, 10u);
  EXPECT_GE(west, 10u);
}

// Silhouettes weighted by what they hide (issue 64: the skyline and the crests heaviest):
// a far ridge stands against the sky (its skyline at row 10) 10 % beyond a near slope whose
// occluding contour is row 25; on the near slope a formulated line (row 33) hides almost
// nothing. The hidden shares are the sky's (infinite), 0.084 and 0.003; the lines' widths
// are the band's plus 1.5 px times their weights: 1, 0.33 (quantised to a quarter pixel) and 0.
TEST(SilhouetteDepth, TheSkylineIsHeaviestAndALineThatHidesNothingLightest) {
  const int w = 60, h = 40;
  std::vector<float> distance(std::size_t(w * h));
  std::vector<std::uint8_t> mask(distance.size(), 0), opacity(distance.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y * w + x);
      distance[i] = y < 10   ? std::numeric_limits<float>::infinity()
                    : y < 25 ? 1100.0f
                             : 1000.0f + float(40 - y);
      if ((y == 10 || y == 25 || y == 33) && x >= 5 && x < 55) mask[i] = 1, opacity[i] = 255;
    }
  const std::vector<float> hidden = silhouette_hidden_share(mask, distance, w, h);
  EXPECT_EQ(hidden[std::size_t(10 * w + 30)], std::numeric_limits<float>::infinity());
  EXPECT_NEAR(hidden[std::size_t(25 * w + 30)], 1100.0 / 1015.0 - 1.0,
              1e-6);  // rows 22 .. 24 behind it
  EXPECT_NEAR(hidden[std::size_t(33 * w + 30)], 1010.0 / 1007.0 - 1.0,
              1e-6);                                 // row 30, its own slope
  EXPECT_EQ(hidden[std::size_t(5 * w + 30)], 0.0f);  // off the mask
  EXPECT_FLOAT_EQ(hidden_weight(hidden[std::size_t(10 * w + 30)]), 1.0f);
  EXPECT_FLOAT_EQ(hidden_weight(0.1f), 0.4f);
  const auto paths = silhouette_paths(opacity, w, h, 1.8f, nullptr, &hidden, 1.5f);
  ASSERT_EQ(paths.size(), 3u);
  std::map<int, float> width_at_row;
  for (const VectorPath& p : paths)
    width_at_row[int(std::lround(p.line.points.front().y() - 0.5))] = p.width;
  EXPECT_FLOAT_EQ(width_at_row[10], 1.8f + 1.5f);
  EXPECT_FLOAT_EQ(width_at_row[25], 1.8f + 0.5f);  // 1.5 x 0.335 to the quarter pixel
  EXPECT_FLOAT_EQ(width_at_row[33], 1.8f);
  for (const VectorPath& p : silhouette_paths(opacity, w, h, 1.8f))
    EXPECT_FLOAT_EQ(p.width, 1.8f);  // not weighted
}

}  // namespace
}  // namespace renderer
