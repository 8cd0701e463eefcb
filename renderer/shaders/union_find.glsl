// Connected components by union-find over item indices (Playne & Hawick 2018, "A new
// algorithm for parallel connected-component labelling on GPUs"), for the piece rules of
// silhouettes (silhouette_pieces.comp.glsl, over pixels) and PELs (pel_pieces.comp.glsl,
// over segments). label[i] is the parent of item i, TR_PIECE_ROOT for a root (set before
// a frame's pieces: the buffer cleared, or each silhouette pixel's as it is listed); a
// parent is always a smaller index of the same piece, so the root is the piece's least
// index, whatever order the joins run in.
// piece_size[] (0 before the frame's pieces) is for the caller's per-root sums.
#ifndef TR_PIECE_BUFFERS  // silhouette_list.glsl declares them, for the pixels it lists
layout(std430, binding = TR_SSBO_PIECE_LABELS) coherent buffer PieceLabels { uint label[]; };
layout(std430, binding = TR_SSBO_PIECE_SIZES) buffer PieceSizes { uint piece_size[]; };
#endif
layout(location = TR_LOC_PIECE_STAGE) uniform int u_piece_stage;

uint find_root(uint x) {
  for (uint y = label[x]; y != TR_PIECE_ROOT; y = label[x]) x = y;
  return x;
}

// Joins the pieces of a and b: atomicMin on the larger root's label.
void unite(uint a, uint b) {
  a = find_root(a);
  b = find_root(b);
  while (a != b) {
    uint hi = max(a, b), lo = min(a, b);
    uint old = atomicMin(label[hi], lo);
    if (old == TR_PIECE_ROOT) return;
    // hi was joined to a smaller root meanwhile: join that piece to lo instead.
    a = find_root(old);
    b = find_root(lo);
  }
}

// The root of item i once every join has run: labels are set to roots (compress_label)
// in the stage after the joins.
uint compress_label(uint i) {
  uint r = find_root(i);
  if (r != i) label[i] = r;
  return r;
}
uint root_of(uint i) { return label[i] == TR_PIECE_ROOT ? i : label[i]; }
