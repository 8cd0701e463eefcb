#pragma once
// The 8-neighbourhood of a grid sample, the one neighbour walk of the toolkit (drainage's
// D8 codes name these directions: drainage/d8.hpp).
#include <array>
#include <cstddef>

namespace terrain {

// (row, column) offsets of the neighbours E, NE, N, NW, W, SW, S, SE (counter-clockwise
// from east; row 0 is north, so N is row - 1). Odd k are the diagonals.
inline constexpr std::array<int, 8> kDRow = {0, -1, -1, -1, 0, 1, 1, 1};
inline constexpr std::array<int, 8> kDCol = {1, 1, 0, -1, -1, -1, 0, 1};
// Order in which D8 tries the neighbours: E, N, W, S, then NE, NW, SW, SE (TauDEM).
inline constexpr std::array<int, 8> kTryOrder = {0, 2, 4, 6, 1, 3, 5, 7};

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
  void each(std::size_t i, F&& f) const {
    each(long(i) / cols, long(i) % cols, f);
  }
  template <class F>
  void each_in_try_order(std::size_t i, F&& f) const {
    each_in_try_order(long(i) / cols, long(i) % cols, f);
  }

 private:
  template <class F>
  void visit(long rr, long cc, int k, F& f) const {
    if (rr >= 0 && cc >= 0 && rr < rows && cc < cols) f(std::size_t(rr * cols + cc), k);
  }
};

}  // namespace terrain
