#pragma once
// Integer DEMs (SRTM, many national DEMs store whole metres) terrace gentle slopes into flats
// one unit high: the drainage finds flats where the ground slopes, and creases run across
// them in parallel D8 tracks (issue 38). The true height of a sample stored as integer k lies
// in [k - 0.5, k + 0.5]; the smoothest surface within those bounds removes the steps and
// changes nothing else by more than half a unit (docs/dem2mesh.md, "Integer DEMs").
#include <cstddef>

#include "terrain/grid.hpp"

namespace terrain {

// Whether every valid sample of `grid` is a whole number and they span at least 3 values:
// a DEM quantised to whole units.
bool is_integer_dem(const Grid& grid);

// Constrained smoothing: each sample moves to the NaN-aware box mean of its neighbourhood,
// then is clamped to within `half_step` of its original value, repeated at radii 16, 8, 4,
// 2 and 1 samples (4 rounds each; wide terraces need the large boxes, the small ones
// restore the detail). No-data stays no-data. Returns the largest change (<= half_step).
double dequantize(Grid& grid, double half_step = 0.5);

}  // namespace terrain
