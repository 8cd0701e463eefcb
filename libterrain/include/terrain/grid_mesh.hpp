#pragma once
// The terrain mesh: a regular grid of vertices with implicit triangles (no per-face
// storage), vertex positions relative to a local origin, and unit vertex normals.
//
// Triangulation convention (one place; locked by tests/grid_mesh_test.cpp):
//   * vertex (r, c) has index r * cols + c (row 0 north, as in grid.hpp);
//   * cell (r, c), r < rows-1, c < cols-1, has corners NW=(r,c), NE=(r,c+1),
//     SW=(r+1,c), SE=(r+1,c+1) and is split along its NW-SE diagonal into
//         face 2*cell + 0 = (NW, SW, SE)      face 2*cell + 1 = (NW, SE, NE)
//     with cell = r * (cols-1) + c; both are counter-clockwise seen from above, so
//     face normals point up (+z);
//   * local coordinates: vertex (r, c) of a flat grid sits at (c*dx, -r*dy, z); the
//     world (CRS) position is origin + local. The origin is the grid's sample (0,0),
//     with origin z = 0, so float coordinates stay exact to ~1 mm over 100 km.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "terrain/grid.hpp"

namespace terrain {

struct GridTopology {
  std::size_t rows = 0, cols = 0;

  std::size_t n_vertices() const { return rows * cols; }
  std::size_t n_cells() const { return (rows - 1) * (cols - 1); }
  std::size_t n_faces() const { return 2 * n_cells(); }
  // Vertex indices of face f in counter-clockwise order (convention above).
  std::array<std::uint32_t, 3> face(std::size_t f) const {
    const std::size_t cell = f / 2, r = cell / (cols - 1), c = cell % (cols - 1);
    const auto nw = std::uint32_t(r * cols + c), ne = nw + 1;
    const auto sw = std::uint32_t(nw + cols), se = sw + 1;
    return (f % 2 == 0) ? std::array<std::uint32_t, 3>{nw, sw, se}
                        : std::array<std::uint32_t, 3>{nw, se, ne};
  }
  std::size_t face_of_cell(std::size_t r, std::size_t c, int k) const {
    return 2 * (r * (cols - 1) + c) + std::size_t(k);
  }
  // The face across the edge opposite corner k of face f, or kNoFace on the mesh boundary.
  // Face 0 = (NW, SW, SE): opposite NW is the south edge (cell below, face 1), opposite SW
  // the diagonal (face 1), opposite SE the west edge (cell to the west, face 1). Face 1 =
  // (NW, SE, NE): opposite NW is the east edge (cell to the east, face 0), opposite SE the
  // north edge (cell above, face 0), opposite NE the diagonal (face 0).
  static constexpr std::size_t kNoFace = std::size_t(-1);
  std::size_t face_across(std::size_t f, int k) const {
    const std::size_t cell = f / 2, r = cell / (cols - 1), c = cell % (cols - 1);
    if (f % 2 == 0) {
      if (k == 0) return r + 2 < rows ? face_of_cell(r + 1, c, 1) : kNoFace;
      if (k == 1) return f + 1;
      return c > 0 ? face_of_cell(r, c - 1, 1) : kNoFace;
    }
    if (k == 0) return c + 2 < cols ? face_of_cell(r, c + 1, 0) : kNoFace;
    if (k == 1) return r > 0 ? face_of_cell(r - 1, c, 0) : kNoFace;
    return f - 1;
  }
  // The faces around vertex v (at most 6) and v's corner (0..2) in each; returns the count.
  // Cell (r-1,c-1): SE = corner 2 of face 0, corner 1 of face 1; cell (r-1,c): SW = corner
  // 1 of face 0; cell (r,c-1): NE = corner 2 of face 1; cell (r,c): NW = corner 0 of both.
  int vertex_faces(std::size_t v, std::array<std::uint32_t, 6>& faces,
                   std::array<std::uint8_t, 6>& corners) const {
    const std::size_t r = v / cols, c = v % cols;
    int n = 0;
    auto add = [&](std::size_t rr, std::size_t cc, int k, int corner) {
      faces[std::size_t(n)] = std::uint32_t(face_of_cell(rr, cc, k));
      corners[std::size_t(n++)] = std::uint8_t(corner);
    };
    if (r > 0 && c > 0) add(r - 1, c - 1, 0, 2), add(r - 1, c - 1, 1, 1);
    if (r > 0 && c + 1 < cols) add(r - 1, c, 0, 1);
    if (r + 1 < rows && c > 0) add(r, c - 1, 1, 2);
    if (r + 1 < rows && c + 1 < cols) add(r, c, 0, 0), add(r, c, 1, 0);
    return n;
  }
};

// Where the mesh sits in the world and which grid it came from.
struct MeshGeoref {
  std::string crs_wkt;  // empty: unknown CRS (metres)
  int epsg = 0;
  double origin_x = 0.0, origin_y = 0.0, origin_z = 0.0;  // world = origin + local
  double dx = 1.0, dy = 1.0;                              // grid spacing, metres
};

// Whether a grid of `topo` placed by `geo` is what a projected terrain mesh can be:
// spacings from 1 mm to 1000 km, an extent and an origin within 1e8 m (UTM coordinates
// are below 1e7), all finite. What the mesh's PLY header and its pyramid's are checked by.
bool georef_in_range(const GridTopology& topo, const MeshGeoref& geo);

// Precomputed inputs of photic extremum lines (voronoi.hpp), stored in the mesh file.
struct VoronoiWeights {
  BigVector<Eigen::Vector3f>
      corner_areas;                     // #F: mixed Voronoi area of each corner, in face(f) order
  BigVector<float> vertex_areas;        // #V: sum of the vertex's corner areas ("voronoi_area")
  BigVector<Eigen::Vector3f> tangents;  // #V: unit t1 perpendicular to the normal; t2 = n x t1
  bool empty() const { return vertex_areas.size() == 0; }
};

// Set when the normals were fitted to a source DEM (fit_normals.hpp): the PN surface's
// error against the source samples before and after, metres.
struct NormalFitInfo {
  bool fitted = false;
  double rmse_before = 0, max_before = 0, rmse_after = 0, max_after = 0;
  std::size_t samples = 0;
};

struct GridMesh {
  GridTopology topo;
  MeshGeoref geo;
  BigVector<Eigen::Vector3f> positions;  // #V, local coordinates
  BigVector<Eigen::Vector3f> normals;    // #V, unit vertex normals
  std::string provenance;                // tool, version, command line (free text)
  VoronoiWeights voronoi;                // empty unless computed (voronoi_weights) or read
  BigVector<float> normal_change;        // #V degrees, written by denoise-normals; else empty
  // #V, where each vertex's height comes from (VertexSource) when the source had no-data
  // under the mesh, else empty. Over the cells an Invented or Outside vertex touches,
  // sample_pn_surface gives no-data: no drainage line is drawn on invented ground.
  BigVector<std::uint8_t> filled;
  NormalFitInfo normal_fit;  // fitted normals (not after denoise-normals)

