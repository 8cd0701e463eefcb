// SIL, first: marks each TR_SILHOUETTE_TILE tile that holds a pixel of an away-facing
// surface (away depth nearer than the far plane). A silhouette pixel has one within a
// pixel of it (silhouette.frag.glsl), so SIL draws only the tiles beside marked ones
// (silhouette_tiles.vert.glsl).
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(binding = TR_TEX_AWAY_DEPTH) uniform sampler2D u_away;
layout(binding = TR_IMG_AWAY_TILES, r8) uniform writeonly image2D u_away_tiles;
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  ivec2 tiles = imageSize(u_away_tiles), size = textureSize(u_away, 0);
  if (i >= uint(tiles.x * tiles.y)) return;
  ivec2 t = ivec2(int(i) % tiles.x, int(i) / tiles.x), p0 = t * TR_SILHOUETTE_TILE;
  ivec2 p1 = min(p0 + TR_SILHOUETTE_TILE, size);
  bool away = false;
  for (int y = p0.y; y < p1.y && !away; ++y)
    for (int x = p0.x; x < p1.x && !away; ++x) away = far_of(texelFetch(u_away, ivec2(x, y), 0).r) < 1.0;
  imageStore(u_away_tiles, t, vec4(away ? 1.0 : 0.0));
}
