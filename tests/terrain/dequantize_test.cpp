// terrain/dequantize.hpp on an integer-rounded ramp with a valley, whose true heights are
// known: the steps are gone (D8 finds a descent almost everywhere), the valley floor descends
// all along (a clamp to the stored half-unit band left it flat at k + 0.5 over each terrace),
// every sample stays within 0.6 of its stored value, the surface comes closer to the true
// one; no-data stays.
#include "terrain/dequantize.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace terrain {
namespace {

TEST(Dequantize, IntegerStepsOfARampWithAValleyAreSmoothedAndItsFloorDescends) {
  const std::size_t R = 80, C = 100;
  Georef geo;
  geo.dx = geo.dy = 10;
  Grid truth(R, C, geo), rounded(R, C, geo);
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t c = 0; c < C; ++c) {
      // 1 m in 50 m down to the west, and a valley along row 40 whose sides rise 1 m in 20 m.
      const double z = 400.0 + 0.02 * double(c) * 10 + 0.05 * std::abs(double(r) - 40.0) * 10;
      truth.z[r * C + c] = float(z);
      rounded.z[r * C + c] = float(std::round(z));
    }
  rounded.z[5 * C + 7] = NAN;
  EXPECT_TRUE(is_integer_dem(rounded));
  EXPECT_FALSE(is_integer_dem(truth));
  Grid smooth = rounded;
  const double change = dequantize(smooth);
  EXPECT_LE(change, 0.6 + 1e-6);
  EXPECT_GT(change, 0.1);
  EXPECT_TRUE(std::isnan(smooth.z[5 * C + 7]));
  // Interior samples with no lower 8-neighbour: where D8 finds no descent (terraces).
  auto no_descent = [&](const Grid& g) {
    std::size_t n = 0;
    for (std::size_t r = 1; r + 1 < R; ++r)
      for (std::size_t c = 1; c + 1 < C; ++c) {
        bool lower = false;
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) lower |= g.z[(r + dr) * C + c + dc] < g.z[r * C + c];
        n += !lower;
      }
    return n;
  };
  double err_rounded = 0, err_smooth = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < R * C; ++i) {
    if (std::isnan(rounded.z[i])) continue;
    EXPECT_LE(std::abs(smooth.z[i] - rounded.z[i]), 0.6f + 1e-5f) << i;
    err_rounded += std::pow(rounded.z[i] - truth.z[i], 2);
    err_smooth += std::pow(smooth.z[i] - truth.z[i], 2);
    ++n;
  }
  EXPECT_GT(no_descent(rounded), R * C / 20);  // the terraces' flats
  EXPECT_LT(no_descent(smooth), R * C / 200);
  std::printf("RMSE against the true ramp: stored %.4f, dequantized %.4f\n",
              std::sqrt(err_rounded / n), std::sqrt(err_smooth / n));
  EXPECT_LT(std::sqrt(err_smooth / n), 0.5 * std::sqrt(err_rounded / n));
  // The valley floor (row 40) descends to the west at every step, away from the grid's edge.
  std::size_t floor_flat = 0;
  for (std::size_t c = 2; c + 3 < C; ++c)
    floor_flat += !(smooth.z[40 * C + c] < smooth.z[40 * C + c + 1]);
  EXPECT_EQ(floor_flat, 0u);
}

// The interpolation alone on a rounded plane whose contours run across the grid at an angle:
// every sample within half a unit of its stored value, and within a quarter of a unit of the
// true plane (rounding alone is off by up to half a unit, 0.29 RMS).
TEST(Dequantize, TerraceInterpolationRebuildsARoundedPlane) {
  const std::size_t R = 60, C = 70;
  Georef geo;
  geo.dx = geo.dy = 10;
  Grid rounded(R, C, geo);
  auto truth = [](std::size_t r, std::size_t c) {
    return 100.0 + 0.13 * double(c) + 0.07 * double(r);
  };
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t c = 0; c < C; ++c) rounded.z[r * C + c] = float(std::round(truth(r, c)));
  const std::vector<double> z = terrace_interpolation(rounded);
  double err = 0, err_rounded = 0;
  std::size_t n = 0;
  for (std::size_t r = 8; r + 8 < R; ++r)  // away from the edges, where terraces lose a contour
    for (std::size_t c = 8; c + 8 < C; ++c) {
      const std::size_t i = r * C + c;
      EXPECT_LE(std::abs(z[i] - rounded.z[i]), 0.5 + 1e-9);
      err += std::pow(z[i] - truth(r, c), 2),
          err_rounded += std::pow(rounded.z[i] - truth(r, c), 2), ++n;
    }
  std::printf("RMSE against the true plane: stored %.4f, interpolated %.4f\n",
              std::sqrt(err_rounded / n), std::sqrt(err / n));
  EXPECT_LT(std::sqrt(err / n), 0.1);
  EXPECT_GT(std::sqrt(err_rounded / n), 0.25);
}

}  // namespace
}  // namespace terrain
