// SIL, formulated silhouettes (Whelan & Visvalingam 2003; renderer::formulated_silhouettes
// is the CPU reference): on the visible surface, the lines that would be silhouettes seen
// from a lowered eye. g(q), formulated_facing.frag.glsl's smoothed facing of the drawn
// surface towards the lowered line of sight (> 0: facing the lowered eye; 2 off the
// terrain or the image). Pixel p is on when g(p) > 0, g(p + step) <= 0, the least g over
// p + step .. p + TR_FORMULATED_REACH step is <= -strength (u_formulated.w), and p - step
// .. p - TR_FORMULATED_REACH step are terrain. g is drawn only near the tiles that
// formulated_tiles.comp.glsl marks: p is looked at only within TR_FORMULATED_REACH + 1
// pixels of one (no formulated pixel lies farther), where every g it reads was drawn.
layout(binding = TR_TEX_FORMULATED_FACING) uniform sampler2D u_facing;
layout(binding = TR_TEX_FORMULATED_TILES) uniform sampler2D u_formulated_tiles;
layout(location = TR_LOC_FORMULATED) uniform vec4 u_formulated;
layout(location = TR_LOC_FORMULATED_STEP) uniform ivec2 u_formulated_step;

float formulated_facing(ivec2 q, ivec2 size) {
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) return 2.0;
  return texelFetch(u_facing, q, 0).r;
}

// Whether a marked tile lies within TR_FORMULATED_REACH + 1 pixels of p (each way).
bool near_formulated_tile(ivec2 p) {
  ivec2 tiles = textureSize(u_formulated_tiles, 0);
  ivec2 lo = max(p - (TR_FORMULATED_REACH + 1), ivec2(0)) / TR_SILHOUETTE_TILE;
  ivec2 hi = min((p + (TR_FORMULATED_REACH + 1)) / TR_SILHOUETTE_TILE, tiles - 1);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      if (texelFetch(u_formulated_tiles, ivec2(x, y), 0).r > 0.0) return true;
  return false;
}

bool formulated(ivec2 p, ivec2 size) {
  if (u_formulated_step == ivec2(0) || !near_formulated_tile(p)) return false;
  if (!(formulated_facing(p, size) > 0.0)) return false;
  ivec2 q = p + u_formulated_step;
  float m = formulated_facing(q, size);
  if (!(m <= 0.0)) return false;
  for (int j = 2; j <= TR_FORMULATED_REACH && m > -u_formulated.w; ++j) {
    q += u_formulated_step;
    m = min(m, formulated_facing(q, size));
  }
  if (!(m <= -u_formulated.w)) return false;
  // Ground in front, as far as the far side is looked for: where the data is cut (the
  // mesh's edge nearest the eye) the ground ends, no crest hides what lies behind it.
  for (int j = 1; j <= TR_FORMULATED_REACH; ++j)
    if (!(formulated_facing(p - j * u_formulated_step, size) < 1.5)) return false;
  return true;
}
