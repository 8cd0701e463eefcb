#pragma once
// Where the creases of a frame lie and how they read, GL-free: the shares of
// their length near the grid boundary, on flat ground and in valleys; how they join into
// strokes; how much of them appears or vanishes between the frames of a flight.
// terrain-render frame / batch --line-stats print them (docs/terrain-render.md, "Line
// statistics"); tests/renderer/line_stats_test.cpp checks them on analytic surfaces.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "terrain/drainage_links.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

// Plan (contour) curvature of the mesh's surface at each vertex, 1/m, from central
// differences of the vertex heights on the grid (Zevenbergen & Thorne 1987):
//   kp = (q^2 r - 2 p q s + p^2 t) / (p^2 + q^2)^(3/2),
// p = dz/dx, q = dz/dy (x east, y north), r = d2z/dx2, s = d2z/dxdy, t = d2z/dy2.
// > 0 where the surface is concave across the slope (valleys, hollows), < 0 on spurs and
// ridges, 0 on planes; 0 on the mesh's boundary and where the slope is below 1e-6. #V.
std::vector<float> plan_curvature(const terrain::GridMesh& mesh);
float plan_curvature_at(const terrain::GridMesh& mesh, std::size_t v);  // of vertex v alone
// A per-vertex value of `mesh` at local x, y, `at(v)` the value of vertex v (no array of it
// held): bilinear between the four vertices about it, clamped to the grid.
template <class At>
double vertex_value_at(const terrain::GridMesh& mesh, At at, double x, double y) {
  const long R = long(mesh.topo.rows), C = long(mesh.topo.cols);
  const double fc = std::clamp(x / mesh.geo.dx, 0.0, double(C - 1)),
               fr = std::clamp(-y / mesh.geo.dy, 0.0, double(R - 1));
  const long c0 = std::min(long(fc), C - 2), r0 = std::min(long(fr), R - 2);
  const double u = fc - double(c0), v = fr - double(r0);
  auto f = [&](long r, long c) { return double(at(std::size_t(r * C + c))); };
  return (1 - v) * ((1 - u) * f(r0, c0) + u * f(r0, c0 + 1)) +
         v * ((1 - u) * f(r0 + 1, c0) + u * f(r0 + 1, c0 + 1));
}

// What each crease segment (i -> its downstream point) lies on, #S flags each.
struct SegmentTraits {
  std::vector<std::uint8_t> boundary;  // i within `margin` samples of the network grid's edge
  std::vector<std::uint8_t> flat;      // the segment does not descend (flat or filled ground)
  std::vector<std::uint8_t>
      valley;  // plan curvature at its midpoint > 0 (bilinear between mesh vertices)
  // Its downstream point is where a drawn line may end: within `margin` samples of the
  // network grid's edge or of no-data (the flow leaves the terrain), or the pit of a closed
  // basin of at least kClosedBasinShare of the network's points (a lake, a sink that
  // conditioning kept; a pit of an unconditioned surface drains less).
  std::vector<std::uint8_t> open_end;
};
inline constexpr double kClosedBasinShare = 0.01;
SegmentTraits segment_traits(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links,
                             const CreaseGeometry& g, int margin = 3);

// The traits of a level of merged creases (merge_crease_runs) from its fine segments':
// boundary, flat and valley those of the first fine segment it replaces, open_end that of
// its last (where the line ends).
SegmentTraits merged_traits(const SegmentTraits& fine, const CreaseLevel& level);

// Screen length in pixels of each segment in `view` as the DM pass draws it (heights
// scaled by `exaggeration`; drawn where its ends lie on the surface, the lift moves only
// their depth), clipped to the image; 0 where an end lies behind the near plane. #S.
std::vector<double> segment_pixels(const CreaseGeometry& g, const View& view, double exaggeration);

