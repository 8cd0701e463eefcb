// SIL, formulated silhouettes (Whelan & Visvalingam 2003; renderer::formulated_silhouettes
// is the CPU reference): on the visible surface, the lines that would be silhouettes seen
// from a lowered eye. g(q) = -n(q) . u_formulated.xyz, the drawn surface's normal (TFT's
// second target) against the lowered line of sight (> 0: facing the lowered eye; 2 off
// the terrain or the image). Pixel p is on when g(p) > 0, g(p + step) <= 0 and the least
// g over p + step .. p + TR_FORMULATED_REACH step is <= -strength (u_formulated.w).
layout(binding = TR_TEX_SURFACE_NORMAL) uniform sampler2D u_normal;
layout(location = TR_LOC_FORMULATED) uniform vec4 u_formulated;
layout(location = TR_LOC_FORMULATED_STEP) uniform ivec2 u_formulated_step;

float facing_at(ivec2 q, ivec2 size) {
  vec4 n = texelFetch(u_normal, clamp(q, ivec2(0), size - 1), 0);
  return -(n.x * u_formulated.x + n.y * u_formulated.y + n.z * u_formulated.z);
}
// g at q: the mean over the terrain pixels of q's 3 x 3 window (the drawn normals' pixel
// noise smoothed), 2 where q is off the terrain or the image.
float formulated_facing(ivec2 q, ivec2 size) {
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) return 2.0;
  if (!(texelFetch(u_normal, q, 0).w > 0.5)) return 2.0;
  float sum = 0.0, count = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 r = q + ivec2(dx, dy);
      if (any(lessThan(r, ivec2(0))) || any(greaterThanEqual(r, size))) continue;
      if (!(texelFetch(u_normal, r, 0).w > 0.5)) continue;
      sum += facing_at(r, size);
      count += 1.0;
    }
  return sum / count;
}

bool on_terrain(ivec2 q, ivec2 size) {
  return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)) && texelFetch(u_normal, q, 0).w > 0.5;
}

bool formulated(ivec2 p, ivec2 size) {
  if (u_formulated_step == ivec2(0)) return false;
  if (!(formulated_facing(p, size) > 0.0)) return false;
  // Ground in front, as far as the far side is looked for: where the data is cut (the
  // mesh's edge nearest the eye) the ground ends, no crest hides what lies behind it.
  for (int j = 1; j <= TR_FORMULATED_REACH; ++j)
    if (!on_terrain(p - j * u_formulated_step, size)) return false;
  ivec2 q = p + u_formulated_step;
  float m = formulated_facing(q, size);
  if (!(m <= 0.0)) return false;
  for (int j = 2; j <= TR_FORMULATED_REACH && m > -u_formulated.w; ++j) {
    q += u_formulated_step;
    m = min(m, formulated_facing(q, size));
  }
  return m <= -u_formulated.w;
}
