// Object-space edges, compute. Stage 0, per edge: its kinds for this eye (contour,
// boundary, crease, facing; classify_edges() of feature_edges.cpp in the same order of
// operations, on the exaggerated mesh); a drawn edge is appended (6 more vertices in the
// indirect draw command) and, for exact caps, the indirect dispatch of stage 1 grows to
// cover it. Stage 1 (exact caps), per drawn edge only: at each end, the far vertex of the
// other drawn edge when exactly one other drawn edge meets there.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_EDGES) readonly buffer Edges { uvec4 edge[]; };
layout(std430, binding = TR_SSBO_EDGE_KINDS) buffer EdgeKinds { uint kinds[]; };
layout(std430, binding = TR_SSBO_VERTEX_EDGES) readonly buffer VertexEdges { uint vertex_edge[]; };
// The indirect draw command of the drawn edges, then the indirect dispatch of stage 1.
layout(std430, binding = TR_SSBO_EDGE_COMMAND) buffer EdgeCommand {
  uint vertex_count; uint instance_count; uint first; uint base_instance;
  uint groups_x; uint groups_y; uint groups_z;
};
layout(std430, binding = TR_SSBO_EDGE_LIST) buffer EdgeList { DrawnEdge drawn[]; };
layout(location = TR_LOC_EDGE_STAGE) uniform int u_edge_stage;
layout(location = TR_LOC_EDGE_MASK) uniform uint u_edge_mask;
layout(location = TR_LOC_EDGE_COUNT) uniform uint u_edge_count;
layout(location = TR_LOC_EDGE_COS) uniform float u_edge_cos;
layout(location = TR_LOC_EDGE_CAPS) uniform int u_edge_caps;

uint invocation_index() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(TR_LOCAL_SIZE) + gl_GlobalInvocationID.x; }

uint classify(uvec4 e) {
  vec3 p0 = exaggerate_position(position(e.x)), p1 = exaggerate_position(position(e.y));
  vec3 na = normalize(cross(p1 - p0, exaggerate_position(position(e.z)) - p0));
  vec3 towards = to_eye(p0);
  float fa = dot(na, towards);
  if (e.w == TR_EDGE_NONE) return TR_EDGE_BOUNDARY | (fa > 0.0 ? TR_EDGE_FACING : 0u);
  vec3 nb = normalize(cross(p0 - p1, exaggerate_position(position(e.w)) - p1));
  float fb = dot(nb, towards);
  uint k = 0u;
  if (fa * fb < 0.0) k |= TR_EDGE_CONTOUR;
  if (dot(na, nb) < u_edge_cos) k |= TR_EDGE_CREASE;
  if (fa > 0.0 || fb > 0.0) k |= TR_EDGE_FACING;
  return k;
}

// The far vertex of the one drawn edge other than (v, other) at vertex v, or TR_EDGE_NONE.
uint join_vertex(uint v, uint other) {
  uint found = 0u, far_vertex = TR_EDGE_NONE;
  for (uint s = 0u; s < TR_EDGE_SLOTS; ++s) {
    uint j = vertex_edge[v * TR_EDGE_SLOTS + s];
    if (j == TR_EDGE_NONE || !edge_drawn(kinds[j], u_edge_mask)) continue;
    uint f = edge[j].x == v ? edge[j].y : edge[j].x;
    if (f == other) continue;  // the edge itself
    ++found;
    far_vertex = f;
  }
  return found == 1u ? far_vertex : TR_EDGE_NONE;
}

void main() {
  if (u_edge_stage == 0) {
    uint i = invocation_index();
    if (i >= u_edge_count) return;
    uvec4 e = edge[i];
    uint k = classify(e);
    kinds[i] = k;
    if (!edge_drawn(k, u_edge_mask)) return;
    uint slot = atomicAdd(vertex_count, 6u) / 6u;
    drawn[slot] = DrawnEdge(e.x, e.y, TR_EDGE_NONE, TR_EDGE_NONE);
    if (u_edge_caps == TR_CAPS_EXACT) atomicMax(groups_x, min(slot / uint(TR_LOCAL_SIZE) + 1u, 65535u));
  } else {
    uint n = vertex_count / 6u, stride = gl_NumWorkGroups.x * uint(TR_LOCAL_SIZE);
    for (uint k = gl_GlobalInvocationID.x; k < n; k += stride) {
      DrawnEdge d = drawn[k];
      drawn[k].join0 = join_vertex(d.v0, d.v1);
      drawn[k].join1 = join_vertex(d.v1, d.v0);
    }
  }
}
