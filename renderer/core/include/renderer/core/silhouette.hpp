#pragma once
// Toward/Away silhouettes (Mower 2015; docs/algorithms.md 9.2), GL-free: the rule the SIL
// pass (silhouette.frag.glsl) applies to the TFT and AFT depth buffers, as its test
// reference.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/camera.hpp"

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
std::vector<std::uint8_t> toward_away_silhouettes(const std::vector<float>& toward,
                                                  const std::vector<float>& away, int w, int h,
                                                  bool reversed_z, bool antialias);

// Formulated silhouettes (Whelan & Visvalingam 2003, "Formulated silhouettes for sketching
// terrain"; docs/algorithms.md 9.2): seen from above, a hill has few occluding contours, so
// the lines drawn are those that would be silhouettes were the eye lowered: on the visible
// surface, where it turns from facing a lower line of sight to facing away from it. The
// lowered line of sight: the view's bearing (the horizontal part of its forward + up
// vectors, so that the top view looks towards the image's top), `altitude` degrees below
// the horizon, one direction for the frame (a parallel lowered eye). `step`: the
// 8-neighbour offset (window pixels, y up) nearest the image of that bearing, the way
// "behind" on the screen; (0, 0) when the bearing has no image (the line of sight
// horizontal): then nothing is drawn. `strength` = sin(degrees): how much steeper than the
// lowered sight line the far side must fall - how much the line would hide.
struct FormulatedView {
  Eigen::Vector3f direction{0, 0, -1};  // unit, mesh frame, from the lowered eye
  int step_x = 0, step_up = 0;
  float strength = 0;
  bool active() const { return step_x != 0 || step_up != 0; }
};
FormulatedView formulated_view(const View& view, double altitude_deg, double strength_deg);

// How far behind a pixel its far side is looked for, pixels along `step` (TR_FORMULATED_REACH).
inline constexpr int kFormulatedReach = 4;

// The formulated silhouette mask (w x h, 0/1) from the drawn surface's unit normals
// (`normals`: 4 floats a pixel, rows from the top, the 4th 1 where the terrain is drawn),
// the rule the SIL pass applies (formulated.glsl): with g(q) = -n(q) . direction (> 0: q
// faces the lowered eye; 2 off the terrain or the image), p is on when g(p) > 0, g(p + s)
// <= 0 for the step s, min g over p + s .. p + kFormulatedReach s <= -strength, and
// p - s .. p - kFormulatedReach s are terrain: a visible slope facing the lowered eye in
// front of one falling away behind it, steeply enough, with ground in front of it (not the
// cut edge of the data). The line lies on the near side of the crest, one pixel wide along
// the step. g(q) is the mean over the terrain pixels of q's 3 x 3 window.
std::vector<std::uint8_t> formulated_silhouettes(const std::vector<float>& normals, int w, int h,
                                                 const FormulatedView& f);

// The pieces of a mask (w x h, non-zero: on): its on pixels joined to those within `join`
// pixels (Chebyshev distance; 1: the 8-neighbours, 3: across gaps of up to 2 pixels).
// piece: per pixel, 0 off, else 1 + the index of its piece; size: pixels per piece.
struct MaskPieces {
  std::vector<std::uint32_t> piece;
  std::vector<std::size_t> size;
};
MaskPieces mask_pieces(const std::vector<std::uint8_t>& mask, int w, int h, int join = 1);

// Silhouette pieces join across gaps of up to kSilhouetteJoin - 1 pixels (TR_SILHOUETTE_JOIN):
// one contour broken where it grazes the rays, or a formulated line where it crosses a
// saddle or a spur, is one stroke for the piece rule and the line statistics.
inline constexpr int kSilhouetteJoin = 5;
// A silhouette piece fades in over this share of the piece rule's minimum below it
// (TR_SILHOUETTE_FADE): a stroke or nothing, with a short fade so that a piece growing
// across the minimum in a flight does not pop.
inline constexpr double kSilhouetteFade = 0.25;

// Pieces, the rule the SIL pass applies after either silhouette method when lines are
// anti-aliased: the silhouette pixels of `mask` (w x h, non-zero: silhouette) joined to
// those within kSilhouetteJoin pixels. A piece of n pixels is drawn with opacity
// piece_opacity(n, m, kSilhouetteFade), m = min_pixels: in full from m pixels, fading out to
// nothing at 3/4 m (a piece that grows or shrinks from frame to frame fades instead of
// popping). Where a surface
// only grazes the eye's rays (rolling ridges seen from above) the away-facing ground is
// patchy and its silhouette a scatter of short dashes; a pen draws the long lines only.
// min_pixels <= 0: every silhouette pixel 1. Non-silhouette pixels 0.
std::vector<float> silhouette_piece_opacity(const std::vector<std::uint8_t>& mask, int w, int h,
                                            double min_pixels);

// The depth a silhouette hides (Imhof: the skyline and the crests carry the heaviest line):
// at each pixel of `mask` (w x h, non-zero: silhouette), from `distance` (w x h, metres along
// the line of sight to the drawn surface, +infinity where nothing is drawn), the share by
// which the farthest surface within kHiddenReach pixels lies beyond the pixel's own,
// (d_far - d) / d: 0 where nothing lies behind, +infinity at the skyline. 0 off the mask.
inline constexpr int kHiddenReach = 3;
std::vector<float> silhouette_hidden_share(const std::vector<std::uint8_t>& mask,
                                           const std::vector<float>& distance, int w, int h);
// The weight of a hidden share in a silhouette's width: 0 at none, 1 from kHiddenFull on (a
// surface a quarter farther than the line, or the sky).
inline constexpr double kHiddenFull = 0.25;
inline float hidden_weight(float share) {
  return float(std::min(1.0, std::max(0.0, double(share) / kHiddenFull)));
}

// The piece rule's opacity of a piece of size n (pixels here; metres for PELs, pel.hpp): in
// full from min_size, fading to nothing over the `fade` share of it below.
inline float piece_opacity(double n, double min_size, double fade = 0.5) {
  if (!(min_size > 0)) return 1.0f;
  const double band = fade * min_size, o = (n - (min_size - band)) / band;
  return float(o < 0 ? 0 : o > 1 ? 1 : o);
}

}  // namespace renderer
