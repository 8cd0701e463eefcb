// SIL, formulated silhouettes, before the facing: the TR_SILHOUETTE_TILE tiles near which a
// formulated pixel p may lie. p needs a smoothed facing g > 0 at itself, so a pixel within
// one of it that faces the lowered eye (-n . u_formulated.xyz > 0) or is no terrain (b), and
// g <= -strength within TR_FORMULATED_REACH pixels along its step, so a terrain pixel within
// TR_FORMULATED_REACH + 1 of it whose own facing is at most -strength (a); both with a
// margin for the rounding of formulated_facing.frag.glsl's mean. First each tile's classes
// (1: it holds an a, 2: a b); then (TR_FORMULATED_MARKS) a tile is marked when it holds an a
// and a tile beside it or itself a b: those two pixels lie within TR_FORMULATED_REACH + 2 of
// each other, so within a tile. p then lies within TR_FORMULATED_REACH + 1 pixels of a marked
// tile (formulated.glsl), and the facing and the test are drawn only there
// (image_passes.cpp), with the same pixels as over the whole image.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(binding = TR_IMG_FORMULATED_TILES, r8) uniform writeonly image2D u_formulated_marks;
#ifdef TR_FORMULATED_MARKS
layout(binding = TR_TEX_FORMULATED_TILES) uniform sampler2D u_formulated_tiles;
#else
layout(binding = TR_TEX_SURFACE_NORMAL) uniform sampler2D u_normal;
layout(location = TR_LOC_FORMULATED) uniform vec4 u_formulated;
#endif
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  ivec2 tiles = imageSize(u_formulated_marks);
  if (i >= uint(tiles.x * tiles.y)) return;
  ivec2 t = ivec2(int(i) % tiles.x, int(i) / tiles.x);
#ifdef TR_FORMULATED_MARKS
  bool mark = false;
  if (uint(texelFetch(u_formulated_tiles, t, 0).r * 255.0 + 0.5) % 2u == 1u)
    for (int y = max(t.y - 1, 0); y <= min(t.y + 1, tiles.y - 1) && !mark; ++y)
      for (int x = max(t.x - 1, 0); x <= min(t.x + 1, tiles.x - 1) && !mark; ++x)
        mark = uint(texelFetch(u_formulated_tiles, ivec2(x, y), 0).r * 255.0 + 0.5) >= 2u;
  imageStore(u_formulated_marks, t, vec4(mark ? 1.0 : 0.0));
#else
  ivec2 size = textureSize(u_normal, 0), p0 = t * TR_SILHOUETTE_TILE;
  ivec2 p1 = min(p0 + TR_SILHOUETTE_TILE, size);
  float away = -u_formulated.w + 1e-4;
  bool a = false, b = false;
  for (int y = p0.y; y < p1.y && !(a && b); ++y)
    for (int x = p0.x; x < p1.x && !(a && b); ++x) {
      vec4 n = texelFetch(u_normal, ivec2(x, y), 0);
      float g = -(n.x * u_formulated.x + n.y * u_formulated.y + n.z * u_formulated.z);
      bool terrain = n.w > 0.5;
      a = a || (terrain && g <= away);
      b = b || !terrain || g > -1e-4;
    }
  imageStore(u_formulated_marks, t, vec4(float((a ? 1 : 0) + (b ? 2 : 0)) / 255.0));
#endif
}
