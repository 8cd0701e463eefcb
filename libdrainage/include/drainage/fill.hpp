#pragma once
// Depression filling by Priority-Flood (Barnes, Lehman & Mulla 2014, "Priority-Flood: An
// optimal depression-filling and watershed-labeling algorithm"; docs/algorithms.md 8.1-8.2).
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "drainage/d8.hpp"

#include "terrain/grid.hpp"

namespace drainage {

// Raises every sample of `z` that cannot drain to the grid boundary to its spill
// elevation, leaving flat surfaces (resolved afterwards by resolve_flats). Seeds: samples
// on the grid edge or beside no-data (water leaves there). 8-connected, as TauDEM's
// pitremove. Deterministic: queue ties break by sample index. Returns how many samples
// were raised. Samples on slopes go through a radix heap (FloodQueue); depression interiors
// use a FIFO (the "improved" variant). Tested against TauDEM pitremove on a real DEM.
std::size_t priority_flood_fill(terrain::Grid& z);

struct BreachStats {
  std::size_t carved = 0;  // samples lowered
  std::size_t raised = 0;  // samples raised (depressions deeper than max_depth, filled)
  double max_carve = 0;    // the deepest lowering, metres
};

// Depression breaching (Lindsay 2016, "Efficient hybrid breaching-filling sink removal
// methods for flow path enforcement in digital elevation models"; docs/algorithms.md 8.4):
// a Priority-Flood from the same seeds as priority_flood_fill, remembering from which
// sample each one was reached. When it reaches a sample j below the flood level, instead
// of raising j it lowers the path by which the flood came - back to the first sample
// already below j - so that j drains along it: the path gets a uniform gradient from j
// down to that sample (a few float steps below j where the path leaves the grid). A path
// that would have to be lowered more than `max_depth` below any of its original
// elevations is left alone and j is raised instead (filled), so deep depressions become
// lakes whose rims are cut by at most max_depth. After it every sample has a path to a
// seed that never rises, and only filled lakes are flat. Deterministic (ties by index).
BreachStats breach_depressions(terrain::Grid& z, double max_depth);

// The Priority-Flood's queue: lowest elevation first, ties by cell index. A radix heap
// (Ahuja, Mehlhorn, Orlin & Tarjan 1990, "Faster algorithms for the shortest path
// problem"): a flood only ever pushes a cell above the one it last took, so each key is
// bucketed by its highest bit that differs from the last key taken, and a bucket is split
// only when it becomes the lowest. The same order as a binary heap on (elevation, index),
// a fifth fewer cycles in a 2048 x 2048 tile of Logan 1 m (docs/performance.md, "Fifth
// session").
class FloodQueue {
 public:
  // Cell i at elevation z (not NaN), above the cell last taken.
  void push(float z, std::uint32_t i) {
    const std::uint64_t k = key(z, i);
    buckets_[bucket(k)].push_back(k);
    ++size_;
  }
  bool empty() const { return size_ == 0; }
  // The lowest cell's index.
  std::uint32_t pop() {
    if (buckets_[0].empty()) {
      std::size_t b = 1;
      while (buckets_[b].empty()) ++b;
      std::vector<std::uint64_t>& from = buckets_[b];
      last_ = *std::min_element(from.begin(), from.end());
      for (const std::uint64_t k : from) buckets_[bucket(k)].push_back(k);
      from.clear();
    }
    --size_;
    const std::uint64_t k = buckets_[0].back();
    buckets_[0].pop_back();
    return std::uint32_t(k);
  }

 private:
  // Ordered as (z, i): the float's bits flipped to sort as unsigned, -0 as +0.
  static std::uint64_t key(float z, std::uint32_t i) {
    std::uint32_t u = std::bit_cast<std::uint32_t>(z == 0.0f ? 0.0f : z);
    u = (u & 0x80000000u) ? ~u : (u | 0x80000000u);
    return std::uint64_t(u) << 32 | i;
  }
  std::size_t bucket(std::uint64_t k) const {
    return k == last_ ? 0 : std::size_t(64 - std::countl_zero(k ^ last_));
  }
  std::array<std::vector<std::uint64_t>, 65> buckets_;
  std::uint64_t last_ = 0;
  std::size_t size_ = 0;
};

// The Priority-Flood loop itself, shared by priority_flood_fill and the tiled fill: floods
// the rows x cols array `z` from `seeds` (ascending cell indices, already claimed) by
// elevation, ties by cell index, depression interiors first-in first-out. claim(i, j) is
// asked for each in-grid neighbour j of a cell i taken from the queue and says whether j
// is to be flooded from i now (the caller then marks j as taken); a flooded j lower than
// i is raised to i. Returns how many cells were raised.
template <class Z, class Claim>
std::size_t priority_flood(Z& z, long rows, long cols, const std::vector<std::uint32_t>& seeds,
                           Claim&& claim) {
  FloodQueue open;
  for (const std::uint32_t i : seeds) open.push(z[i], i);
  std::vector<std::uint32_t> pit;  // FIFO of depression cells, with a head index
  std::size_t pit_head = 0, raised = 0;
  while (!open.empty() || pit_head < pit.size()) {
    std::uint32_t i;
    if (pit_head < pit.size()) {
      i = pit[pit_head++];
      if (pit_head == pit.size()) pit.clear(), pit_head = 0;
    } else {
      i = open.pop();
    }
    Neighbours{rows, cols}.each(i, [&](std::size_t jj, int) {
      const std::uint32_t j = std::uint32_t(jj);
      if (!claim(i, j)) return;
      if (z[j] <= z[i]) {
        if (z[j] < z[i]) ++raised;
        z[j] = z[i];
        pit.push_back(j);
      } else {
        open.push(z[j], j);
      }
    });
  }
  return raised;
}

}  // namespace drainage
