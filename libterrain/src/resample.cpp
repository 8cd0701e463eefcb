#include "terrain/resample.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "terrain/error.hpp"

namespace terrain {

Resampling parse_resampling(std::string_view name) {
  if (name == "bilinear") return Resampling::Bilinear;
  if (name == "cubic") return Resampling::Cubic;
  throw Error("unknown resampling '" + std::string(name) + "' (use bilinear or cubic)");
}

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Keys cubic convolution kernel, a = -0.5 (GDAL's CubicKernel).
double keys(double t) {
  t = std::abs(t);
  if (t <= 1.0) return t * t * (1.5 * t - 2.5) + 1.0;
  if (t <= 2.0) return t * t * (-0.5 * t + 2.5) - 4.0 * t + 2.0;
  return 0.0;
}

std::size_t clamp_index(long i, std::size_t n) {
  return std::size_t(std::clamp(i, 0L, long(n) - 1));
}

}  // namespace

float sample_grid(const Grid& g, double row, double col, Resampling method) {
  // Coordinates within 1e-7 cell of a sample centre are that centre, so that a grid
  // resampled at its own spacing reproduces its samples exactly (no-data neighbours
  // included, which a weight of 1e-12 would otherwise pull in).
  constexpr double kSnap = 1e-7;
  if (std::abs(row - std::round(row)) < kSnap) row = std::round(row);
  if (std::abs(col - std::round(col)) < kSnap) col = std::round(col);
  if (method == Resampling::Bilinear) {
    const long c0 = std::clamp(long(std::floor(col)), 0L, long(g.cols) - 2);
    const long r0 = std::clamp(long(std::floor(row)), 0L, long(g.rows) - 2);
    const double tx = std::clamp(col - double(c0), 0.0, 1.0);
    const double ty = std::clamp(row - double(r0), 0.0, 1.0);
    const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    const float v[4] = {g.at(r0, c0), g.at(r0, c0 + 1), g.at(r0 + 1, c0), g.at(r0 + 1, c0 + 1)};
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) {
      if (w[k] == 0.0) continue;
      if (std::isnan(v[k])) return kNaN;
      sum += w[k] * v[k];
    }
    return float(sum);
  }
  const long c0 = long(std::floor(col)), r0 = long(std::floor(row));
  const double tx = col - double(c0), ty = row - double(r0);
  double wx[4], wy[4];
  for (int k = 0; k < 4; ++k) {
    wx[k] = keys(tx - (k - 1));
    wy[k] = keys(ty - (k - 1));
  }
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    if (wy[i] == 0.0) continue;
    const std::size_t r = clamp_index(r0 + i - 1, g.rows);
    for (int j = 0; j < 4; ++j) {
      if (wx[j] == 0.0) continue;
      const float v = g.at(r, clamp_index(c0 + j - 1, g.cols));
      if (std::isnan(v)) return kNaN;
      sum += wy[i] * wx[j] * v;
    }
  }
  return float(sum);
}

}  // namespace terrain
