// Object-space feature edges (renderer/core/feature_edges.hpp is the CPU reference): the mesh,
// the edge buffer built once (v0, v1 in the order of face A, v2 the third vertex of A, v3
// that of face B or TR_EDGE_NONE), the kinds of the last classification, the edges of each
// vertex, and the list of drawn edges with the indirect draw command.
layout(std430, binding = TR_SSBO_MESH_POSITIONS) readonly buffer MeshPositions { float pos[]; };
layout(std430, binding = TR_SSBO_MESH_NORMALS) readonly buffer MeshNormals { float nrm[]; };

vec3 position(uint v) { return vec3(pos[3u * v], pos[3u * v + 1u], pos[3u * v + 2u]); }
vec3 normal_at(uint v) { return vec3(nrm[3u * v], nrm[3u * v + 1u], nrm[3u * v + 2u]); }

// A drawn edge: its vertices and, for the exact joins, the far vertex of the one other
// drawn edge at each end (TR_EDGE_NONE: a line end, a junction, or cheap caps).
struct DrawnEdge {
  uint v0, v1, join0, join1;
};

// Drawn: one of the requested kinds, and some face of the edge faces the eye.
bool edge_drawn(uint kinds, uint mask) { return (kinds & mask) != 0u && (kinds & TR_EDGE_FACING) != 0u; }
