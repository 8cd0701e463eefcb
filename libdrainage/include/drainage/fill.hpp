#pragma once
// Depression filling by Priority-Flood (Barnes, Lehman & Mulla 2014, "Priority-Flood: An
// optimal depression-filling and watershed-labeling algorithm"; docs/algorithms.md 8.1-8.2).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

#include "drainage/d8.hpp"

#include "terrain/grid.hpp"

namespace drainage {

// Raises every sample of `z` that cannot drain to the grid boundary to its spill
// elevation, leaving flat surfaces (resolved afterwards by resolve_flats). Seeds: samples
// on the grid edge or beside no-data (water leaves there). 8-connected, as TauDEM's
// pitremove. Deterministic: queue ties break by sample index. Returns how many samples
// were raised. O(n log n) in the samples that go through the heap; depression interiors
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

// The queue of the floods below: lowest elevation first, ties by cell index.
struct FloodItem {
  float z;
  std::uint32_t i;
  bool operator>(const FloodItem& o) const { return z > o.z || (z == o.z && i > o.i); }
};
using FloodQueue = std::priority_queue<FloodItem, std::vector<FloodItem>, std::greater<FloodItem>>;

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
  for (const std::uint32_t i : seeds) open.push({z[i], i});
  std::vector<std::uint32_t> pit;  // FIFO of depression cells, with a head index
  std::size_t pit_head = 0, raised = 0;
  while (!open.empty() || pit_head < pit.size()) {
    std::uint32_t i;
    if (pit_head < pit.size()) {
      i = pit[pit_head++];
      if (pit_head == pit.size()) pit.clear(), pit_head = 0;
    } else {
      i = open.top().i;
      open.pop();
    }
    Neighbours{rows, cols}.each(i, [&](std::size_t jj, int) {
      const std::uint32_t j = std::uint32_t(jj);
      if (!claim(i, j)) return;
      if (z[j] <= z[i]) {
        if (z[j] < z[i]) ++raised;
        z[j] = z[i];
        pit.push_back(j);
      } else {
        open.push({z[j], j});
      }
    });
  }
  return raised;
}

}  // namespace drainage
