#pragma once
// Object-space feature edges of a terrain mesh (McGuire & Hughes 2004, "Hardware-
// determined feature edges"; docs/algorithms.md 9.3), GL-free: the edge buffer built once
// from the mesh, the per-view classification and the edges of each vertex (for the joins).
// They are the reference of the GPU edge pass (passes/edge_pass.cpp, shaders edge_*.glsl),
// tested on analytic surfaces (tests/renderer/feature_edges_test.cpp) and compared with
// the GPU exactly (tests/renderer/edge_pass_test.cpp).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/viewpoint.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

// One edge of the mesh with what classifying it needs: its vertices v0 -> v1 in the
// counter-clockwise order of face A, the third vertex v2 of A, and the third vertex v3 of
// face B on the other side (kNoVertex on the mesh boundary).
struct MeshEdge {
  static constexpr std::uint32_t kNoVertex = 0xFFFFFFFFu;
  std::uint32_t v0, v1, v2, v3;
  bool boundary() const { return v3 == kNoVertex; }
};

// Every edge of the grid triangulation (grid_mesh.hpp) once, in the order the faces first
// reach them: (rows - 1) cols + rows (cols - 1) + (rows - 1)(cols - 1) edges.
std::vector<MeshEdge> mesh_edges(const terrain::GridTopology& topo);

// Kinds of a classified edge (bit flags; TR_EDGE_* in gl_contract.h). kFacingEye is not a
// kind: some face of the edge faces the eye.
enum EdgeKind : std::uint8_t {
  kContourEdge = 1,
  kBoundaryEdge = 2,
  kCreaseEdge = 4,
  kFacingEye = 8
};
inline constexpr std::uint8_t kAllEdgeKinds = kContourEdge | kBoundaryEdge | kCreaseEdge;

// An edge is drawn when it has one of the kinds in `mask` and some face of it faces the eye
// (an edge whose faces all turn away is hidden by them).
inline bool edge_drawn(std::uint8_t kinds, std::uint8_t mask) {
  return (kinds & mask) && (kinds & kFacingEye);
}

// Per edge, the kinds it has for an eye at `eye` (same frame as `positions`):
//   contour  (nA . (eye - v0)) (nB . (eye - v0)) < 0: one face towards the eye, one away;
//   crease   nA . nB < cos(crease_angle): the normals of the two faces differ by more
//            than crease_angle degrees (0 = every bend, 180 = none);
//   boundary the edge has one face.
// and kFacingEye when nA . (eye - v0) > 0 or nB . (eye - v0) > 0.
// nA = (v1 - v0) x (v2 - v0), nB = (v0 - v1) x (v3 - v1), both normalized. Orthographic
// (the top view), eye - v0 is the way back along the line of sight (Viewpoint::to_eye).
std::vector<std::uint8_t> classify_edges(std::span<const MeshEdge> edges,
                                         std::span<const Eigen::Vector3f> positions,
                                         const Viewpoint& viewer, double crease_angle_deg);

// The edges of every vertex: kVertexEdgeSlots indices per vertex, unused slots
// MeshEdge::kNoVertex. A vertex of the grid triangulation has at most 6 edges.
inline constexpr std::size_t kVertexEdgeSlots = 6;
std::vector<std::uint32_t> vertex_edges(std::span<const MeshEdge> edges, std::size_t n_vertices);

}  // namespace renderer
