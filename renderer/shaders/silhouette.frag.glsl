// SIL: Toward/Away silhouettes (Mower 2015; docs/algorithms.md 9.2). At pixel p with toward
// depth t and away depth a: silhouette when t < a and some 8-neighbour's toward depth is
// beyond a (a toward surface, an away surface behind it, a neighbour's toward surface
// farther still). One pixel wide. Anti-aliased (u_style.x != 0), two changes so that lines
// read as strokes (renderer/core/silhouette.hpp has the CPU reference):
// - gaps closed: a is the nearest away depth in p's 3 x 3 window. An away-facing band
//   narrower than a pixel is rasterized only at some pixels along its ridge, and the
//   paper's test draws that ridge as dashes;
// - specks dropped: a silhouette pixel with fewer than 3 silhouette pixels (itself
//   included) in its 5 x 5 window, where the surface only grazes the eye's rays.
// Each silhouette pixel is listed for the piece rule (silhouette_list.glsl); a formulated
// silhouette pixel (formulated.glsl) was written and listed by its own pass already.
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(binding = TR_TEX_AWAY_DEPTH) uniform sampler2D u_away;
layout(location = 0) out vec4 o_mask;
bool inside(ivec2 q, ivec2 size) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)); }
// The 2 x 2 depths of s at columns and rows c - 1 and c (one gather, not four fetches).
vec4 gather(sampler2D s, ivec2 c, vec2 size) { return far_of(textureGather(s, vec2(c) / size)); }
bool silhouette(ivec2 p, ivec2 size) {
  // The 3 x 3 window about p as four gathers. Beyond the image's edge a gather clamps to
  // the window's own edge pixels (or p itself), which changes neither the nearest away
  // depth nor the neighbours' test (p's own toward depth is nearer than a).
  vec2 fs = vec2(size);
  float t = far_of(texelFetch(u_toward, p, 0).r);
  float a = far_of(texelFetch(u_away, p, 0).r);
  if (u_style.x != 0.0) {
    vec4 m = min(min(gather(u_away, p, fs), gather(u_away, p + ivec2(1, 0), fs)),
                 min(gather(u_away, p + ivec2(0, 1), fs), gather(u_away, p + ivec2(1, 1), fs)));
    a = min(min(m.x, m.y), min(m.z, m.w));
  }
  if (!(t < a)) return false;
  vec4 f = max(max(gather(u_toward, p, fs), gather(u_toward, p + ivec2(1, 0), fs)),
               max(gather(u_toward, p + ivec2(0, 1), fs), gather(u_toward, p + ivec2(1, 1), fs)));
  return max(max(f.x, f.y), max(f.z, f.w)) > a;
}
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_toward, 0);
  bool s = silhouette(p, size);
  if (s && formulated(p, size)) discard;
  // The mask was cleared to 0, so a pixel that is no silhouette writes nothing (on
  // llvmpipe the speck test's loops then end at once for its lanes).
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
