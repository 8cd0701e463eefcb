// PEL, pieces (anti-aliased lines; renderer::pel_pieces and pel_piece_opacity are the CPU
// reference): segments in faces that share an edge which s crosses join into pieces
// (union-find over segment indices, union_find.glsl), and each segment's opacity
// (PelSegment.b.w) comes from its piece's length L: clamp((L - m/2) / (m/2), 0, 1), m =
// u_piece_min metres. Lengths are summed in fixed point, kUnits to m; a segment adds at
// most m and a root's sum stops growing once it reaches m, so it cannot overflow. An
// indirect dispatch each (written by pel_extract.comp.glsl), looping over the segments.
// Before the stages face_segment is cleared to TR_SEGMENT_NONE, the labels and sizes as
// union_find.glsl says. Stages (u_piece_stage):
//   0 face_segment[f] = k for the segment k of face f;
//   1 each segment joined to the segment of each face across an edge s crosses (each pair
//     once, from the smaller face);
//   2 labels set to roots, each root's length summed;
//   3 the opacity written;
// and, after stage 0, the smoothing of the lines (renderer::smooth_pels), each iteration
//   4 each segment's smoothed ends written to `smoothed`;
//   5 copied back into the segments.
// (Included after pel_common.glsl and union_find.glsl.)
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(location = TR_LOC_PIECE_MIN) uniform float u_piece_min;
layout(std430, binding = TR_SSBO_PEL_COMMAND) readonly buffer PelCommand { uint vertex_count; };
struct PelSegment {
  vec4 a, b;
};
layout(std430, binding = TR_SSBO_PEL_SEGMENTS) buffer PelSegments { PelSegment segment[]; };
layout(std430, binding = TR_SSBO_PEL_FACE_SEGMENTS) buffer FaceSegments { uint face_segment[]; };
layout(std430, binding = TR_SSBO_PEL_SMOOTHED) buffer PelSmoothed { vec4 smoothed[]; };
const float kUnits = 4096.0;

// s as pel_extract.comp.glsl reads it: an exact zero counts as +1e-20.
bool s_positive(uint v) { return (field[v].s == 0.0 ? 1e-20 : field[v].s) > 0.0; }

// The face across edge e = (t[e], t[e + 1]) of face f (face_vertices order), or
// TR_SEGMENT_NONE at the grid's edge: terrain::GridTopology::face_across(f, (e + 2) % 3).
// Face 0 of a cell (NW, SW, SE): west, south, diagonal; face 1 (NW, SE, NE): diagonal,
// east, north.
uint face_across(uint f, int e) {
  uint cell = f / 2u, r = cell / (u_grid.y - 1u), c = cell % (u_grid.y - 1u);
  if (f % 2u == 0u) {
    if (e == 0) return c > 0u ? face_of_cell(r, c - 1u, 1u) : TR_SEGMENT_NONE;
    if (e == 1) return r + 2u < u_grid.x ? face_of_cell(r + 1u, c, 1u) : TR_SEGMENT_NONE;
    return f + 1u;
  }
  if (e == 0) return f - 1u;
  if (e == 1) return c + 2u < u_grid.y ? face_of_cell(r, c + 1u, 0u) : TR_SEGMENT_NONE;
  return r > 0u ? face_of_cell(r - 1u, c, 0u) : TR_SEGMENT_NONE;
}

// The index among face g's crossings (0, 1) of the crossing on edge {u, v}, in
// pel_extract.comp.glsl's order; -1: none.
int crossing_index(uint g, uint u, uint v) {
  uvec3 t = face_vertices(g);
  uint ids[3] = uint[3](t.x, t.y, t.z);
  int n = 0;
  for (int e = 0; e < 3; ++e) {
    uint a = ids[e], b = ids[(e + 1) % 3];
    if (s_positive(a) == s_positive(b)) continue;
    if ((a == u && b == v) || (a == v && b == u)) return n;
    ++n;
  }
  return -1;
}

// One smoothing step of segment k's ends (renderer::smooth_pels): end j, on the j-th edge
// s crosses, moves halfway to the midpoint of the segment's other end and the far end of
// the segment across that edge, where there is one.
void smooth_stage(uint k, uint f) {
  uvec3 t = face_vertices(f);
  uint ids[3] = uint[3](t.x, t.y, t.z);
  vec3 p[2] = vec3[2](segment[k].a.xyz, segment[k].b.xyz);
  vec3 q[2] = p;
  int j = 0;
  for (int e = 0; e < 3 && j < 2; ++e) {
    uint a = ids[e], b = ids[(e + 1) % 3];
    if (s_positive(a) == s_positive(b)) continue;
    uint g = face_across(f, e);
    uint kg = g == TR_SEGMENT_NONE ? TR_SEGMENT_NONE : face_segment[g];
    int i = kg == TR_SEGMENT_NONE ? -1 : crossing_index(g, a, b);
    if (i >= 0) {
      vec3 beyond = i == 0 ? segment[kg].b.xyz : segment[kg].a.xyz;
      vec3 mid = 0.5 * (p[1 - j] + beyond);
      q[j] = p[j] + 0.5 * (mid - p[j]);
    }
    ++j;
  }
  smoothed[2u * k] = vec4(q[0], 0.0);
  smoothed[2u * k + 1u] = vec4(q[1], 0.0);
}

void piece_stage(uint k) {
  uint f = floatBitsToUint(segment[k].a.w);
  if (u_piece_stage == 4) {
    smooth_stage(k, f);
  } else if (u_piece_stage == 5) {
    segment[k].a.xyz = smoothed[2u * k].xyz;
    segment[k].b.xyz = smoothed[2u * k + 1u].xyz;
  } else if (u_piece_stage == 0) {
    face_segment[f] = k;
  } else if (u_piece_stage == 1) {
    uvec3 t = face_vertices(f);
    uint ids[3] = uint[3](t.x, t.y, t.z);
    for (int e = 0; e < 3; ++e) {
      uint g = face_across(f, e);
      if (g == TR_SEGMENT_NONE || g < f || face_segment[g] == TR_SEGMENT_NONE) continue;
      if (s_positive(ids[e]) != s_positive(ids[(e + 1) % 3])) unite(k, face_segment[g]);
    }
  } else if (u_piece_stage == 2) {
    uint r = compress_label(k);
    float share = min(distance(segment[k].a.xyz, segment[k].b.xyz) / u_piece_min, 1.0);
    if (piece_size[r] < uint(kUnits)) atomicAdd(piece_size[r], uint(round(share * kUnits)));
  } else {
    segment[k].b.w = clamp(2.0 * float(piece_size[root_of(k)]) / kUnits - 1.0, 0.0, 1.0);
  }
}

void main() {
  uint stride = gl_NumWorkGroups.x * uint(TR_LOCAL_SIZE), n = vertex_count / 6u;
  for (uint k = gl_GlobalInvocationID.x; k < n; k += stride) piece_stage(k);
}
