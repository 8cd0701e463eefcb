// Object-space edges, compute. Stage 0, per edge: its kinds for this eye (contour,
// boundary, crease, facing; classify_edges() of feature_edges.cpp in the same order of
// operations, on the exaggerated mesh), and with cheap caps or none the drawn edges are
// appended right away. Stage 1 (exact caps), per drawn edge: at each end, the far vertex of
// the other drawn edge when exactly one other drawn edge meets there; then appended. Each
// append adds 6 vertices to the indirect draw command.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_EDGES) readonly buffer Edges { uvec4 edge[]; };
layout(std430, binding = TR_SSBO_EDGE_KINDS) buffer EdgeKinds { uint kinds[]; };
layout(std430, binding = TR_SSBO_VERTEX_EDGES) readonly buffer VertexEdges { uint vertex_edge[]; };
layout(std430, binding = TR_SSBO_EDGE_COMMAND) buffer EdgeCommand { uint vertex_count; uint instance_count; uint first; uint base_instance; };
layout(std430, binding = TR_SSBO_EDGE_LIST) writeonly buffer EdgeList { DrawnEdge drawn[]; };
layout(location = TR_LOC_EDGE_STAGE) uniform int u_edge_stage;
layout(location = TR_LOC_EDGE_MASK) uniform uint u_edge_mask;
layout(location = TR_LOC_EDGE_COUNT) uniform uint u_edge_count;
layout(location = TR_LOC_EDGE_COS) uniform float u_edge_cos;
layout(location = TR_LOC_EDGE_CAPS) uniform int u_edge_caps;

uint invocation_index() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(TR_LOCAL_SIZE) + gl_GlobalInvocationID.x; }

uint classify(uvec4 e) {
  vec3 p0 = exaggerate_position(position(e.x)), p1 = exaggerate_position(position(e.y));
  vec3 na = normalize(cross(p1 - p0, exaggerate_position(position(e.z)) - p0));
  vec3 to_eye = u_eye.xyz - p0;
  float fa = dot(na, to_eye);
  if (e.w == TR_EDGE_NONE) return TR_EDGE_BOUNDARY | (fa > 0.0 ? TR_EDGE_FACING : 0u);
  vec3 nb = normalize(cross(p0 - p1, exaggerate_position(position(e.w)) - p1));
  float fb = dot(nb, to_eye);
  uint k = 0u;
  if (fa * fb < 0.0) k |= TR_EDGE_CONTOUR;
  if (dot(na, nb) < u_edge_cos) k |= TR_EDGE_CREASE;
  if (fa > 0.0 || fb > 0.0) k |= TR_EDGE_FACING;
  return k;
}

// The far vertex of the one other drawn edge at vertex v, or TR_EDGE_NONE.
uint join_vertex(uint v, uint self) {
  uint found = 0u, far_vertex = TR_EDGE_NONE;
  for (uint s = 0u; s < TR_EDGE_SLOTS; ++s) {
    uint j = vertex_edge[v * TR_EDGE_SLOTS + s];
    if (j == TR_EDGE_NONE || j == self || !edge_drawn(kinds[j], u_edge_mask)) continue;
    ++found;
    far_vertex = edge[j].x == v ? edge[j].y : edge[j].x;
  }
  return found == 1u ? far_vertex : TR_EDGE_NONE;
}

void append(uvec4 e, uint join0, uint join1) {
  uint k = atomicAdd(vertex_count, 6u) / 6u;
  drawn[k] = DrawnEdge(e.x, e.y, join0, join1);
}

void main() {
  uint i = invocation_index();
  if (i >= u_edge_count) return;
  uvec4 e = edge[i];
  if (u_edge_stage == 0) {
    uint k = classify(e);
    kinds[i] = k;
    if (u_edge_caps != TR_CAPS_EXACT && edge_drawn(k, u_edge_mask)) append(e, TR_EDGE_NONE, TR_EDGE_NONE);
  } else if (edge_drawn(kinds[i], u_edge_mask)) {
    append(e, join_vertex(e.x, i), join_vertex(e.y, i));
  }
}
