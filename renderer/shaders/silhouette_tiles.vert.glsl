// SIL's draw (silhouette.frag.glsl, Toward/Away): two triangles per TR_SILHOUETTE_TILE tile
// of the image, drawn where the tile or a neighbour holds an away-facing surface pixel
// (away_tiles.comp.glsl; a silhouette pixel has one within a pixel of it), collapsed to
// nothing elsewhere: the test runs on the pixels that can pass it only.
layout(binding = TR_TEX_AWAY_TILES) uniform sampler2D u_away_tiles;
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
void main() {
  ivec2 tiles = textureSize(u_away_tiles, 0);
  int tile = gl_VertexID / 6, corner = gl_VertexID % 6;
  ivec2 t = ivec2(tile % tiles.x, tile / tiles.x);
  bool near = false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      near = near || texelFetch(u_away_tiles, clamp(t + ivec2(dx, dy), ivec2(0), tiles - 1), 0).r > 0.0;
  // Corners (0,0) (1,0) (0,1), (0,1) (1,0) (1,1) of the tile, in pixels, then clip space.
  ivec2 c = ivec2(corner == 1 || corner == 4 || corner == 5 ? 1 : 0, corner == 2 || corner == 3 || corner == 5 ? 1 : 0);
  vec2 size = vec2(textureSize(u_toward, 0));
  vec2 px = min(vec2((t + c) * TR_SILHOUETTE_TILE), size);
  gl_Position = near ? vec4(px / size * 2.0 - 1.0, 0.0, 1.0) : vec4(2.0, 2.0, 2.0, 1.0);
}
