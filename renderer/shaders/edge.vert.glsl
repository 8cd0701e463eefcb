// Object-space edges, draw: each drawn edge as a screen-space quad (6 vertices) of width
// u_edge_width pixels between its vertices, at the depth of the vertices lifted towards the
// eye like the creases (line_clip). The ends: none (butt), cheap (square caps:
// extended by half a width), or exact (docs/terrain-render.md): where the edge has a join
// vertex, the end is cut on the mitre line of the two edges, computed from the three
// vertices in one canonical order (lower vertex index first) so that both quads get
// bit-identical corners and the rasterizer's
// shared-edge rule leaves neither a gap nor an overlap; turns sharper than the mitre limit
// and ends without a join get square caps.
layout(std430, binding = TR_SSBO_EDGE_LIST) readonly buffer EdgeList { DrawnEdge drawn[]; };
layout(location = TR_LOC_EDGE_CAPS) uniform int u_edge_caps;
layout(location = TR_LOC_EDGE_WIDTH) uniform float u_edge_width;

vec4 clip_of(uint v) {
  return line_clip(exaggerate_position(position(v)), u_score.w);
}
vec2 screen_of(vec4 c) { return c.xy / c.w * (0.5 * u_viewport.xy); }

void main() {
  const uint end_of[6] = uint[6](0u, 1u, 1u, 0u, 1u, 0u);
  const float side_of[6] = float[6](-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
  uint q = uint(gl_VertexID) / 6u, k = uint(gl_VertexID) % 6u;
  DrawnEdge d = drawn[q];
  uint j = end_of[k];
  uint b = j == 0u ? d.v0 : d.v1, a = j == 0u ? d.v1 : d.v0, c = j == 0u ? d.join0 : d.join1;
  vec4 cb = clip_of(b), ca = clip_of(a);
  if (cb.w <= u_misc.x || ca.w <= u_misc.x) {  // reaches the near plane: dropped
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec2 sb = screen_of(cb), sa = screen_of(ca);
  vec2 dir = j == 0u ? sa - sb : sb - sa;  // end 0 towards end 1
  dir = dot(dir, dir) > 0.0 ? normalize(dir) : vec2(1.0, 0.0);
  vec2 perp = vec2(-dir.y, dir.x);
  float half_width = 0.5 * u_edge_width, side = side_of[k];
  vec2 offset = perp * side * half_width;
  if (u_edge_caps != TR_CAPS_NONE) offset += dir * (j == 0u ? -half_width : half_width);
  if (u_edge_caps == TR_CAPS_EXACT && c != TR_EDGE_NONE) {
    vec4 cc = clip_of(c);
    if (cc.w > u_misc.x) {
      vec2 sc = screen_of(cc);
      vec2 p = a < c ? sa : sc, r = a < c ? sc : sa;  // canonical order p -> b -> r
      vec2 d1 = sb - p, d2 = r - sb;
      if (dot(d1, d1) > 0.0 && dot(d2, d2) > 0.0) {
        d1 = normalize(d1);
        d2 = normalize(d2);
        vec2 n1 = vec2(-d1.y, d1.x), m = n1 + vec2(-d2.y, d2.x);
        if (dot(m, m) > 0.0) {
          m = normalize(m);
          float cos_half = dot(m, n1);
          if (cos_half >= TR_MITER_MIN_COS) {
            vec2 mitre = m * (half_width / cos_half);
            offset = dot(m, perp) * side > 0.0 ? mitre : -mitre;
          }
        }
      }
    }
  }
  gl_Position = vec4((sb + offset) / (0.5 * u_viewport.xy) * cb.w, cb.z, cb.w);
}
