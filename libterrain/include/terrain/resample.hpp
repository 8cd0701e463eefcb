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

}  // namespace terrain
