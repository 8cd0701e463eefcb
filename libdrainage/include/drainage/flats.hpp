#pragma once
// Flat resolution (Barnes, Lehman & Mulla 2014, "An efficient assignment of drainage
// direction over flat surfaces in raster digital elevation models"; docs/algorithms.md 8.5).
#include <cstdint>
#include <vector>

#include "drainage/d8.hpp"
#include "terrain/grid.hpp"

namespace drainage {

struct FlatStats {
  std::size_t flats = 0;           // connected flats (equal elevation, no-flow cells)
  std::size_t undrainable = 0;     // flats with no lower outlet (closed depressions)
  std::size_t cells_resolved = 0;  // no-flow cells that received a direction
};

// Gives a direction to every kNoFlow sample of `dirs` (from d8_directions on `z`) that lies
// on a drainable flat: towards lower terrain, away from higher terrain (mask
// M = 2 T + (H - A), direction to the same-flat neighbour with the smallest M, ties by
// kTryOrder). An undrainable flat (a flat-bottomed pit) is not left as thousands of
// one-sample pits: its sample farthest from higher ground (largest A, then lowest index)
// stays the single pit and the rest of the flat drains to it the same way. Deterministic
// and sequential (breadth-first searches). Tested on the worked example of docs/algorithms.md
// 8.7, a plateau with one outlet, and real DEMs (no kNoFlow left except one per flat).
FlatStats resolve_flats(const terrain::Grid& z, D8Codes& dirs);

}  // namespace drainage
