// DM and PEL: line coverage. Pixel-exact lines (u_style.x == 0) cover their quad with 1
// (the composite removes hidden ones with this layer's depth). Anti-aliased lines write
// the capsule's coverage (capsule_coverage) times the segment's opacity where the
// fragment is on the toward surface and not behind it (hidden-line removal here, since
// coverage blends with MAX and keeps no depth).
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
flat in vec4 v_ends;   // the segment's ends, window pixels
flat in vec3 v_shape;  // radius at each end (pixels), opacity
layout(location = 0) out vec4 o_colour;
void main() {
  if (u_style.x == 0.0) {
    o_colour = vec4(1.0);
    return;
  }
  // Not behind the surface, and on it: where no surface is, a line lifted off it would
  // float in the sky past a skyline or a mesh edge.
  float t = far_of(texelFetch(u_toward, ivec2(gl_FragCoord.xy), 0).r);
  if (!(t < 1.0) || far_of(gl_FragCoord.z) > t) discard;
  o_colour = vec4(v_shape.z * capsule_coverage(gl_FragCoord.xy, v_ends.xy, v_ends.zw, v_shape.x, v_shape.y));
}
