// Formulated silhouettes (GL-free reference, renderer/silhouette.hpp) on analytic surfaces
// seen from above, whose lowered-eye silhouettes are known: a tent's crest across the view's
// bearing, none along it or where the far side is too gentle, and a cone's two generators.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "renderer/silhouette.hpp"
#include "renderer/top_view.hpp"

namespace renderer {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Per pixel of a w x h image (rows from the top, x east, y north about the centre), the
// unit normal `n(X, Y)` of the surface drawn there.
std::vector<float> normals_of(int w, int h, const std::function<Eigen::Vector3d(double, double)>& n) {
  std::vector<float> out(4 * std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3d v = n(x + 0.5 - 0.5 * w, 0.5 * h - (y + 0.5)).normalized();
      float* o = &out[4 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
      o[0] = float(v.x()), o[1] = float(v.y()), o[2] = float(v.z()), o[3] = 1;
    }
  return out;
}

std::size_t on(const std::vector<std::uint8_t>& m) { return std::size_t(std::count(m.begin(), m.end(), 1)); }

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
    return normals_of(w, h, [=](double, double Y) { return Eigen::Vector3d(0, Y > Y0 ? s : -s, 1); });
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
      if (r < 4) continue;  // the apex
      const double az = std::atan2(X, Y) / kDeg;  // from north, clockwise
      const double tolerance = std::asin(std::min(1.0, 3 / r)) / kDeg + 2;
      if (std::abs(std::abs(az) - generator) > tolerance) ++off;
      (X > 0 ? east : west) += 1;
    }
  EXPECT_EQ(off, 0u);
  EXPECT_GE(east, 10u);
  EXPECT_GE(west, 10u);
}

}  // namespace
}  // namespace renderer
