#pragma once
// Depression filling by Priority-Flood (Barnes, Lehman & Mulla 2014, "Priority-Flood: An
// optimal depression-filling and watershed-labeling algorithm"; docs/algorithms.md 8.1-8.2).
#include <cstddef>

#include "terrain/grid.hpp"

namespace drainage {

// Raises every sample of `z` that cannot drain to the grid boundary to its spill
// elevation, leaving flat surfaces (resolved afterwards by resolve_flats). Seeds: samples
// on the grid edge or beside no-data (water leaves there). 8-connected, as TauDEM's
// pitremove. Deterministic: queue ties break by sample index. Returns how many samples
// were raised. O(n log n) in the samples that go through the heap; depression interiors
// use a FIFO (the "improved" variant). Tested against TauDEM pitremove on a real DEM.
std::size_t priority_flood_fill(terrain::Grid& z);

}  // namespace drainage
