// A list of patches a compute pass writes for SceneGpu::draw_patch_list (PatchList,
// passes.hpp): in AwayPatches a counter (4 uints), then each listed patch's 3 vertex
// indices; in AwayDraws, draw d (5 uints: count, instances, first index, base vertex, base
// instance) holds listed patches 64 d .. 64 d + 63 (llvmpipe drops patches from a draw that
// tessellates into more than 65536 triangles; kPatchesPerDraw).
layout(std430, binding = TR_SSBO_AWAY_PATCHES) buffer AwayPatches { uint away_tri[]; };
layout(std430, binding = TR_SSBO_AWAY_DRAWS) buffer AwayDraws { uint away_draw[]; };
void list_patch(uint v1, uint v2, uint v3) {
  uint slot = atomicAdd(away_tri[0], 1u), d = slot / TR_PATCHES_PER_DRAW;
  away_tri[4u + 3u * slot] = v1, away_tri[5u + 3u * slot] = v2, away_tri[6u + 3u * slot] = v3;
  atomicAdd(away_draw[5u * d], 3u);
  away_draw[5u * d + 1u] = 1u;
  away_draw[5u * d + 2u] = 4u + 3u * TR_PATCHES_PER_DRAW * d;
}
