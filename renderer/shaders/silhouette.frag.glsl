// SIL: Toward/Away silhouettes (Mower 2015; docs/algorithms.md 9.2). At pixel p with toward
// depth t and away depth a: silhouette when t < a and some 8-neighbour's toward depth is
// beyond a (a toward surface, an away surface behind it, a neighbour's toward surface
// farther still). One pixel wide. Anti-aliased (u_style.x != 0), two changes so that lines
// read as strokes (renderer/silhouette.hpp has the CPU reference):
// - gaps closed: a is the nearest away depth in p's 3 x 3 window. An away-facing band
//   narrower than a pixel is rasterized only at some pixels along its ridge, and the
//   paper's test draws that ridge as dashes;
// - specks dropped: a silhouette pixel with fewer than 3 silhouette pixels (itself
//   included) in its 5 x 5 window, where the surface only grazes the eye's rays.
// Each silhouette pixel is listed for the piece rule (silhouette_list.glsl).
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(binding = TR_TEX_AWAY_DEPTH) uniform sampler2D u_away;
layout(location = 0) out vec4 o_mask;
bool inside(ivec2 q, ivec2 size) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)); }
bool silhouette(ivec2 p, ivec2 size) {
  float t = far_of(texelFetch(u_toward, p, 0).r);
  float a = far_of(texelFetch(u_away, p, 0).r);
  if (u_style.x != 0.0)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 q = p + ivec2(dx, dy);
        if (inside(q, size)) a = min(a, far_of(texelFetch(u_away, q, 0).r));
      }
  if (!(t < a)) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if ((dx != 0 || dy != 0) && inside(q, size) && far_of(texelFetch(u_toward, q, 0).r) > a) return true;
    }
  return false;
}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_toward, 0);
  bool s = silhouette(p, size);
  // The mask was cleared to 0. (On llvmpipe a group of pixels that all discard skips the
  // rest of the shader; an `if` alone runs both sides, its lanes masked.)
  if (!s) discard;
  if (u_style.x != 0.0) {
    int n = 0;
    for (int dy = -2; dy <= 2 && n < 3; ++dy)
      for (int dx = -2; dx <= 2 && n < 3; ++dx) {
        ivec2 q = p + ivec2(dx, dy);
        if (inside(q, size) && silhouette(q, size)) ++n;
      }
    s = n >= 3;
  }
  if (s) list_silhouette_pixel(p, size), mark_silhouette_tile(p);
  o_mask = vec4(s ? 1.0 : 0.0);
}
