// DM, step 3: each selected segment as a screen-space quad (6 vertices, no geometry
// shader), its ends lifted along the PN normal and extended by half a width (round-ish
// joins); the width grows from u_lines.x at flow 0 to u_lines.y at flow 1, so creases
// thicken towards outlets.
layout(std430, binding = 5) readonly buffer Selected { uint selected[]; };
void main() {
  const uint end_of[6] = uint[6](0u, 1u, 1u, 0u, 1u, 0u);
  const float side_of[6] = float[6](-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
  uint q = uint(gl_VertexID) / 6u, k = uint(gl_VertexID) % 6u;
  uvec2 e = seg[selected[q]];
  vec4 clip[2];
  float flow[2];
  for (int j = 0; j < 2; ++j) {
    uint v = j == 0 ? e.x : e.y;
    vec4 pf = cv[2u * v];
    vec3 p = exaggerate_position(pf.xyz) + u_score.w * exaggerate_normal(cv[2u * v + 1u].xyz);
    clip[j] = u_view_proj * vec4(p, 1.0);
    flow[j] = pf.w;
  }
  if (clip[0].w <= u_misc.x || clip[1].w <= u_misc.x) {  // reaches the near plane: dropped
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec2 half_vp = 0.5 * u_viewport.xy;
  vec2 sa = clip[0].xy / clip[0].w * half_vp, sb = clip[1].xy / clip[1].w * half_vp;
  vec2 d = sb - sa;
  vec2 dir = dot(d, d) > 0.0 ? normalize(d) : vec2(1.0, 0.0);
  vec2 perp = vec2(-dir.y, dir.x);
  uint j = end_of[k];
  float w = mix(u_lines.x, u_lines.y, clamp(flow[j], 0.0, 1.0)) * 0.5;
  vec2 offset_px = perp * side_of[k] * w + dir * (j == 0u ? -w : w);
  vec4 c = clip[j];
  c.xy += offset_px / half_vp * c.w;
  gl_Position = c;
}
