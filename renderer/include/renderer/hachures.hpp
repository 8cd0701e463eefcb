#pragma once
// Hachures (issue 51; docs/terrain-render.md, "Hachures"), GL-free: strokes along the
// projected fall line of the surface, seeded and spaced in screen space, the CPU reference
// that a compute-shader pass is to follow.
//
// The input is a field over the image: for each pixel that shows terrain, the direction
// of steepest descent as it runs on the screen (a unit 2D vector), the slope there and a
// tone (0 white .. 1 black). The tracer is Jobard and Lefer's evenly spaced streamlines
// (1997): seeds on a grid of `spacing` pixels, each traced downhill and uphill with
// midpoint (RK2) steps of half a pixel while the next point shows terrain, is steep enough,
// is not a blocked pixel (a drawn crease or silhouette: hachures stop at lines and never
// cross them) and lies at least `spacing * test_share` from every other hachure; a traced
// line shorter than `min_length` pixels is dropped. Flats (slope below `min_slope`) stay
// white. The spacing is spacing / tone (tone clamped to kMinTone .. 1): `spacing` where the
// tone is black, six times it where white, so that the ink a pixel gets follows the tone
// (Lehmann's scale: steeper or darker, denser).
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "renderer/camera.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct HachureField {
  int width = 0, height = 0;
  std::vector<Eigen::Vector2f> fall;  // #pixels, unit screen direction downhill (u right, v down); 0 where no terrain
  std::vector<float> slope;           // #pixels, radians, as drawn (heights exaggerated); NaN where no terrain
  std::vector<float> tone;            // #pixels, 0 .. 1 (darkness the hachures should give)
  std::vector<std::uint8_t> blocked;  // #pixels, 1 on a drawn crease or silhouette (optional: empty)
  bool terrain(long u, long v) const {
    return u >= 0 && v >= 0 && u < width && v < height &&
           !std::isnan(slope[std::size_t(v) * std::size_t(width) + std::size_t(u)]);
  }
};

inline constexpr double kMinTone = 1.0 / 6.0;
struct HachureRule {
  double spacing = 6.0;       // pixels between neighbouring hachures where the tone is black
  double test_share = 0.5;    // a hachure stops this share of its spacing from another one
  double min_slope = 0.05;    // radians: flatter ground stays white (about 3 degrees)
  double min_length = 4.0;    // pixels: shorter traces are dropped
  double max_length = 1e9;    // pixels: a hachure ends after this long (rows of hachures: the row's height)
};

struct Hachure {
  std::vector<Eigen::Vector2f> points;  // pixel coordinates (u right, v down), downhill order
  std::vector<float> tone;              // at each point
};

// The evenly spaced hachures of `field` under `rule`. Deterministic (seeds in row order).
std::vector<Hachure> trace_hachures(const HachureField& field, const HachureRule& rule);

// The field of a frame: each pixel whose toward depth (`toward_depth`, the frame's TFT
// buffer, row 0 at the top) shows surface is unprojected to the mesh's local frame (heights
// scaled by `exaggeration`), the PN surface above that point gives its normal (pn_point_above),
// and the fall line there, a short step down the surface, is projected back to the screen.
// Tone: the slope's (Lehmann: 0 flat .. 1 at 45 degrees, tan of the slope) or, with `light`
// set, the shadow's (1 - n.l on the exaggerated surface, clamped).
HachureField hachure_field(const terrain::GridMesh& mesh, const View& view, double exaggeration,
                           const std::vector<float>& toward_depth, const Eigen::Vector3d* light = nullptr);

}  // namespace renderer
