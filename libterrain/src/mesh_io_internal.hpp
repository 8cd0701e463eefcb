#pragma once
// What the terrain PLY's three sources share: mesh_io.cpp (the toolkit's own layout, written
// and read in blocks), mesh_io_openmesh.cpp (OpenMesh's PLY and OBJ writers, its reader for
// other layouts), mesh_pyramid_read.cpp (a mesh read from its pyramid). Not installed.
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>

#include "terrain/error.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/ply_header.hpp"

namespace terrain::detail {

// The Voronoi weights' property names.
inline constexpr const char* kTangent[3] = {"tangent_x", "tangent_y", "tangent_z"};
inline constexpr const char* kCornerArea[3] = {"corner_area_0", "corner_area_1", "corner_area_2"};
// The line that carries the mesh's digest (mesh_digest.hpp), its 16 digits last.
inline constexpr std::string_view kDigestComment = "comment mesh_digest ";

// The header's comment block (format, grid, origin, CRS, provenance, fit; the digest when
// given), each line "comment ...\n".
std::string header_comments(const GridMesh& m, std::optional<std::uint64_t> digest);
// Throws "WHAT: ..." unless every header field that sizes or places something is what a
// projected mesh can be.
void check_mesh_georef(const GridMesh& m, const std::string& what);
// Every vertex finite, every normal of unit length, every vertex on the grid's lattice
// (`level` > 0: a pyramid level's vertices on the lattice of `fine`).
void check_vertices(const GridMesh& m, const std::string& path, int level = 0,
                    const GridMesh* fine = nullptr);
// A terrain PLY's header, checked, and the mesh it describes (no vertices yet), read from
// `in`, opened here on `path`.
GridMesh read_terrain_header(const std::string& path, PlyHeader& header, std::ifstream& in);
// The digest the header states (comment mesh_digest), if any.
std::optional<std::uint64_t> header_digest(const PlyHeader& header);
// The one message for faces that differ from the grid's triangulation.
Error faces_error(const std::string& path, const GridTopology& topo, std::size_t read,
                  std::size_t bad);
// The body of a PLY in another layout than the toolkit's own, through OpenMesh's reader:
// vertices, normals, faces checked against the grid, the optional data
// (mesh_io_openmesh.cpp).
void read_body_openmesh(std::ifstream& in, GridMesh& m, const std::string& path);

}  // namespace terrain::detail