// The fraction of each segment's pixels that show, by the test the renderer applies to
// that segment's own line, not to whatever else is drawn at its pixels: sampled at each
// pixel along the segment on screen (clipped to the image), the line's depth there (its
// ends moved `lift` towards the eye, as line_clip in common.glsl does) against
// `toward_depth` (view.width x view.height window depths, row 0 at the top, the clear
// depth where no surface is; FrameBuffers::toward_depth). Anti-aliased (line.frag.glsl's
// test, as PELs take it; creases smooth it along their strokes, stroke_visibility.hpp):
// not behind the farthest surface of the sample's pixel and its 8 neighbours, one of which
// shows surface. Pixel-exact (the composite): its own pixel shows surface and the line is
// not behind it. Segments with no pixel get 0. #S.
std::vector<double> visible_fraction(const CreaseGeometry& g, const View& view, double exaggeration,
                                     double lift, const std::vector<float>& toward_depth,
                                     bool antialias);

// The strokes drawn: chains of drawn segments (drawn[s] > 0), each drawn segment
// continuing the stroke of the drawn inflow of largest flow at its upstream vertex (ties:
// the lower segment index); others start a stroke. Each stroke lists its segments from
// upstream down.
std::vector<std::vector<std::uint32_t>> crease_strokes(const CreaseGeometry& g,
                                                       const std::vector<float>& drawn);

// The connected share: of the drawn crease length (drawn[s] x length[s], the lengths before
// hidden-line removal), the part in drawn trees that end where a line may end
// (SegmentTraits::open_end): a drawn segment's tree follows drawn segments downstream to
// the last one; a tree whose last segment stops short of that - before the river it joins,
// or in the middle of a slope - is a dash. 1 when nothing is drawn.
double connected_share(const CreaseGeometry& g, const SegmentTraits& traits,
                       const std::vector<float>& drawn, const std::vector<double>& length);

struct LineStats {
  double length_px = 0;                       // drawn crease length (opacity-weighted)
  double connected = 1;                       // connected_share, before hiding
  double boundary = 0, flat = 0, valley = 0;  // shares of length_px
  std::size_t strokes = 0;
  double mean_stroke_px = 0;  // length_px / strokes
  // The strokes counted as their length is, by opacity: each stroke by the mean opacity
  // of its pixels (sum of opacity x pixels over its pixels), so a stroke fading in at
  // half opacity is half a stroke of half its ink; with opacities 0 or 1, strokes.
  double weighted_strokes = 0;
  double weighted_mean_stroke_px = 0;  // length_px / weighted_strokes
};
// `drawn`: #S opacity in [0, 1] (accepted_segments as 0 / 1); `pixels`: #S drawn length
// (segment_pixels, times visible_fraction: the lines left after hidden-line removal).
LineStats line_stats(const CreaseGeometry& g, const SegmentTraits& traits,
                     const std::vector<float>& drawn, const std::vector<double>& pixels);

// The silhouettes a frame draws: `opacity` (w x h, 0..255, FrameBuffers::silhouette_opacity)
// in pieces of drawn pixels, as the piece rule joins them (mask_pieces of silhouette.hpp, joined
// across gaps: kSilhouetteJoin), formulated silhouettes included.
// mean_piece_px: the pieces' mean size, each weighted by its opacity (as the creases'
// weighted_mean_stroke_px): a piece the piece rule draws at opacity o counts as o of a piece.
struct SilhouetteStats {
  double pixels = 0;  // opacity-weighted
  std::size_t pieces = 0;
  double mean_piece_px = 0;  // pixels / the pieces' summed opacity
};
SilhouetteStats silhouette_stats(const std::vector<std::uint8_t>& opacity, int w, int h);

// Flicker over a flight: the share of line pixels that appear or vanish between
// consecutive frames, sum_k sum_s |a_k(s) - a_k+1(s)| L / sum_k sum_s max(a_k(s), a_k+1(s)) L
// with a the opacity and L the mean of the segment's pixel lengths in the two frames.
// 0 for fewer than two frames or no line.
double flicker(const std::vector<std::vector<float>>& drawn,
               const std::vector<std::vector<double>>& pixels);

}  // namespace renderer
