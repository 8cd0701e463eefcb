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

SampleTaps sample_taps(double coord, std::size_t n, Resampling method) {
  // Coordinates within 1e-7 cell of a sample centre are that centre, so that a grid
  // resampled at its own spacing reproduces its samples exactly (no-data neighbours
  // included, which a weight of 1e-12 would otherwise pull in).
  constexpr double kSnap = 1e-7;
  if (std::abs(coord - std::round(coord)) < kSnap) coord = std::round(coord);
  SampleTaps t;
  if (method == Resampling::Bilinear) {
    const long i0 = std::clamp(long(std::floor(coord)), 0L, long(n) - 2);
    const double f = std::clamp(coord - double(i0), 0.0, 1.0);
    t.n = 2;
    t.index[0] = std::size_t(i0), t.index[1] = std::size_t(i0 + 1);
    t.weight[0] = 1 - f, t.weight[1] = f;
    return t;
  }
  const long i0 = long(std::floor(coord));
  const double f = coord - double(i0);
  t.n = 4;
  for (int k = 0; k < 4; ++k) {
    t.index[k] = clamp_index(i0 + k - 1, n);
    t.weight[k] = keys(f - (k - 1));
  }
  return t;
}

float sample_taps(const Grid& g, const SampleTaps& row, const SampleTaps& col) {
  double sum = 0.0;
  for (int i = 0; i < row.n; ++i) {
    if (row.weight[i] == 0.0) continue;
    const float* line = g.z.data() + row.index[i] * g.cols;
    for (int j = 0; j < col.n; ++j) {
      if (col.weight[j] == 0.0) continue;
      const float v = line[col.index[j]];
      if (std::isnan(v)) return kNaN;
      sum += col.weight[j] * row.weight[i] * v;
    }
  }
  return float(sum);
}

float sample_grid(const Grid& g, double row, double col, Resampling method) {
  return sample_taps(g, sample_taps(row, g.rows, method), sample_taps(col, g.cols, method));
}

}  // namespace terrain
