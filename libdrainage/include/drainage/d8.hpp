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

namespace drainage {

// One D8 code per grid sample.
using D8Codes = terrain::BigVector<std::uint8_t>;

inline constexpr std::uint8_t kNoFlow = 8;
inline constexpr std::uint8_t kOutlet = 9;
inline constexpr std::uint8_t kNodata = 255;
inline constexpr std::uint32_t kNone = 0xFFFFFFFFu;  // "no vertex" in index arrays

inline constexpr std::array<int, 8> kDRow = {0, -1, -1, -1, 0, 1, 1, 1};
inline constexpr std::array<int, 8> kDCol = {1, 1, 0, -1, -1, -1, 0, 1};
inline constexpr std::array<const char*, 8> kName = {"E", "NE", "N", "NW", "W", "SW", "S", "SE"};
// Order in which neighbours are tried; a later one replaces the best only when strictly
// steeper, so ties go to the first cardinal of E, N, W, S, then NE, NW, SW, SE (TauDEM).
inline constexpr std::array<int, 8> kTryOrder = {0, 2, 4, 6, 1, 3, 5, 7};

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

// The 8-neighbourhood of a rows x cols grid, the one loop over kDRow/kDCol: f(j, k) gets
// the row-major index j of each in-grid neighbour and its direction code k.
struct Neighbours {
  long rows, cols;
  // Each neighbour j of cell (r, c), lying in direction k from it, k = 0..7.
  template <class F>
  void each(long r, long c, F&& f) const {
    for (int k = 0; k < 8; ++k) visit(r + kDRow[std::size_t(k)], c + kDCol[std::size_t(k)], k, f);
  }
  // The same in kTryOrder (where the first of equals wins).
  template <class F>
  void each_in_try_order(long r, long c, F&& f) const {
    for (int k : kTryOrder) visit(r + kDRow[std::size_t(k)], c + kDCol[std::size_t(k)], k, f);
  }
  // Each neighbour j from which flow along code k enters (r, c): j = (r, c) - offset of k.
  template <class F>
  void inflows(long r, long c, F&& f) const {
    for (int k = 0; k < 8; ++k) visit(r - kDRow[std::size_t(k)], c - kDCol[std::size_t(k)], k, f);
  }
  template <class F>
  void each(std::size_t i, F&& f) const { each(long(i) / cols, long(i) % cols, f); }
  template <class F>
  void each_in_try_order(std::size_t i, F&& f) const { each_in_try_order(long(i) / cols, long(i) % cols, f); }

 private:
  template <class F>
  void visit(long rr, long cc, int k, F& f) const {
    if (rr >= 0 && cc >= 0 && rr < rows && cc < cols) f(std::size_t(rr * cols + cc), k);
  }
};

// Index of the downstream sample of `i` under `code`, or kNone (kNoFlow, kOutlet, kNodata).
inline std::uint32_t downstream(std::uint32_t i, std::uint8_t code, std::size_t cols) {
  if (code >= 8) return kNone;
  return std::uint32_t(std::int64_t(i) + std::int64_t(kDRow[code]) * std::int64_t(cols) + kDCol[code]);
}

}  // namespace drainage
