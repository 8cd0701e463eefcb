#pragma once
// D8 steepest-descent flow directions (O'Callaghan & Mark 1984; docs/algorithms.md 7).
//
// The one direction convention of the toolkit (locked by tests/drainage/d8_test.cpp):
//   code k = 0..7 names the neighbour  E, NE, N, NW, W, SW, S, SE  (counter-clockwise
//   from east, TauDEM's order; TauDEM code = k + 1), with (row, col) offsets below (row 0
//   is north, so N is row - 1). Special codes: kNoFlow (no lower neighbour: a pit or a
//   flat cell), kOutlet (flow leaves the grid or enters no-data), kNodata (not a point).
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "terrain/big_vector.hpp"
#include "terrain/grid.hpp"
#include "terrain/neighbours.hpp"

namespace drainage {

// One D8 code per grid sample.
using D8Codes = terrain::BigVector<std::uint8_t>;

inline constexpr std::uint8_t kNoFlow = 8;
inline constexpr std::uint8_t kOutlet = 9;
inline constexpr std::uint8_t kNodata = 255;
inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;  // "no vertex" in index arrays

using terrain::kDCol;  // terrain/neighbours.hpp: the offsets of E, NE, N, NW, W, SW, S, SE
using terrain::kDRow;
using terrain::Neighbours;
inline constexpr std::array<const char*, 8> kName = {"E", "NE", "N", "NW", "W", "SW", "S", "SE"};
// Neighbours are tried in terrain::kTryOrder; a later one replaces the best only when
// strictly steeper, so ties go to the first cardinal of E, N, W, S, then NE, NW, SW, SE.
using terrain::kTryOrder;

// Codes of other tools, indexed by our code k (0..7).
inline constexpr std::array<int, 8> kTaudemCode = {1, 2, 3, 4, 5, 6, 7, 8};
inline constexpr std::array<int, 8> kEsriCode = {1, 128, 64, 32, 16, 8, 4, 2};

enum class D8Encoding { Taudem, Esri };
D8Encoding parse_d8_encoding(std::string_view name);  // "taudem" | "esri"; throws terrain::Error

// Our code for a foreign code; kNoFlow for the encoding's "no direction" (0), kNodata for
// a no-data sample; throws terrain::Error naming the value when it is out of range.
std::uint8_t from_foreign_code(double value, D8Encoding enc, bool is_nodata);
// The foreign code of our code; 0 for kNoFlow / kOutlet (no in-grid direction).
int to_foreign_code(std::uint8_t code, D8Encoding enc);

// Steepest-descent direction of every sample of `z` (rows x cols, NaN = no-data):
// slope_k = (z_c - z_k) / dist_k with dist = dx, dy or hypot(dx, dy) in metres (a
// geographic grid's per-row geodesic cell sizes, terrain::metric_cell_sizes); the steepest strictly
// positive slope wins, ties by kTryOrder. Boundary rule: a neighbour off the grid or in
// no-data is extrapolated linearly, z = 2 z_c - z_opposite (z_c when the opposite sample is
// missing too); if such a virtual neighbour is the steepest, or a boundary sample has no
// lower neighbour at all, the sample is an outlet (kOutlet). Interior samples with no lower
// neighbour get kNoFlow. Parallel over rows; the result does not depend on the threads.
D8Codes d8_directions(const terrain::Grid& z);

// Index of the downstream sample of `i` under `code`, or kNone (kNoFlow, kOutlet, kNodata).
inline std::uint32_t downstream(std::uint32_t i, std::uint8_t code, std::size_t cols) {
  if (code >= 8) return kNone;
  return std::uint32_t(std::int64_t(i) + std::int64_t(kDRow[code]) * std::int64_t(cols) +
                       kDCol[code]);
}

// The one downstream step: the (row, column) that in-grid code k (0..7) points to from
// (r, c), which may lie off the grid (or off a window: the caller decides what that means).
struct RowCol {
  long r, c;
};
inline RowCol step(long r, long c, std::uint8_t k) { return {r + kDRow[k], c + kDCol[k]}; }

// The sample that sample i of a rows x cols grid of codes drains into, or kNone where the
// flow ends (no direction, off the grid, into no-data).
inline std::size_t flows_into(const D8Codes& dirs, std::size_t rows, std::size_t cols,
                              std::size_t i) {
  if (dirs[i] >= 8) return kNone;
  const RowCol d = step(long(i / cols), long(i % cols), dirs[i]);
  if (d.r < 0 || d.c < 0 || d.r >= long(rows) || d.c >= long(cols)) return kNone;
  const std::size_t j = std::size_t(d.r) * cols + std::size_t(d.c);
  return dirs[j] == kNodata ? kNone : j;
}

}  // namespace drainage
