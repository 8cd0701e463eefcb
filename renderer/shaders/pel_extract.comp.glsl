// PEL segments: per face, the zero crossings of s on its edges; a face with two gives a
// segment, kept when c < 0 and m / max(m) > tau at both ends. Appended with the indirect
// draw command (6 vertices per segment). Each record: two vec4 (point xyz, then the face
// index as float bits or the segment's opacity: 1 here, pel_pieces.comp.glsl may lower
// it).
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(location = TR_LOC_PEL_TAU) uniform float u_tau;
// The draw command, then the indirect dispatch of the piece rule (pel_pieces.comp.glsl):
// one work group per TR_LOCAL_SIZE segments, at most 65535 (its stages loop).
layout(std430, binding = TR_SSBO_PEL_COMMAND) buffer PelCommand {
  uint vertex_count, instance_count, first, base_instance;
  uint groups_x, groups_y, groups_z;
};
struct PelSegment {
  vec4 a, b;
};
layout(std430, binding = TR_SSBO_PEL_SEGMENTS) writeonly buffer PelSegments { PelSegment segment[]; };
void main() {
  uint f = invocation_index();
  if (f >= 2u * (u_grid.x - 1u) * (u_grid.y - 1u)) return;
  uvec3 t = face_vertices(f);
  uint ids[3] = uint[3](t.x, t.y, t.z);
  float inv_max = uintBitsToFloat(max_m_bits) > 0.0 ? 1.0 / uintBitsToFloat(max_m_bits) : 0.0;
  vec3 pts[2];
  int n = 0;
  bool keep = true;
  for (int e = 0; e < 3; ++e) {
    uint a = ids[e], b = ids[(e + 1) % 3];
    float sa = field[a].s == 0.0 ? 1e-20 : field[a].s, sb = field[b].s == 0.0 ? 1e-20 : field[b].s;
    if ((sa > 0.0) == (sb > 0.0)) continue;
    float w = sa / (sa - sb);
    if (n < 2) pts[n] = position(a) + w * (position(b) - position(a));
    ++n;
    float c = field[a].c + w * (field[b].c - field[a].c);
    float mn = (field[a].m + w * (field[b].m - field[a].m)) * inv_max;
    keep = keep && c < 0.0 && mn > u_tau;
  }
  if (n != 2 || !keep) return;
  uint k = atomicAdd(vertex_count, 6u) / 6u;
  atomicMax(groups_x, min(k / uint(TR_LOCAL_SIZE) + 1u, 65535u));
  segment[k].a = vec4(pts[0], uintBitsToFloat(f));
  segment[k].b = vec4(pts[1], 1.0);
}
