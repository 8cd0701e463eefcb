// SIL: Toward/Away silhouettes (Mower 2015; docs/algorithms.md 9.2). At pixel p with toward
// depth t and away depth a: silhouette when t < a and some 8-neighbour's toward depth is
// beyond a (a toward surface, an away surface behind it, a neighbour's toward surface
// farther still). One pixel wide.
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(binding = TR_TEX_AWAY_DEPTH) uniform sampler2D u_away;
layout(location = 0) out vec4 o_mask;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_toward, 0);
  float t = far_of(texelFetch(u_toward, p, 0).r);
  float a = far_of(texelFetch(u_away, p, 0).r);
  float s = 0.0;
  if (t < a) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 q = p + ivec2(dx, dy);
        if ((dx != 0 || dy != 0) && all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)) &&
            far_of(texelFetch(u_toward, q, 0).r) > a)
          s = 1.0;
      }
  }
  o_mask = vec4(s);
}
