// Adjacency silhouettes, first pass (Mower 2014, Algorithm 1): every tessellated PN
// triangle gets an ID (1, 2, ...; 0 = no surface) and its three vertices (mesh frame,
// exaggerated) go to the triangle list at ID - 1. A triangle beyond the list's capacity
// gets the ID 0xFFFFFFFF ("unknown"), which the second pass ignores.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;
in vec3 f_pos[];
flat out uint g_id;
layout(std430, binding = TR_SSBO_ID_TRIANGLES) buffer IdTriangles {
  uint n_triangles;
  uint pad0, pad1, pad2;
  vec4 tri[];  // 3 per triangle
};
layout(location = TR_LOC_ID_CAPACITY) uniform uint u_capacity;
void main() {
  uint k = atomicAdd(n_triangles, 1u);
  uint id = 0xFFFFFFFFu;
  if (k < u_capacity) {
    for (int v = 0; v < 3; ++v) tri[3u * k + uint(v)] = vec4(f_pos[v], 0.0);
    id = k + 1u;
  }
  for (int v = 0; v < 3; ++v) {
    gl_Position = gl_in[v].gl_Position;
    g_id = id;
    EmitVertex();
  }
  EndPrimitive();
}
