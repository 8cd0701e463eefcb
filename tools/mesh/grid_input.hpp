#pragma once
// dem2mesh's inputs onto the grid: a raster DEM (only the window the crop needs is read,
// integer heights dequantized, resampled) or scattered points (projected, triangulated,
// interpolated), with the source samples kept for --fit-normals.
#include <optional>
#include <string>

#include "common.hpp"
#include "terrain/fit_normals.hpp"
#include "terrain/grid.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/prepare_grid.hpp"

namespace terrain::tools::mesh {

// A raster DEM: only the source window the crop needs is read (plus the kernel's margin),
// then resampled onto the grid. `source` (optional) receives the source samples read, in
// the grid's CRS, for --fit-normals. `src_crs` (--src-crs) replaces the raster's own CRS,
// as gdalwarp's -s_srs. `filled` receives which samples --fill-nodata filled (#samples,
// 1 where filled; empty when none was), for the mesh to record (GridMesh::filled).
terrain::Grid raster_grid(const std::string& input, const terrain::GridRequest& req,
                          const std::string& dequantize, const std::string& src_crs,
                          std::optional<double> nodata, const Verbosity& verb,
                          terrain::Grid* source, std::vector<std::uint8_t>& filled);

struct PointOptions {
  std::string interpolation;  // linear, natural, natural-c0
  double max_edge;
  std::string src_crs;
};
// Scattered points: read, projected to UTM if geographic, triangulated and interpolated
// onto the grid; no-data samples (outside the hull, long triangles) are an error unless
// --fill-nodata, as for rasters; `filled` as for rasters.
terrain::Grid points_grid(const std::string& input, const terrain::GridRequest& req,
                          const PointOptions& o, const Verbosity& verb,
                          terrain::SourceSamples* source, std::vector<std::uint8_t>& filled);

// stdout's 'key: value' lines of the mesh written (and of the fit, and of the pyramid
// when `pyramid` is not empty).
void print_mesh_summary(const std::string& output, const terrain::Georef& g,
                        const terrain::GridTopology& topo, terrain::NormalWeighting nw,
                        const terrain::NormalFitReport* fit, const std::string& pyramid,
                        std::uint64_t pyramid_bytes, std::size_t faces, std::size_t outside);

}  // namespace terrain::tools::mesh
