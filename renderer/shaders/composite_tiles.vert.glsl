// LAY's silhouette draw (composite.frag.glsl with TR_COMPOSITE_SILHOUETTES): two triangles
// per TR_SILHOUETTE_TILE tile of the image, drawn where a tile that SIL marked lies within
// the silhouettes' reach, collapsed to nothing elsewhere, so the silhouette band's code runs on the pixels near silhouettes
// only.
layout(binding = TR_TEX_SILHOUETTE_TILES) uniform sampler2D u_silhouette_tiles;
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
void main() {
  ivec2 tiles = textureSize(u_silhouette_tiles, 0);
  int tile = gl_VertexID / 6, corner = gl_VertexID % 6;
  ivec2 t = ivec2(tile % tiles.x, tile / tiles.x);
  int k = (silhouette_reach() + TR_SILHOUETTE_TILE - 1) / TR_SILHOUETTE_TILE;  // tiles within reach
  bool near = false;
  for (int dy = -k; dy <= k; ++dy)
    for (int dx = -k; dx <= k; ++dx) {
      ivec2 q = clamp(t + ivec2(dx, dy), ivec2(0), tiles - 1);
      near = near || texelFetch(u_silhouette_tiles, q, 0).r > 0.0;
    }
  // Corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1) of the tile, in pixels, then clip space.
  ivec2 c = ivec2(corner == 1 || corner == 4 || corner == 5 ? 1 : 0, corner == 2 || corner == 3 || corner == 5 ? 1 : 0);
  vec2 size = vec2(textureSize(u_toward, 0));
  vec2 px = min(vec2((t + c) * TR_SILHOUETTE_TILE), size);
  gl_Position = near ? vec4(px / size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
