// PEL segments as screen-space quads, at the depth of their ends lifted towards the eye
// like the creases (line_clip)
// (anti-aliased: with a one-pixel fringe for the capsule's coverage, line.frag.glsl, and
// the segment's opacity from the piece rule, pel_pieces.comp.glsl).
struct PelSegment {
  vec4 a, b;
};
layout(std430, binding = TR_SSBO_PEL_SEGMENTS) readonly buffer PelSegments { PelSegment segment[]; };
layout(location = TR_LOC_PEL_WIDTH) uniform float u_pel_width;
flat out vec4 v_ends;
flat out vec3 v_shape;
void main() {
  uint q = uint(gl_VertexID) / 6u, k = uint(gl_VertexID) % 6u;
  PelSegment sg = segment[q];
  vec4 c0 = line_clip(exaggerate_position(sg.a.xyz), u_score.w);
  vec4 c1 = line_clip(exaggerate_position(sg.b.xyz), u_score.w);
  float w = u_pel_width + (u_style.x != 0.0 ? 2.0 : 0.0);
  gl_Position = segment_quad_vertex(c0, c1, w, w, k);
  v_ends = vec4(window_of(c0), window_of(c1));
  v_shape = vec3(0.5 * u_pel_width, 0.5 * u_pel_width, sg.b.w);
}
