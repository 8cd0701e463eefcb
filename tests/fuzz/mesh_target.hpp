#pragma once
// What fuzz_ply runs on one input, shared with the regression test: the terrain mesh
// reader (strict PLY header, OpenMesh's body parser, the grid, lattice and value checks),
// then on what was read the PN surface sampled as build-drainage's mesh mode samples it
// (every face's patch evaluated), so that a header the reader lets through is exercised
// end to end. Throws terrain::Error for a bad file.
#include <algorithm>
#include <string>

#include "terrain/mesh_io.hpp"
#include "terrain/pn_surface.hpp"

namespace terrain::fuzz {

inline void mesh_target(const std::string& path) {
  const GridMesh m = read_mesh_ply(path);
  if (m.n_vertices() > 20000) return;  // keep each run short
  // Twice as fine as the mesh, as the mesh mode's 10 m sampling of a 50 m mesh is finer.
  (void)sample_pn_surface(m, std::min(m.geo.dx, m.geo.dy) / 2);
}

}  // namespace terrain::fuzz
