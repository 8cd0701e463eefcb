// PEL segments as screen-space quads, lifted along their face normal like the creases.
struct PelSegment {
  vec4 a, b, n;
};
layout(std430, binding = 14) readonly buffer PelSegments { PelSegment segment[]; };
layout(location = 14) uniform float u_pel_width;
void main() {
  const uint end_of[6] = uint[6](0u, 1u, 1u, 0u, 1u, 0u);
  const float side_of[6] = float[6](-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
  uint q = uint(gl_VertexID) / 6u, k = uint(gl_VertexID) % 6u;
  PelSegment sg = segment[q];
  vec3 lift = u_score.w * exaggerate_normal(sg.n.xyz);
  vec4 clip[2];
  clip[0] = u_view_proj * vec4(exaggerate_position(sg.a.xyz) + lift, 1.0);
  clip[1] = u_view_proj * vec4(exaggerate_position(sg.b.xyz) + lift, 1.0);
  if (clip[0].w <= u_misc.x || clip[1].w <= u_misc.x) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec2 half_vp = 0.5 * u_viewport.xy;
  vec2 sa = clip[0].xy / clip[0].w * half_vp, sb = clip[1].xy / clip[1].w * half_vp;
  vec2 d = sb - sa;
  vec2 dir = dot(d, d) > 0.0 ? normalize(d) : vec2(1.0, 0.0);
  vec2 perp = vec2(-dir.y, dir.x);
  uint j = end_of[k];
  float w = 0.5 * u_pel_width;
  vec4 c = clip[j];
  c.xy += (perp * side_of[k] * w + dir * (j == 0u ? -w : w)) / half_vp * c.w;
  gl_Position = c;
}
