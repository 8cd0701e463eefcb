// DM, step 3: each selected segment as a screen-space quad (6 vertices, no geometry
// shader), its ends where they lie on the PN surface, at the depth of the ends lifted
// towards the eye (line_clip); the width grows from u_lines.x to u_lines.y
// with the square root of the basin share (as a river's width with its discharge), so
// creases thicken towards outlets. Pixel-exact: the quad's ends are extended by half a
// width. Anti-aliased: the quad holds the segment's capsule and a one-pixel fringe, and the
// segment has its opacity (crease_bridge.comp: fade instead of cut, gaps bridged) and its
// samples' visibility along the stroke (crease_visibility.comp, read by line.frag).
layout(std430, binding = TR_SSBO_CREASE_SELECTED) readonly buffer Selected { uint selected[]; };
layout(std430, binding = TR_SSBO_CREASE_OPACITY) readonly buffer Opacity { float opacity[]; };
flat out vec4 v_ends;
flat out vec3 v_shape;
flat out uint v_segment;
void main() {
  uint q = uint(gl_VertexID) / 6u, k = uint(gl_VertexID) % 6u;
  uvec2 e = seg[selected[q]];
  vec4 clip[2];
  float width[2];
  for (int j = 0; j < 2; ++j) {
    uint v = j == 0 ? e.x : e.y;
    vec4 nf = cv[3u * v + 1u];
    clip[j] = line_clip(exaggerate_position(cv[3u * v].xyz), u_score.w);
    width[j] = mix(u_lines.x, u_lines.y, sqrt(clamp(nf.w, 0.0, 1.0)));
  }
  float fringe = u_style.x != 0.0 ? 2.0 : 0.0;
  gl_Position = segment_quad_vertex(clip[0], clip[1], width[0] + fringe, width[1] + fringe, k);
  v_ends = vec4(window_of(clip[0]), window_of(clip[1]));
  v_shape = vec3(0.5 * width[0], 0.5 * width[1], opacity[selected[q]]);
  v_segment = selected[q];
}
