#pragma once
// Hidden-line removal of anti-aliased creases along their strokes (docs/terrain-render.md,
// "Hidden runs and peeks"), GL-free: the CPU reference of the DM pass's three visibility
// stages (crease_visibility.comp.glsl) and what --line-stats measures.
//
// Each drawn segment is sampled at n = ceil(its screen length) points, 1 to
// kStrokeSamples, at (k + 0.5) / n along it. A sample is visible by line.frag's test: not
// behind the farthest toward surface of its pixel and the 8 neighbours, one of which shows
// surface. Visibility is then smoothed along the stroke, as a pen would draw it:
//   - a hidden run between visible samples, at most gap_px long, every sample of it at
//     most gap_depth metres behind that farthest surface, is drawn: the floor of a gully
//     seen at a grazing angle, whose near wall hides it a pixel or two at a time, becomes
//     a line, not dashes; a ridge in front of the line (far more than gap_depth) still
//     cuts it;
//   - then a drawn run at most min_peek_px long beside a hidden sample (a channel peeking
//     out for a few pixels between ridges, or at the image's edge) is left out: a dot, not
//     a line. Here a tributary's run ends where it joins a line that goes on past
//     min_peek_px, as its stroke does (crease_strokes): the last pixels of a tributary
//     hidden upstream are a tick on the trunk, not a line.
// Strokes are followed upstream along SegmentChains::prev and downstream along next, over
// segments with samples, at most kStrokeReach segments each way. 0 turns a rule off.
#include <cstdint>
#include <optional>
#include <vector>

#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/frame_params.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

inline constexpr int kStrokeSamples = 32;  // TR_STROKE_SAMPLES: the bits of a mask

struct StrokeVisibilityRule {
  double gap_px = 0;       // longest hidden run drawn (pixels)
  double gap_depth = 0;    // ... when none of it is more than this behind the surface (metres)
  double min_peek_px = 0;  // longest drawn run left out beside a hidden sample (pixels)
};
// Style::crease_hidden_gap and crease_min_peek (pixels), crease_hidden_depth times the
// mesh's spacing (the smaller of dx, dy).
StrokeVisibilityRule stroke_visibility_rule(const Style& style, const terrain::GridMesh& mesh);

// Bit k of a mask is sample k.
struct SegmentSamples {
  std::uint32_t visible = 0;     // line.frag's test
  std::uint32_t bridgeable = 0;  // hidden, on screen, at most gap_depth behind the farthest surface
  std::uint32_t closed = 0;      // visible, or in a hidden run that is drawn
  std::uint32_t shown = 0;       // closed, less the peeks: what the DM pass draws
  std::uint32_t n = 0;           // samples; 0: not drawn, or an end behind the near plane
  float step = 0;                // screen length of a sample (pixels)
};

// Crease vertex i as drawn: its height scaled by the exaggeration e (local frame).
Eigen::Vector3d drawn_position(const CreaseGeometry& g, std::uint32_t i, double e);

// Point p (drawn, local frame) moved `lift` metres towards the eye (at most half way),
// projected: where a line takes its depth (line_clip in common.glsl).
Projected lifted_projection(const View& view, const Eigen::Vector3d& p, double lift);

// The window depth of the farthest toward surface among pixel (x, y) and its 8 neighbours
// (clamped to the image; `toward_depth` row 0 at the top), none where none of them shows
// surface: what line.frag tests a line sample against.
std::optional<double> farthest_surface(const View& view, const std::vector<float>& toward_depth,
                                       long x, long y);

// The samples of every segment with drawn[s] > 0 (#S), in `view` with heights scaled by
// `exaggeration`, each end's depth taken `lift` metres towards the eye (line_clip), against
// `toward_depth` (view.width x view.height window depths, row 0 at the top;
// FrameBuffers::toward_depth). `chains`: segment_chains(g), as the DM pass holds them.
std::vector<SegmentSamples> stroke_visibility(const CreaseGeometry& g, const SegmentChains& chains,
                                              const std::vector<float>& drawn, const View& view,
                                              double exaggeration, double lift,
                                              const std::vector<float>& toward_depth,
                                              const StrokeVisibilityRule& rule);

// Screen length each segment shows (#S): its shown samples times their step, off-screen
// samples never shown.
std::vector<double> shown_pixels(const std::vector<SegmentSamples>& samples);

// Two sets of samples of the same segments compared (the DM pass's against the CPU
// reference): segments with samples in either, those whose sample counts differ, the
// samples of the others, and how many of those differ in each mask; and of `b`, its
// hidden samples drawn and its peek samples left out.
struct SampleComparison {
  std::size_t segments = 0, other_count = 0, samples = 0;
  std::size_t differ[4] = {};  // visible, bridgeable, closed, shown
  std::size_t hidden_drawn = 0, peeks = 0;
};
SampleComparison compare_samples(const std::vector<SegmentSamples>& a,
                                 const std::vector<SegmentSamples>& b);

}  // namespace renderer
