#pragma once
// Toward/Away silhouettes (Mower 2015; docs/algorithms.md 9.2), GL-free: the rule the SIL
// pass (silhouette.frag.glsl) applies to the TFT and AFT depth buffers, as its test
// reference.
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

}  // namespace renderer
