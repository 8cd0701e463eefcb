#pragma once
// The mesh file: binary little-endian PLY that MeshLab and Blender open.
//
//   element vertex: float x y z (local coordinates), float nx ny nz (unit normals)
//   element face:   list uchar int vertex_indices (the grid_mesh.hpp triangulation)
//   header comments, ignored by other readers, carry what later steps need:
//     comment terrain-mesh 1                      format version of these comments
//     comment grid <rows> <cols> <dx> <dy>        grid layout and spacing (metres)
//     comment origin <x> <y> <z>                  world = origin + local (CRS units)
//     comment crs_epsg <code>                     0 when unknown
//     comment crs_wkt <text>                      WKT2, split over lines of <= 200 chars
//     comment mesh_digest <16 hex digits>         XXH3-64 of the vertices (mesh_digest.hpp)
//     comment normals_fitted <rmse_before> <max_before> <rmse_after> <max_after> <samples>
//                                                 only for fitted normals (fit_normals.hpp)
//     comment provenance <text>                   tool, version and command line
// The PLY body is written and read by OpenMesh's PLY codec through an exporter and an
// importer over our arrays (no half-edge mesh is built); the comment lines are added to
// and read from the header text around it. Documented in docs/formats.md.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "terrain/grid_mesh.hpp"
#include "terrain/mesh_pyramid.hpp"

namespace terrain {

// Writes atomically (temp file + rename). Throws Error on failure. Binary little-endian
// PLY written from the mesh's arrays in blocks (a regular grid needs no half-edge
// structure): the header, comments, properties and bytes of OpenMesh's PLY writer.
void write_mesh_ply(const GridMesh& mesh, const std::string& path);
// The same bytes as write_mesh_ply(make_grid_mesh(grid, weighting) with frame's comments
// and optional `filled`), the vertices made a band at a time while earlier ones are
// written: no whole-mesh arrays. frame: grid_mesh_frame(grid) with provenance (and filled).
void write_grid_mesh_ply(const GridMesh& frame, const Grid& grid, NormalWeighting weighting,
                         const std::string& path);
// The same file through OpenMesh's PLY writer (slow and general): the fast writer's test
// reference.
void write_mesh_ply_openmesh(const GridMesh& mesh, const std::string& path);

// Reads a mesh written by write_mesh_ply. Throws Error: missing or non-PLY file, no
// terrain-mesh comments, no vertex normals, vertex count or faces that do not match the
// grid layout, truncated data.
GridMesh read_mesh_ply(const std::string& path);

// The mesh of `ply_path` read from the mesh pyramid beside it (pyramid_path_of; dem2mesh
// --pyramid), which holds the same vertices in zstd tiles read in parallel, with its levels
// of detail (the blocks and their errors): of the PLY only the header is read (the grid,
// the georeference, the provenance). Used only when the pyramid is the PLY's: both state the
// same digest of the mesh's vertices (mesh_digest.hpp, written by dem2mesh into both), of
// the same grid and georeference, and the PLY has no vertex or face data the pyramid does
// not keep (Voronoi weights, normal change, filled flags). Otherwise nullopt, and `why`
// says why (empty when there is no pyramid at all). Throws Error on a bad PLY header or a
// damaged pyramid.
//
// `part`, when given, picks the pyramid level read as the mesh from the open pyramid (its
// grid sizes; 0: the mesh itself): level l's grid, every 2^l-th row and column and the
// last ones, as a grid mesh of its own whose geo.dx and dy are the mesh's extent over its
// cells (so its extent is the mesh's; its last row and column are the closer ones). The
// levels of detail stay the mesh's, with MeshLevels::base = l.
//
// `part` may also name a window of the mesh's blocks (rows br0 .. br1 - 1, columns bc0 ..
// bc1 - 1 of MeshLevels' blocks; clamped to them): then only the tiles of level l under it
// are read, and the mesh is that window, a grid mesh of its own: its origin at its first
// vertex (positions moved by as much; exactly on a lattice of dyadic spacing), its spacing
// the whole level's, and levels.window says where it lies (its blocks and topology are the
// window's). A window of every block reads the whole level.
struct PyramidPart {
  int level = 0;
  std::size_t br0 = 0, bc0 = 0, br1 = std::size_t(-1),
              bc1 = std::size_t(-1);    // blocks; default: all
  PyramidPart(int l = 0) : level(l) {}  // NOLINT: a level alone reads the whole of it
  PyramidPart(int l, std::size_t r0, std::size_t c0, std::size_t r1, std::size_t c1)
      : level(l), br0(r0), bc0(c0), br1(r1), bc1(c1) {}
};
struct PyramidMesh {
  GridMesh mesh;
  MeshLevels levels;
  std::uint64_t digest = 0;  // the mesh's and the pyramid's (mesh_digest.hpp)
};
std::optional<PyramidMesh> read_mesh_via_pyramid(
    const std::string& ply_path, std::string& why,
    const std::function<PyramidPart(const MeshPyramid&)>& part = {});
// A terrain mesh as the tools read it: from its pyramid when that is current
// (read_mesh_via_pyramid), else from the PLY (read_mesh_ply). `source` says which, and why
// not the pyramid: "'MESH.tpyr' (its pyramid)", "the PLY", "the PLY: <why>". `levels`,
// when given, receives the pyramid's levels of detail (left empty from a PLY). `warning`,
// when given, receives why a pyramid beside the PLY was not used (empty when none is there
// or it was used): the tools print it.
GridMesh read_terrain_mesh(const std::string& ply_path, std::string* source = nullptr,
                           MeshLevels* levels = nullptr, std::string* warning = nullptr);

// A terrain PLY written row by row, for meshes larger than memory (dem2mesh --tile-size):
// the header of `header` (its grid, georeference, provenance; its vertex arrays are not
// read), the vertex rows as add_rows gives them, then the grid's faces (finish): the bytes
// write_mesh_ply writes for the whole mesh without optional data. Writes `path` in place
// (a path staged by an OutputSet: atomic through it).
class PlyRowWriter {
 public:
  PlyRowWriter(const GridMesh& header, const std::string& path);
  ~PlyRowWriter();
  PlyRowWriter(const PlyRowWriter&) = delete;
  PlyRowWriter& operator=(const PlyRowWriter&) = delete;
  // The next n vertex rows: positions and normals, header.topo.cols each.
  void add_rows(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals, std::size_t n);
  void finish();  // after the last row: the faces, and the file closed

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes the mesh as Wavefront OBJ (vertices, vertex normals, faces) through OpenMesh's
// OBJ writer, in local coordinates; leading '#' comment lines give the origin, CRS and
// provenance. Atomic.
void write_mesh_obj(const GridMesh& mesh, const std::string& path);

// True when `path` starts with the PLY magic line.
bool is_ply_file(const std::string& path);

}  // namespace terrain
