// DM and PEL: line coverage. Pixel-exact lines (u_style.x == 0) cover their quad with 1
// (the composite removes hidden ones with this layer's depth). Anti-aliased lines write
// the capsule's coverage (capsule_coverage) times the segment's opacity where the
// segment's spine is on the toward surface and not behind it (hidden-line removal here,
// since coverage blends with MAX and keeps no depth).
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
flat in vec4 v_ends;   // the segment's ends, window pixels
flat in vec3 v_shape;  // radius at each end (pixels), opacity
#ifdef TR_CREASE_SAMPLES
flat in uint v_segment;
// Creases: the tiles their fragments cover (LAY composites them over the copied surface
// only there).
layout(binding = TR_IMG_CREASE_TILES, r8) uniform writeonly image2D u_crease_tiles;
void mark_tile() { imageStore(u_crease_tiles, ivec2(gl_FragCoord.xy) / TR_SILHOUETTE_TILE, vec4(1.0)); }
#else
void mark_tile() {}
#endif
layout(location = 0) out vec4 o_colour;
void main() {
  if (u_style.x == 0.0) {
    mark_tile();
    o_colour = vec4(1.0);
    return;
  }
  // Visible where its spine is: the fragment takes the depth test of the segment's point
  // nearest to it (the quad's depth is constant across its width), not of its own pixel,
  // where on ground seen at a grazing angle the surface in front of the line would hide the
  // line's near half and move it off its place by half a width. The spine point lies
  // anywhere in its pixel, whose surface depth at the centre differs from the point's by
  // up to half a pixel's depth gradient, large at a grazing angle; so the line is behind
  // only when behind the farthest surface of the spine pixel and its 8 neighbours (Cole &
  // Finkelstein 2010 test line visibility against a neighbourhood too). Where no surface
  // is about the spine (past a skyline or a mesh edge) nothing is drawn; a line along the
  // mesh's edge, whose spine pixels fall on either side of it, stays whole.
  float along = clamp(segment_param(gl_FragCoord.xy, v_ends.xy, v_ends.zw), 0.0, 1.0);
#ifdef TR_CREASE_SAMPLES
  // Creases: the same test, made once per sample of the segment and smoothed along its
  // stroke (crease_visibility.comp.glsl: short hidden runs drawn, peeks left out); the
  // fragment takes its spine point's sample.
  uint n = samples[v_segment].n;
  if (n == 0u || ((samples[v_segment].shown >> min(n - 1u, uint(along * float(n)))) & 1u) == 0u) discard;
#else
  vec2 point = mix(v_ends.xy, v_ends.zw, along);
  ivec2 last = ivec2(u_viewport.xy) - 1, spine = clamp(ivec2(floor(point)), ivec2(0), last);
  float t = -1.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      float s = far_of(texelFetch(u_toward, clamp(spine + ivec2(dx, dy), ivec2(0), last), 0).r);
      if (s < 1.0) t = max(t, s);
    }
  if (t < 0.0 || far_of(gl_FragCoord.z) > t) discard;
#endif
  float cover = v_shape.z * capsule_coverage(gl_FragCoord.xy, v_ends.xy, v_ends.zw, v_shape.x, v_shape.y);
  if (cover > 0.0) mark_tile();
  o_colour = vec4(cover);
}
