#include "terrain/grid.hpp"

#include <algorithm>
#include <limits>

namespace terrain {

std::vector<std::uint8_t> Grid::nodata_mask() const {
  std::vector<std::uint8_t> mask(z.size());
  std::transform(z.begin(), z.end(), mask.begin(),
                 [](float v) { return static_cast<std::uint8_t>(std::isnan(v)); });
  return mask;
}

std::size_t Grid::mark_nodata(float value) {
  std::size_t n = 0;
  for (float& v : z)
    if (v == value) v = std::numeric_limits<float>::quiet_NaN(), ++n;
  return n;
}

std::size_t Grid::count_nodata() const {
  std::size_t n = 0;
  const float* v = z.data();
  const std::size_t size = z.size();
#pragma omp simd reduction(+ : n)
  for (std::size_t i = 0; i < size; ++i) n += std::size_t(v[i] != v[i]);  // NaN: no data
  return n;
}

ElevationStats elevation_stats(std::span<const float> z) {
  ElevationStats s;
  double sum = 0.0, sum2 = 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (float v : z) {
    if (std::isnan(v)) {
      ++s.nodata;
      continue;
    }
    ++s.count;
    sum += v;
    sum2 += double(v) * v;
    lo = std::min(lo, double(v));
    hi = std::max(hi, double(v));
  }
  if (s.count > 0) {
    s.min = lo;
    s.max = hi;
    s.mean = sum / double(s.count);
    s.stddev = std::sqrt(std::max(0.0, sum2 / double(s.count) - s.mean * s.mean));
  }
  return s;
}

}  // namespace terrain
