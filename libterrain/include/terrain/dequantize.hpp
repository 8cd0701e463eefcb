#pragma once
// Integer DEMs (SRTM, many national DEMs store whole metres) terrace gentle slopes into flats
// one unit high: the drainage finds flats where the ground slopes, and creases run across
// them in parallel D8 tracks. The true height of a sample stored as integer k lies
// in [k - 0.5, k + 0.5], and the edge between two terraces is the contour half-way between
// them: heights interpolated between those contours remove the steps, keep every valley
// floor descending and come closer to the true surface than any smoothing of the steps
// (docs/dem2mesh.md, "Integer DEMs").
#include <cstddef>
#include <vector>

#include "terrain/grid.hpp"

namespace terrain {

// Whether every valid sample of `grid` is a whole number and they span at least 3 values:
// a DEM quantised to whole units.
bool is_integer_dem(const Grid& grid);

// Heights between the terraces' edges (h = half_step): a sample of value k lies at geodesic
// distance d_lo (within its terrace: 8-connected samples of value k) from the contour with the
// lower terrace and d_hi from the higher one (half a sample beyond the terrace's edge samples),
// and gets k - h + 2h d_lo / (d_lo + d_hi), linear across the terrace. Terraces with one kind
// of edge (summits, pits) rise or fall by 2h to their farthest sample; terraces with none
// keep k. NaN where `grid` has no data.
std::vector<double> terrace_interpolation(const Grid& grid, double half_step = 0.5);

// terrace_interpolation, then smoothed within `within` of it: each sample moves to the
// NaN-aware box mean of its neighbourhood, clamped to within `within` of its interpolated
// height, at radii 16, 8, 4, 2 and 1 samples (4 rounds each, 16 at radius 1). This removes
// the interpolation's folds along each terrace's middle and keeps its descent: a clamp to the
// stored value's half-unit band instead left valley floors flat at k + 0.5, since the box
// mean over a valley lies above its floor. No-data stays no-data. Returns the largest change
// from the stored value (<= half_step + within).
double dequantize(Grid& grid, double half_step = 0.5, double within = 0.1);

}  // namespace terrain
