#pragma once
// dem2mesh --tile-size / --memory: the mesh made and written in bands of rows, for DEMs
// larger than memory (docs/dem2mesh.md, "DEMs larger than memory"). Each band's source
// window is read, resampled with the whole grid's arithmetic, meshed with a row of margin
// above and below (so its normals are the whole mesh's) and appended to the PLY and the
// pyramid; only one band is held. The files are a single run's, byte for byte.
#include <cstdint>
#include <string>

#include "common.hpp"
#include "terrain/grid.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/prepare_grid.hpp"

namespace terrain::tools::mesh {

// --tile-size ROWS and --memory MIB.
void add_band_options(CLI::App& app, std::size_t& rows, double& memory_mib);

struct BandedRequest {
  std::string input, output, pyramid;  // pyramid: empty for none
  std::string src_crs, dequantize;     // as --src-crs, --dequantize
  terrain::GridRequest grid;
  terrain::NormalWeighting weighting = terrain::NormalWeighting::Uniform;
  std::size_t band_rows = 0;  // --tile-size; 0: from memory_mib
  double memory_mib = 0;      // --memory
  std::string provenance;
};

// What needs the whole grid at once (each named in the Error): scattered points,
// --fit-normals, --fill-nodata, --grid-out, dequantizing (--dequantize on).
struct WholeGridNeeds {
  bool points, fit, fill_nodata, grid_out;
  std::string dequantize;
};
void check_banded(const WholeGridNeeds& needs);

struct BandedResult {
  terrain::Georef geo;  // the grid's
  terrain::GridTopology topo;
  std::size_t band_rows = 0;
  std::uint64_t pyramid_bytes = 0;
};
// Writes the PLY and (with a pyramid path) the pyramid together, or neither.
BandedResult mesh_in_bands(const BandedRequest& request, const Verbosity& verb);

}  // namespace terrain::tools::mesh
