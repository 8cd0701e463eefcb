#pragma once
// Drainage steps tile by tile, for grids larger than memory: each tile is read (with a
// one-sample halo) through a window reader, processed alone, and what crosses tile edges
// is resolved on a graph of the tile perimeters (Barnes, Lehman & Mulla 2016, "Parallel
// Priority-Flood depression filling for trillion cell digital elevation models").
// The results equal the single-grid functions exactly (tests/drainage/tiled_test.cpp).
#include <cstddef>
#include <functional>

#include "terrain/dem_io.hpp"
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
};

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
std::size_t tiled_priority_flood_fill(const TileGrid& tiles, const WindowReader& read,
                                      const std::function<void(std::size_t, terrain::Grid&)>& done);

}  // namespace drainage
