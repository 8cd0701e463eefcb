// SIL, pieces (anti-aliased lines; renderer::silhouette_piece_opacity is the CPU
// reference): the silhouette pixels joined to those within TR_SILHOUETTE_JOIN pixels into pieces, and each
// pixel's opacity from its piece's size n: clamp((n - (1 - f) m) / (f m), 0, 1), m = u_piece_min
// pixels, f = TR_SILHOUETTE_FADE. Union-find (union_find.glsl) over pixel indices on the pixels the silhouette
// pass listed (silhouette_list.glsl, which sets each listed pixel's label and size), one
// listed pixel per invocation (the opacity cleared to 0 before the silhouette pass). Stages
// (u_piece_stage), an indirect dispatch each:
//   1 each silhouette pixel joined to the silhouette pixels of the half of its window
//     before it (rows below, and west on its row: every pair once), by atomicMin on the
//     larger root's label;
//   2 each silhouette pixel's label set to its root, the root's size counted;
//   3 the opacity written.
// (Included after silhouette_list.glsl and union_find.glsl.)
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(binding = TR_TEX_SILHOUETTE) uniform sampler2D u_silhouette;
layout(binding = TR_IMG_SILHOUETTE_OPACITY, r8) uniform writeonly image2D u_opacity;

void piece_stage(uint i, ivec2 size) {
  ivec2 p = ivec2(int(i % uint(size.x)), int(i / uint(size.x)));
  if (u_piece_stage == 1) {
    const int j = TR_SILHOUETTE_JOIN;
    for (int dy = -j; dy <= 0; ++dy)
      for (int dx = -j; dx <= j; ++dx) {
        if (dy == 0 && dx >= 0) break;
        ivec2 q = p + ivec2(dx, dy);
        if (q.x < 0 || q.y < 0 || q.x >= size.x) continue;
        if (texelFetch(u_silhouette, q, 0).r > 0.0) unite(i, uint(q.y) * uint(size.x) + uint(q.x));
      }
  } else if (u_piece_stage == 2) {
    atomicAdd(piece_size[compress_label(i)], 1u);
  } else {
    uint r = root_of(i);
    float band = TR_SILHOUETTE_FADE * u_piece_min;
    imageStore(u_opacity, p, vec4(clamp((float(piece_size[r]) - (u_piece_min - band)) / band, 0.0, 1.0)));
  }
}

void main() {
  ivec2 size = textureSize(u_silhouette, 0);
  uint stride = gl_NumWorkGroups.x * uint(TR_LOCAL_SIZE);
  for (uint k = gl_GlobalInvocationID.x; k < piece_count; k += stride) piece_stage(piece_pixel[k], size);
}
