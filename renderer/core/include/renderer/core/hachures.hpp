#pragma once
// Hachures (docs/terrain-render.md, "Hachures"), GL-free: strokes along the
// projected fall line of the surface, seeded and spaced in screen space; the tracer, and
// the CPU reference of the field that the GPU computes (TerrainRenderer::hachure_field).
//
// The input is a field over the image: for each pixel that shows terrain, the direction
// of steepest descent as it runs on the screen (a unit 2D vector), the slope there and a
// tone (0 white .. 1 black). The tracer is Jobard and Lefer's evenly spaced streamlines
// (1997): seeds (given ones first, then a grid a third of `spacing` apart), each traced
// downhill and uphill with midpoint (RK2) steps of half a pixel while the next point shows
// terrain, is steep enough, is not a blocked pixel (a drawn crease or silhouette: hachures
// stop at lines and never cross them) and lies at least `test_share` times the smaller of
// the two local spacings from every other hachure; a traced line shorter than
// `min_length` pixels is dropped. Flats (slope below `min_slope`) stay
// white. The spacing is spacing / tone (tone clamped to kMinTone .. 1): `spacing` where the
// tone is black, six times it where white, so that the ink a pixel gets follows the tone
// (Lehmann's scale: steeper or darker, denser).
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/camera.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct HachureField {
  int width = 0, height = 0;
  std::vector<Eigen::Vector2f>
      fall;  // #pixels, unit screen direction downhill (u right, v down); 0 where no terrain
  std::vector<float>
      slope;  // #pixels, radians, as drawn (heights exaggerated); NaN where no terrain
  std::vector<float> tone;  // #pixels, 0 .. 1 (darkness the hachures should give)
  std::vector<std::uint8_t>
      blocked;                   // #pixels, 1 on a drawn crease or silhouette (optional: empty)
  std::vector<float> elevation;  // #pixels, metres (true, not exaggerated): the rows' form lines
  bool terrain(long u, long v) const {
    return u >= 0 && v >= 0 && u < width && v < height &&
           !std::isnan(slope[std::size_t(v) * std::size_t(width) + std::size_t(u)]);
  }
};

inline constexpr double kMinTone = 1.0 / 6.0;
// The light's tone is the shadow less this share of the flat's shadow, 1 - n.l - kFlatShare
// (1 - l_z): slopes lit a little more than the flat, which the shaded layer draws lighter
// than the flat, get no hachures, as the flats (measured: docs/terrain-render.md, "Tone").
inline constexpr double kFlatShare = 0.5;
struct HachureRule {
  double spacing = 6.0;     // pixels between neighbouring hachures where the tone is black
  double test_share = 0.5;  // a hachure stops this share of its spacing from another one
  double min_slope = 0.05;  // radians: flatter ground stays white (about 3 degrees)
  double min_length = 4.0;  // pixels: shorter traces are dropped
  // Pixels: a hachure ends after this long; each run from its seed ends within twice the
  // field's diagonal in any case, and where its fall line comes back to a half-pixel cell
  // it passed more than 4 steps before (a loop).
  double max_length = 1e9;
  // Imhof's rows (--hachure-style rows): with an interval > 0 (metres), each hachure runs
  // between two form lines, the contours at multiples of the interval (HachureField::elevation),
  // and ends half a pixel short of them (a white seam along the contour); the spacing test
  // sees only the hachures of the same row, so the rows abut without thinning each other.
  double row_interval = 0;
};

struct Hachure {
  std::vector<Eigen::Vector2f> points;  // pixel coordinates (u right, v down), downhill order
  std::vector<float> tone;              // at each point
  std::vector<float> slope;             // at each point, radians (as the field has it)
  long row = -1;                        // rows: the band floor(elevation / row_interval); else -1
};

// The evenly spaced hachures of `field` under `rule`. Deterministic: the seeds `first`
// (pixel coordinates, in their order: surface_seeds gives ones that stay on the surface
// from frame to frame), then the grid's in row order.
std::vector<Hachure> trace_hachures(const HachureField& field, const HachureRule& rule,
                                    const std::vector<Eigen::Vector2f>& first = {});

// The point of the surface a frame shows at pixel (u, v) (local frame, heights
// exaggerated), unprojected from its window depth (`toward_depth`, row 0 at the top; camera.hpp's
// unproject, `inverse` its inverse view-projection); none outside the image or where the
// depth is the clear depth.
std::optional<Eigen::Vector3d> surface_point(const View& view, const Eigen::Matrix4d& inverse,
                                             const std::vector<float>& toward_depth, double u,
                                             double v);

// Coherence of hachures along a flight (the crease flicker measure, applied to
// hachures): the points `previous` (local frame, the hachures of frame k on its surface)
// projected into frame k + 1 (`next`, its depth and its hachure ink, width x height); of
// those that land in the image on surface that shows them (within 1 % of their distance
// of the surface point there), the share with ink of frame k + 1 within `radius` pixels.
// Its `counted` the points that landed (0: the share is 1).
struct Coherence {
  std::size_t counted = 0, near = 0;
  double share() const { return counted ? double(near) / double(counted) : 1.0; }
};
Coherence hachure_coherence(const std::vector<Eigen::Vector3f>& previous, const View& next,
                            const std::vector<float>& next_depth,
                            const std::vector<std::uint8_t>& next_ink, int radius = 1);

