// SIL: the silhouette pixels of a frame, listed for the piece rule (silhouette_pieces.comp.glsl)
// by the pass that finds them (silhouette.frag.glsl, adjacency.frag.glsl) when
// u_piece_min > 0. The header is also the indirect dispatch of the rule's stages: one
// work group per TR_LOCAL_SIZE listed pixels, at most 65535 (the stages loop over the list).
layout(std430, binding = TR_SSBO_PIECE_LIST) buffer PieceList {
  uint piece_count;
  uint piece_groups_x, piece_groups_y, piece_groups_z;
  uint piece_pixel[];  // pixel index y * width + x, window rows (0 at the bottom)
};
// The union-find's labels and sizes (union_find.glsl), per pixel: set for a pixel when it
// is listed, so that the buffers need no clearing (the rule reads only listed pixels').
#define TR_PIECE_BUFFERS 1
layout(std430, binding = TR_SSBO_PIECE_LABELS) coherent buffer PieceLabels { uint label[]; };
layout(std430, binding = TR_SSBO_PIECE_SIZES) buffer PieceSizes { uint piece_size[]; };
layout(location = TR_LOC_PIECE_MIN) uniform float u_piece_min;
layout(binding = TR_IMG_SILHOUETTE_TILES, r8) uniform writeonly image2D u_tiles;

// Marks the tile of silhouette pixel p (LAY's search for silhouettes near a pixel).
void mark_silhouette_tile(ivec2 p) { imageStore(u_tiles, p / TR_SILHOUETTE_TILE, vec4(1.0)); }

void list_silhouette_pixel(ivec2 p, ivec2 size) {
  if (!(u_piece_min > 0.0)) return;
  uint k = atomicAdd(piece_count, 1u), i = uint(p.y) * uint(size.x) + uint(p.x);
  piece_pixel[k] = i;
  label[i] = TR_PIECE_ROOT;
  piece_size[i] = 0u;
  atomicMax(piece_groups_x, min(k / uint(TR_LOCAL_SIZE) + 1u, 65535u));
}
