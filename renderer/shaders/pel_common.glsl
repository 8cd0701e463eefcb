// PEL compute passes: the grid topology (grid_mesh.hpp), the mesh data and the per-vertex
// fields, and the Voronoi-weighted vertex gradient of docs/algorithms.md 5.1-5.3 (CPU
// reference: renderer/core/src/lines/pel.cpp, same order of operations).
layout(std430, binding = TR_SSBO_MESH_POSITIONS) readonly buffer MeshPositions { float pos[]; };
layout(std430, binding = TR_SSBO_MESH_NORMALS) readonly buffer MeshNormals { float nrm[]; };
layout(std430, binding = TR_SSBO_CORNER_AREAS) readonly buffer CornerAreas { float corner_area[]; };
layout(std430, binding = TR_SSBO_VERTEX_AREAS) readonly buffer VertexAreas { float vertex_area[]; };
layout(std430, binding = TR_SSBO_TANGENTS) readonly buffer Tangents { float tangent[]; };
struct PelField {
  vec2 g;   // gradient of f in the vertex frame (t1, t2)
  float f, m, s, c;
};
layout(std430, binding = TR_SSBO_PEL_FIELDS) buffer Fields { PelField field[]; };
layout(std430, binding = TR_SSBO_PEL_MAX_M) buffer MaxM { uint max_m_bits; };

layout(location = TR_LOC_PEL_GRID) uniform uvec2 u_grid;  // rows, cols

vec3 position(uint v) { return vec3(pos[3u * v], pos[3u * v + 1u], pos[3u * v + 2u]); }
vec3 normal_at(uint v) { return vec3(nrm[3u * v], nrm[3u * v + 1u], nrm[3u * v + 2u]); }

// All PEL compute shaders use local_size_x = TR_LOCAL_SIZE.
uint invocation_index() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(TR_LOCAL_SIZE) + gl_GlobalInvocationID.x; }

// Vertices of face f, counter-clockwise: face 2*cell = (NW, SW, SE), 2*cell+1 = (NW, SE, NE).
uvec3 face_vertices(uint f) {
  uint cell = f / 2u, r = cell / (u_grid.y - 1u), c = cell % (u_grid.y - 1u);
  uint nw = r * u_grid.y + c, ne = nw + 1u, sw = nw + u_grid.y, se = sw + 1u;
  return (f % 2u == 0u) ? uvec3(nw, sw, se) : uvec3(nw, se, ne);
}
uint face_of_cell(uint r, uint c, uint k) { return 2u * (r * (u_grid.y - 1u) + c) + k; }

float field_value(uint v, int which) {
  return which == 0 ? field[v].f : (which == 1 ? field[v].m : field[v].s);
}

// Gradient of the linear interpolant of field `which` on face f; nf gets its unit normal.
vec3 face_gradient(uint f, int which, out vec3 nf) {
  uvec3 t = face_vertices(f);
  vec3 x0 = position(t.x), x1 = position(t.y), x2 = position(t.z);
  vec3 cr = cross(x1 - x0, x2 - x0);
  float dbl_area = length(cr);
  if (!(dbl_area > 0.0)) {
    nf = vec3(0.0, 0.0, 1.0);
    return vec3(0.0);
  }
  nf = cr / dbl_area;
  vec3 e0 = x2 - x1, e1 = x0 - x2, e2 = x1 - x0;
  return (field_value(t.x, which) * cross(nf, e0) + field_value(t.y, which) * cross(nf, e1) +
          field_value(t.z, which) * cross(nf, e2)) / dbl_area;
}

// Vertex gradient of field `which` in the frame (t1, t2 = n x t1).
vec2 vertex_gradient(uint v, int which) {
  uint r = v / u_grid.y, c = v % u_grid.y;
  vec3 N = normal_at(v), t1 = vec3(tangent[3u * v], tangent[3u * v + 1u], tangent[3u * v + 2u]), t2 = cross(N, t1);
  float area = vertex_area[v];
  if (!(area > 0.0)) return vec2(0.0);
  uint faces[6];
  uint corners[6];
  int n = 0;
  if (r > 0u && c > 0u) {
    faces[n] = face_of_cell(r - 1u, c - 1u, 0u); corners[n++] = 2u;
    faces[n] = face_of_cell(r - 1u, c - 1u, 1u); corners[n++] = 1u;
  }
  if (r > 0u && c + 1u < u_grid.y) { faces[n] = face_of_cell(r - 1u, c, 0u); corners[n++] = 1u; }
  if (r + 1u < u_grid.x && c > 0u) { faces[n] = face_of_cell(r, c - 1u, 1u); corners[n++] = 2u; }
  if (r + 1u < u_grid.x && c + 1u < u_grid.y) {
    faces[n] = face_of_cell(r, c, 0u); corners[n++] = 0u;
    faces[n] = face_of_cell(r, c, 1u); corners[n++] = 0u;
  }
  vec3 sum = vec3(0.0);
  for (int i = 0; i < n; ++i) {
    vec3 nf;
    vec3 g = face_gradient(faces[i], which, nf);
    float ndot = dot(nf, N);
    if (ndot <= -1.0) {
      g = -g;
    } else {
      vec3 perp_old = N - ndot * nf, dperp = (nf + N) / (1.0 + ndot);
      g -= dperp * dot(g, perp_old);
    }
    sum += (corner_area[3u * faces[i] + corners[i]] / area) * g;
  }
  return vec2(dot(sum, t1), dot(sum, t2));
}
