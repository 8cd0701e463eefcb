// SIL and LAY draw only near marked tiles: one invocation per TR_SILHOUETTE_TILE tile of
// the image (rows of tiles) appends the rectangle of the tile's pixels within u_reach
// (columns, rows) of a tile that u_marks marks (the bounding box of those pixels: a tile
// beside a marked one gives a strip u_reach pixels wide, not its 64), when there are any.
// Pixel p counts as within reach of tile m when the rectangle of half-sides u_reach about p
// meets m.
// Here rather than in the draws' vertex shader: llvmpipe runs vertex shaders on one
// thread, compute shaders on all.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(binding = TR_TEX_TILE_MARKS) uniform sampler2D u_marks;
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(location = TR_LOC_TILE_REACH) uniform ivec2 u_reach;
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  ivec2 tiles = textureSize(u_marks, 0), size = textureSize(u_toward, 0);
  if (i >= uint(tiles.x * tiles.y)) return;
  ivec2 t = ivec2(int(i) % tiles.x, int(i) / tiles.x);
  ivec2 t_lo = t * TR_SILHOUETTE_TILE, t_hi = min(t_lo + TR_SILHOUETTE_TILE, size) - 1;  // the tile's pixels
  ivec2 lo = t_hi + 1, hi = t_lo - 1;  // none yet
  ivec2 k = (u_reach + TR_SILHOUETTE_TILE - 1) / TR_SILHOUETTE_TILE;
  for (int dy = -k.y; dy <= k.y; ++dy)
    for (int dx = -k.x; dx <= k.x; ++dx) {
      ivec2 m = t + ivec2(dx, dy);
      if (any(lessThan(m, ivec2(0))) || any(greaterThanEqual(m, tiles)) || !(texelFetch(u_marks, m, 0).r > 0.0)) continue;
      ivec2 m_lo = m * TR_SILHOUETTE_TILE - u_reach;
      ivec2 m_hi = min(m * TR_SILHOUETTE_TILE + TR_SILHOUETTE_TILE, size) - 1 + u_reach;
      lo = min(lo, max(m_lo, t_lo));
      hi = max(hi, min(m_hi, t_hi));
    }
  if (any(greaterThan(lo, hi))) return;
  rect[atomicAdd(rect_vertices, 6u) / 6u] = ivec4(lo, hi + 1);
}
