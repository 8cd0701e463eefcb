#pragma once
// Toward/Away silhouettes (Mower 2015; docs/algorithms.md 9.2), GL-free: the rule the SIL
// pass (silhouette.frag.glsl) applies to the TFT and AFT depth buffers, as its test
// reference.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace renderer {

// The silhouette mask (w x h, 0/1) from the window depths of the nearest toward-facing
// (`toward`) and away-facing (`away`) surfaces, w x h each, cleared to the far value (0
// with `reversed_z`, else 1). Pixel-exact (antialias false), the paper's test: with t and a
// the distances ("larger is farther") at p, p is a silhouette when t < a and some
// 8-neighbour's toward distance is beyond a.
// Anti-aliased (the default style) two changes, both for lines that read as strokes:
// - gaps closed: a is the nearest away distance in p's 3 x 3 window. Where a ridge's
//   away-facing band is narrower than a pixel it is rasterized only at some pixels along
//   the ridge, and the paper's test draws the ridge as dashes;
// - specks dropped: a silhouette pixel with fewer than 3 silhouette pixels (itself
//   included) in its 5 x 5 window is left out, where the surface only grazes the rays.
std::vector<std::uint8_t> toward_away_silhouettes(const std::vector<float>& toward, const std::vector<float>& away,
                                                  int w, int h, bool reversed_z, bool antialias);

// The pieces of a mask (w x h, non-zero: on): its on pixels joined by their 8-neighbours.
// piece: per pixel, 0 off, else 1 + the index of its piece; size: pixels per piece.
struct MaskPieces {
  std::vector<std::uint32_t> piece;
  std::vector<std::size_t> size;
};
MaskPieces mask_pieces(const std::vector<std::uint8_t>& mask, int w, int h);

// Pieces, the rule the SIL pass applies after either silhouette method when lines are
// anti-aliased: the silhouette pixels of `mask` (w x h, non-zero: silhouette) joined by
// their 8-neighbours. A piece of n pixels is drawn with opacity clamp((n - m/2) / (m/2),
// 0, 1), m = min_pixels: in full from m pixels, fading out to nothing at m/2 (a piece
// that grows or shrinks from frame to frame fades instead of popping). Where a surface
// only grazes the eye's rays (rolling ridges seen from above) the away-facing ground is
// patchy and its silhouette a scatter of short dashes; a pen draws the long lines only.
// min_pixels <= 0: every silhouette pixel 1. Non-silhouette pixels 0.
std::vector<float> silhouette_piece_opacity(const std::vector<std::uint8_t>& mask, int w, int h, double min_pixels);

// The piece rule's opacity of a piece of size n (pixels here; metres for PELs, pel.hpp).
inline float piece_opacity(double n, double min_size) {
  if (!(min_size > 0)) return 1.0f;
  const double half = 0.5 * min_size, o = (n - half) / half;
  return float(o < 0 ? 0 : o > 1 ? 1 : o);
}

}  // namespace renderer
