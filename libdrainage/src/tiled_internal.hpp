#pragma once
// Helpers shared by the tiled fill (tiled_fill.cpp) and the tiled network
// (tiled_network.cpp). Not installed.
#include <cstdint>
#include <string>

#include "drainage/tile_comm.hpp"

namespace drainage::tiled {

// The sum of every rank's `n`, on every rank.
inline std::uint64_t sum_over_ranks(const TileComm& comm, std::uint64_t n) {
  if (comm.size() == 1) return n;
  std::uint64_t sum = 0;
  for (const std::string& bytes : comm.all_gather(Packer().put(n).take())) sum += Unpacker(bytes).get<std::uint64_t>();
  return sum;
}

constexpr std::uint32_t kOutside = 0;  // the label of cells that drain off the grid (Barnes' "ocean")

// Position of tile cell (r, c) on the tile's perimeter ring (r or c on the tile's edge).
inline std::size_t ring_position(std::size_t r, std::size_t c, std::size_t nr, std::size_t nc) {
  if (r == 0) return c;
  if (r == nr - 1) return nc + c;
  if (c == 0) return 2 * nc + (r - 1);
  return 2 * nc + nr + (r - 1);
}
inline std::size_t ring_size(std::size_t nr, std::size_t nc) { return 2 * nc + 2 * nr; }

}  // namespace drainage::tiled
