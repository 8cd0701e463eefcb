// terrain/dequantize.hpp on an integer-rounded ramp with a valley, whose true heights are
// known: the steps are gone (D8 finds a descent almost everywhere), every sample stays within half a
// unit of its stored value, the surface comes closer to the true one; no-data stays.
#include "terrain/dequantize.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace terrain {
namespace {

TEST(Dequantize, IntegerStepsOfARampWithAValleyAreSmoothedWithinHalfAUnit) {
  const std::size_t R = 80, C = 100;
  Georef geo;
  geo.dx = geo.dy = 10;
  Grid truth(R, C, geo), rounded(R, C, geo);
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t c = 0; c < C; ++c) {
      // 1 m in 50 m down to the west, and a valley along row 40 whose sides rise 1 m in 100 m.
      const double z = 400.0 + 0.02 * double(c) * 10 + 0.01 * std::abs(double(r) - 40.0) * 10;
      truth.z[r * C + c] = float(z);
      rounded.z[r * C + c] = float(std::round(z));
    }
  rounded.z[5 * C + 7] = NAN;
  EXPECT_TRUE(is_integer_dem(rounded));
  EXPECT_FALSE(is_integer_dem(truth));
  Grid smooth = rounded;
  const double change = dequantize(smooth);
  EXPECT_LE(change, 0.5 + 1e-6);
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
    EXPECT_LE(std::abs(smooth.z[i] - rounded.z[i]), 0.5f + 1e-5f) << i;
    err_rounded += std::pow(rounded.z[i] - truth.z[i], 2);
    err_smooth += std::pow(smooth.z[i] - truth.z[i], 2);
    ++n;
  }
  EXPECT_GT(no_descent(rounded), R * C / 20);  // the terraces' flats
  EXPECT_LT(no_descent(smooth), R * C / 200);
  EXPECT_LT(std::sqrt(err_smooth / n), 0.5 * std::sqrt(err_rounded / n));
}

}  // namespace
}  // namespace terrain
