// SIL, formulated silhouettes (formulated.glsl), full screen, before the Toward/Away test:
// each formulated pixel written to the mask and listed for the piece rule (the Toward/Away
// test leaves these pixels to this pass, so that none is listed twice).
layout(location = 0) out vec4 o_mask;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_facing, 0);
  if (!formulated(p, size)) discard;
  list_silhouette_pixel(p, size);
  mark_silhouette_tile(p);
  o_mask = vec4(1.0);
}
