#pragma once
// Hillshade from unit normals, for previews.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "terrain/grid.hpp"

namespace terrain {

// Grey level 0..255 per normal: 255 * max(0, n . L), L the unit vector towards a light at
// azimuth `azimuth_deg` (clockwise from grid north, +y) and altitude `altitude_deg` above
// the horizon. The default is the cartographic convention (315, 45): lit from the NW.
std::vector<std::uint8_t> hillshade(std::span<const Eigen::Vector3f> normals,
                                    double azimuth_deg = 315.0, double altitude_deg = 45.0);

// Hillshade of a grid (rows x cols, row 0 north): area-weighted vertex normals of its
// triangulated samples, elevations scaled by `z_factor`; geographic grids use metres per
// degree at their centre. No-data samples get 0 (callers mask them).
std::vector<std::uint8_t> hillshade_grid(const Grid& grid, double azimuth_deg = 315.0,
                                         double altitude_deg = 45.0, double z_factor = 1.0);

// RGB (3 bytes per value) of `values` on a perceptual blue-green-yellow ramp from `lo`
// (dark blue) to `hi` (yellow), clamped; NaN gives black.
std::vector<std::uint8_t> colour_ramp(std::span<const float> values, double lo, double hi);

// The unit vector towards the light of hillshade().
Eigen::Vector3d light_direction(double azimuth_deg, double altitude_deg);

}  // namespace terrain
