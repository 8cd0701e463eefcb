#pragma once
// Point sampling of a grid at fractional sample coordinates.
#include <string_view>

#include "terrain/grid.hpp"

namespace terrain {

enum class Resampling { Bilinear, Cubic };

// Parses "bilinear" / "cubic"; throws Error otherwise.
Resampling parse_resampling(std::string_view name);

// Value of `grid` at fractional sample coordinates (row, col), where integer coordinates
// are sample centres (see grid.hpp). Bilinear uses the 4 surrounding samples; cubic the
// 4 x 4 Keys kernel with a = -0.5, as GDAL's "cubic" (docs/algorithms.md 10.3). Indices beyond
// the grid are clamped to the edge sample. Returns NaN when a sample with non-zero weight
// is no-data. Tested against hand-worked values and against gdalwarp (tests/resample_test).
float sample_grid(const Grid& grid, double row, double col, Resampling method);

// The kernel is separable: sample_grid = sample_taps(grid, taps(row), taps(col)). A
// resampling whose source rows depend on the target row only and source columns on the
// target column only computes the taps once per row and once per column.
struct SampleTaps {
  std::size_t index[4];  // samples along one axis, clamped to the grid
  double weight[4];
  int n = 0;
};
SampleTaps sample_taps(double coord, std::size_t n, Resampling method);
float sample_taps(const Grid& grid, const SampleTaps& row, const SampleTaps& col);

}  // namespace terrain