// Seeds that stay on the surface as the camera moves (frame-to-frame coherence): the
// ground under the frame is cut into square cells `cell` metres a side (local x, y); for
// every cell a pixel of the grid a third of `spacing` apart falls in, the pixel whose ground
// point (surface_point of the frame's `toward_depth`) lies nearest the cell's centre is its
// seed, and the seeds are ordered by a hash of their cell. The same cells win in the next
// frame, their seeds moved with the ground: the hachures move with it. The cells are
// those of the mesh's own frame, `anchor` (the local frame's origin in it; a window of the
// mesh held, LodHierarchy::window) added to the ground points: the same seeds whatever
// part of the mesh is held.
std::vector<Eigen::Vector2f> surface_seeds(const View& view, const std::vector<float>& toward_depth,
                                           double spacing, double cell,
                                           const Eigen::Vector2d& anchor = Eigen::Vector2d::Zero());

// The field of a frame: each pixel whose toward depth (`toward_depth`, the frame's TFT
// buffer, row 0 at the top) shows surface is unprojected to the mesh's local frame (heights
// scaled by `exaggeration`), the PN surface above that point gives its normal (pn_point_above),
// and the fall line there, a short step down the surface, is projected back to the screen.
// Tone: the slope's (Lehmann: 0 flat .. 1 at 45 degrees, tan of the slope) or, with `light`
// set, the shadow's (1 - n.l on the exaggerated surface, less kFlatShare of the flat's,
// clamped).
HachureField hachure_field(const terrain::GridMesh& mesh, const View& view, double exaggeration,
                           const std::vector<float>& toward_depth,
                           const Eigen::Vector3d* light = nullptr);

// The figures of traced hachures (--line-stats; the direction and spacing figures).
struct HachureStats {
  std::size_t hachures = 0, points = 0;
  double length_px = 0;
  double along_share = 0;  // steps within 10 degrees of the field's fall line at their midpoint
  double spacing_share =
      0;  // points whose nearest point of another hachure is 0.5 to 2 local spacings away
  double close_share = 0, far_share = 0;  // the others: nearer than 0.5, farther than 2
  std::vector<std::uint8_t>
      ink;  // width x height: 1 where a hachure's point lies (coherence between frames)
  std::vector<Eigen::Vector3f>
      surface;  // the hachures' points on the surface (local frame; filled by the scene)
};
// The local spacing is the rule's spacing / tone (as the tracer uses it); a point whose
// nearest other hachure is farther than 2 local spacings counts against the share.
HachureStats hachure_stats(const HachureField& field, const std::vector<Hachure>& hachures,
                           const HachureRule& rule);

// The interval of the rows' form lines for a view `scale` metres a pixel across (true
// metres: heights not exaggerated) with hachures `spacing` pixels apart: a row about four
// spacings long on a slope of `slope` radians (the field's median), interval = 4 x spacing
// x scale x tan(slope), rounded to 1, 2 or 5 times a power of ten (the cartographer's contour
// intervals).
double row_interval_for(double scale, double spacing, double slope);

// Stretches the field's tone over the whole range: the 2nd percentile of the tones of
// the pixels steeper than `min_slope` goes to 0, the 98th to 1, linearly, clamped. The
// spacing's range (six to one) then spans the frame's own range of tone, whatever the
// light and the relief, so the hachures resolve the tone as finely as the spacing allows.
void stretch_tone(HachureField& field, double min_slope);

// The median slope of a field's terrain pixels that are steeper than `min_slope`
// (0 where none is).
double median_slope(const HachureField& field, double min_slope);

// The q-quantile (0 .. 1) of the slopes of the field's terrain pixels (0 where none is).
double slope_percentile(const HachureField& field, double q);

// Plan view (a map: terrain-inspect export --layers hachures): north up, `scale` metres a
// pixel, covering the mesh's extent. Pixel (u, v) has its corner at local (x0 + u scale,
// y0 - v scale), so the map's geotransform is (origin_x + x0, scale, 0, origin_y + y0, 0,
// -scale).
struct PlanView {
  double x0 = 0, y0 = 0, scale = 1;  // local coordinates of the top-left corner; metres a pixel
  int width = 0, height = 0;
};
// Throws terrain::Error for a scale <= 0, a map of more than 2^31 pixels, or one whose
// longer side is under kMinPlanSide pixels (nothing of the terrain would show).
inline constexpr double kMinPlanSide = 16;
PlanView plan_view(const terrain::GridMesh& mesh, double scale);
inline Eigen::Vector2d plan_to_local(const PlanView& p, const Eigen::Vector2f& px) {
  return {p.x0 + double(px.x()) * p.scale, p.y0 - double(px.y()) * p.scale};
}

// The field of a plan view: at each pixel centre, the PN surface above it (pn_point_above)
// gives the gradient; the fall line on the map is the gradient's opposite (v down is
// south), the slope its angle (true, exaggeration 1), the tone the shadow's (1 - n.l,
// `light` given) or the slope's (tan of the slope, black at 45 degrees). Parallel over rows.
HachureField plan_hachure_field(const terrain::GridMesh& mesh, const PlanView& plan,
                                const Eigen::Vector3d* light);

}  // namespace renderer
