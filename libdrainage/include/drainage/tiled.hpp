#pragma once
// Drainage steps tile by tile, for grids larger than memory: each tile is read (with a
// one-sample halo) through a window reader, processed alone, and what crosses tile edges
// is resolved on a graph of the tile perimeters (Barnes, Lehman & Mulla 2016, "Parallel
// Priority-Flood depression filling for trillion cell digital elevation models").
// The results equal the single-grid functions exactly (tests/drainage/tiled_test.cpp).
#include <array>
#include <cstddef>
#include <functional>
#include <string>

#include <vector>

#include "drainage/d8.hpp"
#include "drainage/tile_comm.hpp"
#include "terrain/big_vector.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/grid.hpp"

namespace drainage {

// A rows x cols grid cut into square tiles of `side` samples (the last row and column of
// tiles are cut to the grid), numbered row-major.
struct TileGrid {
  std::size_t rows = 0, cols = 0, side = 0;
  std::size_t tile_rows() const { return (rows + side - 1) / side; }
  std::size_t tile_cols() const { return (cols + side - 1) / side; }
  std::size_t count() const { return tile_rows() * tile_cols(); }
  terrain::RasterWindow window(std::size_t t) const;
  // `w` grown by one sample on each side, within the grid.
  terrain::RasterWindow halo(const terrain::RasterWindow& w) const;
};

// Whether cell (r, c) of an nr x nc tile lies on the tile's edge (its perimeter ring).
inline bool on_tile_edge(std::size_t r, std::size_t c, std::size_t nr, std::size_t nc) {
  return r == 0 || c == 0 || r == nr - 1 || c == nc - 1;
}

// Reads a window of the elevations (NaN = no-data): GDAL windowed reads of a raster
// (terrain::read_dem with a window), or a grid in memory in tests.
using WindowReader = std::function<terrain::Grid(const terrain::RasterWindow&)>;

// Priority-Flood filling (fill.hpp) tile by tile: two passes over the tiles, one tile in
// memory at a time plus the perimeter graph (O(perimeter) per tile). Pass 1 floods each
// tile from its perimeter and from the grid's own seeds (grid edge, beside no-data),
// labelling every cell with the perimeter cell (or "outside") that reached it, and records
// the lowest spill elevation between touching labels, inside tiles and across tile edges.
// The minimax (spill) elevation of every label from the outside is then solved on that
// graph; pass 2 floods each tile again and raises each cell to its label's spill.
// `done(t, tile)` receives each tile's filled elevations (tile t's window, in order).
// Returns the number of samples raised, as priority_flood_fill does.
// With several ranks (tile_comm.hpp), each rank floods its own tiles, rank 0 gathers the
// perimeter graph, solves it and sends each rank the spill elevations of its tiles' labels,
// and `done` is called on each tile's owner only.
// With `cache_path` (a file private to this rank, made and removed here), pass 1 keeps each
// tile's flooded elevations and labels there (8 bytes a cell) and pass 2 reads them back
// instead of flooding again (Barnes et al. 2016's "cache" strategy against "evict"): the
// fill's time nearly halves; the results are the same. Tiles are flooded on all threads (a
// tile per thread in memory; `read` is called from several at once); `done` runs one at a
// time, in tile order.
std::size_t tiled_priority_flood_fill(const TileGrid& tiles, const WindowReader& read,
                                      const std::function<void(std::size_t, terrain::Grid&)>& done,
                                      const TileComm& comm = single_process(),
                                      const std::string& cache_path = {});

// Reads the D8 codes (d8.hpp) of a window.
using CodeReader = std::function<D8Codes(const terrain::RasterWindow&)>;

// One tile of a tiled network, final: the fields a .dv version 2 block stores.
struct NetworkTile {
  terrain::RasterWindow window;
  D8Codes dirs;  // the tile's codes
  terrain::BigVector<std::uint8_t>
      cut;  // 1 where dirs < 8 but the flow ends (enters no-data or leaves the grid)
  terrain::BigVector<std::uint32_t> accumulated;  // as Network::accumulated
  terrain::BigVector<std::uint32_t> basin;        // as Network::basin (global ids)
  terrain::BigVector<std::uint8_t> order;         // as Network::order
  std::vector<char> prepared;                     // what the caller's `prepare` made of it
};

// What the whole network has that no tile has alone.
struct NetworkTotals {
  std::size_t points = 0, branches = 0;
  // The points by class, as the .dv's reader derives them: pits (outlets included),
  // ridges, channels, junctions.
  std::array<std::uint64_t, 4> classes{};
  std::vector<std::uint32_t> pits,
      pit_accumulated;  // by basin id: as Network::pits, and their flow
};

// analyze_network (network.hpp) tile by tile, with identical results (Barnes 2017,
// "Parallel non-divergent flow accumulation for trillion cell digital elevation models",
// extended to Strahler order and basins). Pass 1 reads each tile's codes with a one-sample
// halo and reduces the cells whose flow comes from outside the tile to a small graph:
// nodes are cells entered from outside, cells where two such flows merge, and cells whose
// flow leaves the tile or ends; an edge carries the accumulation added along its path and
// the path's Strahler order as a table of the incoming order. The graph of all tiles is
// solved in topological order (accumulation, order, the pit each node drains to); pass 2
// reads each tile again, completes it and hands it to `done(t, tile)` in tile order.
// With several ranks, as tiled_priority_flood_fill: rank 0 gathers the tiles' graphs,
// solves them and sends each rank its tiles' node values; `done` runs on each tile's owner,
// in tile order there; rank 0 returns the totals, the other ranks the counts (points,
// branches) without the pits. Tiles are worked on all threads (a tile per thread in
// memory; `read` is called from several at once): `prepare(t, tile)`, when given, runs on the
// tile's thread as soon as it is complete (to encode it, say, into tile.prepared; it must only read
// shared state; `done` then gets the tile with `prepared` only, its arrays released), `done` one at
// a time.
NetworkTotals tiled_network(const TileGrid& tiles, const CodeReader& read,
                            const std::function<void(std::size_t, const NetworkTile&)>& done,
                            const TileComm& comm = single_process(),
                            const std::function<void(std::size_t, NetworkTile&)>& prepare = {});

}  // namespace drainage
