#pragma once
// A frame's line art as stroked paths in screen coordinates, GL-free: what the
// SVG / PDF writer (vector_file.hpp) draws, built from the same strokes, masks and
// segments the PNG's passes draw (docs/terrain-render.md, "Vector output").
//   creases      one path per visible run of each drawn stroke (crease_strokes), where the
//                stroke's samples show (the DM pass's own hidden-run and peek rules), at
//                the run's mean opacity (by length); a filled outline where its width
//                varies by 0.125 px or more, else a stroke of its width quantised to 0.25 px;
//   silhouettes  the drawn pixels (the piece rule's opacity > 0) chained into centre lines
//                (chain_mask), smoothed and simplified to 0.25 px, each at its piece's
//                mean opacity;
//   pels, edges  the visible parts of their segments (sampled every 0.5 px by the test the
//                PNG applies to them), chained where consecutive pieces join.
// Coordinates: x right, y down, pixels; the frame's size is the page.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/hachures.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/vector_lines.hpp"

namespace renderer {

struct VectorPath {
  Polyline line;
  float width = 1;    // pixels: a stroke of this width ...
  float opacity = 1;  // 0..1
  // ... or, where not empty, one width per point: a line whose width varies, drawn as a
  // filled outline (the union of the capsules of its segments, round ends).
  std::vector<float> widths;
  // What it was drawn from, as its layer names them (VectorLayer::value_names): a crease's
  // basin share a / T (its width's source) and Strahler order on the drawn network (their
  // largest along the path), a hachure's mean tone; empty elsewhere.
  std::vector<float> values{};
};

enum class LineCap { Butt, Round, Square };

struct VectorLayer {
  std::string name;  // "creases", "silhouettes", "pels", "edges"
  Eigen::Vector3f colour{0, 0, 0};
  LineCap cap = LineCap::Round;  // and the join: round, or mitre for square caps
  std::vector<VectorPath> paths;
  std::size_t strokes = 0;  // the strokes, pieces or chains drawn that the paths come from
  std::vector<std::string> value_names{};  // what VectorPath::values hold ("tone", ...)
};

// Strahler's order of every crease vertex on the network `g` draws (its segments, the
// channels the crease rules keep): 1 where no segment comes in, else the largest order
// coming in, plus one where two or more bring it; 0 on a vertex of no segment.
std::vector<std::uint8_t> crease_orders(const CreaseGeometry& g);

// What lies under the lines: nothing, the surface as filled regions of the mask colour, or
// the shaded relief as an embedded image (both over a background rectangle).
enum class VectorUnderlay { None, Mask, Shaded };
VectorUnderlay parse_underlay(const std::string& name);  // none | mask | shaded; Error otherwise

struct VectorArt {
  int width = 0, height = 0;
  VectorUnderlay underlay = VectorUnderlay::Mask;
  Eigen::Vector3f background{1, 1, 1}, mask_colour{1, 1, 1};
  std::vector<std::uint8_t>
      surface;                       // width x height, 1 where the surface shows (row 0 at the top)
  std::vector<std::uint8_t> shaded;  // width x height x 4 RGBA, the shaded surface (Shaded only)
  std::vector<VectorLayer> layers;   // in drawing order, bottom first
};

// Creases: `drawn` (#S opacity, FrameLines::drawn), `samples` (#S, the DM pass's
// read_crease_samples or the CPU stroke_visibility), widths from `width_min` to
// `width_max` by the square root of the basin share, as crease.vert draws them.
std::vector<VectorPath> crease_paths(const CreaseGeometry& g, const std::vector<float>& drawn,
                                     const std::vector<SegmentSamples>& samples, const View& view,
                                     double exaggeration, double width_min, double width_max,
                                     std::size_t* strokes = nullptr);

// Silhouettes: `opacity` (w x h, 0..255, FrameBuffers::silhouette_opacity) as lines of
// `width` pixels; given `hidden` (silhouette_hidden_share of their pixels), each line
// `heavier` pixels wider times the mean hidden_weight of its pixels (the skyline and the
// lines that hide most the heaviest).
std::vector<VectorPath> silhouette_paths(const std::vector<std::uint8_t>& opacity, int w, int h,
                                         float width, std::size_t* pieces = nullptr,
                                         const std::vector<float>* hidden = nullptr,
                                         float heavier = 0);

// Segments in the mesh's local frame (already exaggerated), each with an opacity; the parts
// that show are kept: anti-aliased lines (PELs) by line.frag's test (not behind the
// farthest toward surface of the sample's pixel and its 8 neighbours, one of which shows
// surface), pixel-exact ones (edges) by the composite's (nothing in front at its own
// pixel). Ends are lifted `lift` metres towards the eye for the test.
struct SceneSegment {
  Eigen::Vector3d a, b;
  float opacity = 1;
};
std::vector<VectorPath> segment_paths(const std::vector<SceneSegment>& segments, const View& view,
                                      double lift, const std::vector<float>& toward_depth,
                                      bool antialias, float width, std::size_t* chains = nullptr);

// The paths of traced hachures (pixel coordinates), each as wide as its mean tone asks:
// 0.5 to 1.5 times Style::hachure_width (pen pressure).
VectorLayer hachure_paths(const std::vector<Hachure>& hachures, const Style& style);

}  // namespace renderer
