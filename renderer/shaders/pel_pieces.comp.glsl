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
//   3 the opacity written.
// (Included after pel_common.glsl and union_find.glsl.)
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(location = TR_LOC_PIECE_MIN) uniform float u_piece_min;
layout(std430, binding = TR_SSBO_PEL_COMMAND) readonly buffer PelCommand { uint vertex_count; };
struct PelSegment {
  vec4 a, b, n;
};
layout(std430, binding = TR_SSBO_PEL_SEGMENTS) buffer PelSegments { PelSegment segment[]; };
layout(std430, binding = TR_SSBO_PEL_FACE_SEGMENTS) buffer FaceSegments { uint face_segment[]; };
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

void piece_stage(uint k) {
  uint f = floatBitsToUint(segment[k].a.w);
  if (u_piece_stage == 0) {
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
