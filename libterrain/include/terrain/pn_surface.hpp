#pragma once
// The PN surface of a grid mesh: the patch of every face, the surface point above a given
// (x, y) (docs/algorithms.md 2.4), and sampling the surface on a regular grid.
#include <optional>
#include <utility>

#include "terrain/error.hpp"
#include "terrain/grid.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/pn_triangle.hpp"

namespace terrain {

// The PN patch of face f of `mesh` (corners in the face's counter-clockwise order).
PnPatch face_patch(const GridMesh& mesh, std::size_t f);

struct SurfacePoint {
  std::size_t face = 0;
  double b1 = 0, b2 = 0, b3 = 0;  // barycentrics in that face's patch
  Eigen::Vector3d position;       // local coordinates; x, y equal the request
  Eigen::Vector3d normal;         // unit PN shading normal
};

// The point of the PN surface exactly above local (x, y). Starts in the flat grid
// triangle under (x, y), solves the patch by Newton, and walks to the neighbour across
// the edge opposite the most negative barycentric until the solution lies in its patch
// (at most 8 hops; the PN footprints of neighbouring patches share their boundary
// curves, so they tile the plane). On the mesh boundary, where there is no neighbour,
// the boundary patch is extrapolated (barycentrics down to -0.5), so every point of the
// flat grid's extent has an answer. Returns nullopt outside that, or when Newton fails.
// Tested: x, y of the result equal the request to 1e-6 m on real meshes; planar meshes.
std::optional<SurfacePoint> pn_point_above(const GridMesh& mesh, double x, double y);

struct SampledSurface {
  Grid grid;                  // the samples, with the mesh's CRS; sample (0,0) = mesh vertex (0,0)
  std::size_t fallbacks = 0;  // samples where Newton failed and the flat triangle was used
};

// Samples the PN surface at every point (i * spacing, -j * spacing) (local coordinates)
// of the mesh's extent: z is the PN surface exactly above (pn_point_above), computed with
// patches cached per cell row in monomial form. Parallel over rows; the result does not
// depend on the thread count. Samples in a mesh cell with a vertex that dem2mesh
// --fill-nodata invented (GridMesh::filled) are no-data: drainage is not drawn on
// invented ground. Throws Error for spacing <= 0 or more than 2^32 - 1 samples.
SampledSurface sample_pn_surface(const GridMesh& mesh, double spacing,
                                 const Progress& progress = {});

// The columns and rows sample_pn_surface gives at `spacing` (a tool checks memory with it).
std::pair<std::size_t, std::size_t> sampled_size(const GridMesh& mesh, double spacing);

}  // namespace terrain