  std::size_t n_vertices() const { return positions.size(); }
  std::size_t n_faces() const { return topo.n_faces(); }  // the grid's, holes included
  // Whether face f is part of the surface: none of its corners lies outside the data.
  bool face_kept(std::size_t f) const;
  // The faces that are (face_kept), in face order; every face when the mesh has no hole.
  std::vector<std::uint32_t> kept_faces() const;
  bool has_holes() const;  // a vertex lies outside the data
  // The data's outline: each edge between a kept face and one outside the data, as its two
  // vertices (none when the mesh has no hole).
  std::vector<std::array<std::uint32_t, 2>> outline_edges() const;
};

// Where a vertex's height comes from (GridMesh::filled). A face with an Outside corner is
// no face: the mesh's outline follows the data (docs/dem2mesh.md, "No-data").
enum VertexSource : std::uint8_t {
  kFromData = 0,
  kInvented = 1,    // dem2mesh --fill-nodata: drawn, no drainage over its cells
  kOutside = 2,     // no data around: no face touches it, no drainage over its cells
  kVoidFilled = 3,  // a small void inside the data, filled: drawn, and flow runs through it
};
// Whether the drainage is sampled over the cells a vertex of this source touches.
inline bool drained(std::uint8_t source) { return source == kFromData || source == kVoidFilled; }

enum class NormalWeighting { Uniform, Angle, Area };

// Vertex normals on grid topology (docs/algorithms.md 3): the normalized sum of the incident
// unit face normals (Uniform: the Creases paper's rule), weighted by the corner angle
// (Angle, Thurmer & Wuthrich 1998) or by face area (Area, exact for quadratics on a
// regular grid). positions: #V local coordinates. Degenerate faces add nothing; a vertex
// with no usable face gets (0, 0, 1). Tested on planes and a worked example.
BigVector<Eigen::Vector3f> vertex_normals(const BigVector<Eigen::Vector3f>& positions,
                                          const GridTopology& topo, NormalWeighting weighting);

// Unit normal of the triangle (p0, p1, p2), counter-clockwise; zero when degenerate.
Eigen::Vector3d face_normal(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& p2);

// Parses "uniform" (alias "paper"), "angle", "area"; throws Error otherwise.
NormalWeighting parse_normal_weighting(const std::string& name);
const char* to_string(NormalWeighting w);

// Builds the mesh of a grid without no-data (Error otherwise): one vertex per sample,
// two triangles per cell, vertex normals by `weighting`. The CRS and spacing come from
// grid.geo.
GridMesh make_grid_mesh(const Grid& grid, NormalWeighting weighting);
// The mesh's grid and georeferencing as make_grid_mesh sets them, without vertices: of a
// grid, or of `rows` x `cols` samples georeferenced by `geo` (dem2mesh's bands).
GridMesh grid_mesh_frame(const Grid& grid);
GridMesh grid_mesh_frame(const Georef& geo, std::size_t rows, std::size_t cols);

// make_grid_mesh's positions and normals a band of rows at a time, for a writer that
// streams them (write_grid_mesh_ply): the same floats, without the whole mesh in memory.
// Throws Error where make_grid_mesh does. One object per thread.
class GridMeshRows {
 public:
  GridMeshRows(const Grid& grid, NormalWeighting weighting);
  // Vertex rows [r0, r1): (r1 - r0) * cols positions and normals, row-major, held here
  // until the next call.
  std::pair<const Eigen::Vector3f*, const Eigen::Vector3f*> rows(std::size_t r0, std::size_t r1);
  // The same, copied to `positions` and `normals`.
  void rows(std::size_t r0, std::size_t r1, Eigen::Vector3f* positions, Eigen::Vector3f* normals);

 private:
  const Grid& grid_;
  NormalWeighting weighting_;
  std::vector<Eigen::Vector3f> window_, window_normals_;  // the band and a row each side
};
// The vertex of grid row r, column c at height z, as make_grid_mesh places it (local frame:
// x east, y north of the first sample); dem2mesh's bands place theirs with it too.
inline Eigen::Vector3f grid_vertex(std::size_t r, std::size_t c, double dx, double dy, float z) {
  return {float(double(c) * dx), float(-double(r) * dy), z};
}

// The mesh's vertex elevations back on its grid (rows x cols) with its georeferencing.
Grid mesh_to_grid(const GridMesh& mesh);

}  // namespace terrain
