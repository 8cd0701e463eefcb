#pragma once
// The georeferenced elevation grid and its one coordinate convention.
//
// Convention (locked by tests/grid_test.cpp):
//   * row 0 is the northern row, rows grow southwards; column 0 is the western column,
//     columns grow eastwards (a north-up GDAL raster);
//   * (x0, y0) is the upper-left CORNER of the upper-left cell (GDAL geotransform);
//   * sample (r, c) sits at the CENTRE of its cell:
//         x(c) = x0 + (c + 0.5) * dx        y(r) = y0 - (r + 0.5) * dy
//   * dx, dy are positive cell sizes in CRS units (metres, or degrees for geographic).
// Elevations are float, coordinates double. No-data samples are NaN.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "terrain/big_vector.hpp"

namespace terrain {

enum class CrsKind { None, Geographic, Projected };

struct Georef {
  double x0 = 0.0;  // upper-left corner, CRS units
  double y0 = 0.0;
  double dx = 1.0;      // cell width (E-W), > 0
  double dy = 1.0;      // cell height (N-S), > 0
  std::string crs_wkt;  // empty when the CRS is unknown
  int epsg = 0;         // 0 when no EPSG code is known
  CrsKind crs_kind = CrsKind::None;

  double x_of_col(double c) const { return x0 + (c + 0.5) * dx; }
  double y_of_row(double r) const { return y0 - (r + 0.5) * dy; }
  double col_of_x(double x) const { return (x - x0) / dx - 0.5; }
  double row_of_y(double y) const { return (y0 - y) / dy - 0.5; }
  // The georeferencing of a window whose first sample is this grid's (row, col).
  Georef window(std::size_t row, std::size_t col) const {
    Georef g = *this;
    g.x0 += double(col) * dx;
    g.y0 -= double(row) * dy;
    return g;
  }
};

struct Grid {
  std::size_t rows = 0;
  std::size_t cols = 0;
  Georef geo;
  BigVector<float> z;  // rows * cols, row-major, NaN = no data

  Grid() = default;
  Grid(std::size_t rows_, std::size_t cols_, Georef geo_, float fill = 0.0f)
      : rows(rows_), cols(cols_), geo(std::move(geo_)), z(rows_ * cols_, fill) {}

  std::size_t size() const { return z.size(); }
  std::size_t index(std::size_t r, std::size_t c) const { return r * cols + c; }
  float at(std::size_t r, std::size_t c) const { return z[r * cols + c]; }
  float& at(std::size_t r, std::size_t c) { return z[r * cols + c]; }
  bool valid(std::size_t i) const { return !std::isnan(z[i]); }

  // 1 where the sample is no-data, 0 elsewhere (rows * cols).
  std::vector<std::uint8_t> nodata_mask() const;
  // Marks every sample equal to `value` no-data (NaN); returns how many.
  std::size_t mark_nodata(float value);
  std::size_t count_nodata() const;
};

// Summary statistics of the valid samples (count 0 when there are none).
struct ElevationStats {
  std::size_t count = 0;
  std::size_t nodata = 0;
  double min = 0.0, max = 0.0, mean = 0.0, stddev = 0.0;
};
ElevationStats elevation_stats(std::span<const float> z);

// Human-readable CRS name ("NAD83 / UTM zone 10N"), or "none" without a CRS.
std::string crs_name(const Georef& geo);

}  // namespace terrain
