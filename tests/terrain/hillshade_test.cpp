// Hillshade and colour ramp: analytic normals and planes whose grey levels are known.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "terrain/hillshade.hpp"

namespace terrain {
namespace {

TEST(Hillshade, GreyIsTheCosineToTheLight) {
  const Eigen::Vector3d l = light_direction(315, 45);  // NW, 45 degrees up
  EXPECT_NEAR(l.x(), -0.5, 1e-12);
  EXPECT_NEAR(l.y(), 0.5, 1e-12);
  EXPECT_NEAR(l.z(), std::sqrt(0.5), 1e-12);
  const std::vector<Eigen::Vector3f> normals = {
      l.cast<float>(), {0, 0, 1}, -l.cast<float>(), {0.5f, 0.5f, 0.0f}};
  const auto grey = hillshade(normals, 315, 45);
  EXPECT_EQ(grey[0], 255);
  EXPECT_EQ(grey[1], std::lround(255 * std::sqrt(0.5)));  // 180
  EXPECT_EQ(grey[2], 0);                                  // facing away
  EXPECT_EQ(grey[3], 0);                                  // perpendicular to the light
  const auto overhead = hillshade(normals, 0, 90);
  EXPECT_EQ(overhead[1], 255);
}

// A plane whose normal points at the light shades 255 everywhere; a flat plane shades
// 255 sin(altitude) whatever the vertical exaggeration.
TEST(Hillshade, PlanesOfKnownShade) {
  Georef geo;
  geo.dx = geo.dy = 10;
  Grid facing(12, 15, geo), flat(12, 15, geo, 250.0f);
  for (std::size_t r = 0; r < facing.rows;
       ++r)  // z = x - y: normal (-1, 1, 1) / sqrt(3), towards the NW
    for (std::size_t c = 0; c < facing.cols; ++c)
      facing.at(r, c) = float(geo.x_of_col(double(c)) - geo.y_of_row(double(r)));
  const double alt =
      std::asin(1 / std::sqrt(3.0)) * 180 / std::numbers::pi;  // the normal's altitude
  for (std::uint8_t g : hillshade_grid(facing, 315, alt)) EXPECT_GE(g, 254);
  for (double zf : {1.0, 3.0})
    for (std::uint8_t g : hillshade_grid(flat, 315, 30, zf)) EXPECT_EQ(g, std::lround(255 * 0.5));
}

TEST(Hillshade, ColourRampEndsAndNaN) {
  const std::vector<float> v = {0.0f, 10.0f, -5.0f, 20.0f, std::numeric_limits<float>::quiet_NaN()};
  const auto rgb = colour_ramp(v, 0, 10);
  ASSERT_EQ(rgb.size(), 15u);
  EXPECT_GT(rgb[2], rgb[0]);  // lo: blue dominates
  EXPECT_GT(rgb[3], rgb[5]);  // hi: yellow (red and green over blue)
  EXPECT_GT(rgb[4], rgb[5]);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(rgb[6 + k], rgb[k]);      // below lo: clamped to lo
    EXPECT_EQ(rgb[9 + k], rgb[3 + k]);  // above hi: clamped to hi
    EXPECT_EQ(rgb[12 + k], 0);          // NaN: black
  }
}

}  // namespace
}  // namespace terrain
