#pragma once
// Drainage creases (Mower's Creases algorithm, docs/algorithms.md 9.1), GL-free: the geometry
// the DM pass draws and the score that selects it. The renderer's compute shader
// (crease_score.glsl) evaluates the same formula; these functions are its test reference.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/frame_params.hpp"
#include "renderer/core/viewpoint.hpp"
#include "terrain/drainage_links.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

// A drainage network (terrain::DrainageLinks, e.g. from a .dv) in a mesh's local frame.
struct CreaseGeometry {
  std::vector<Eigen::Vector3f> positions;  // #C crease vertices, on the PN surface (local)
  std::vector<std::uint32_t> source;     // #C the vertex's point in the network (row * cols + col)
  std::vector<Eigen::Vector3f> normals;  // #C unit PN normals of the mesh's surface there
  std::vector<float> flow;               // #C basin-normalized flow (fc), in [0, 1]
  // #C the share of its basin that drains through the vertex, a / T (crease_flow on the
  // linear scale, whatever the score's): the line's width grows with its square root, as a
  // river's width with the square root of its discharge (Leopold & Maddock 1953).
  std::vector<float> share;
  std::vector<float> area;  // #C the area draining through the vertex, m^2 (points x dx dy)
  std::vector<std::uint32_t> segments;  // 2 x #S: (vertex, its downstream vertex)
  // The median |z - PN surface z| over the network's points above the mesh (all of them,
  // not only the creases' vertices, whose channels conditioning moves), metres, as read: 0 up
  // to float rounding for a network sampled from this mesh.
  double median_surface_offset = 0;
  std::size_t n_segments() const { return segments.size() / 2; }
};

// Which drainage links become crease segments, and how their flow is normalized
// (docs/terrain-render.md, "Where creases are drawn").
struct CreaseRules {
  // A channel-initiation threshold as a contributing area (m^2): links whose point drains
  // less (accumulated points x the network's cell area, dx dy) are left out, so a network
  // sampled at 10 m and at 5 m starts its channels at the same place (0 keeps every link, as
  // the paper). The default is terrain-render's: 1 ha, 100 points at 10 m.
  double min_area = 1e4;
  // Channels, not flow down planes: links where the area draining through the point, over
  // the longest flow path to it from the divide (contributing_width), is narrower than this
  // (m; and than 2 network spacings) are left out. A D8 track down a plane gathers one cell
  // per cell it runs, so its width is the network's spacing however long it runs: with the
  // area threshold alone, planes draw fans of parallel tracks a kilometre long. A hollow or
  // a valley gathers from both sides. 0: off.
  double min_width = 30;
  // Links that run along the network grid's edge, within 2 samples of it, are left out: the
  // edge turns D8 flow along it (a channel that leaves the grid obliquely runs along its last
  // rows, its outlet on the edge), a line of the grid, not of the terrain. Off: kept.
  bool off_edge_runs = true;
  // Basins that drain off the grid (their pit on the grid's edge or beside no-data) are
  // pieces of larger basins the grid cannot see: their flow is normalized by at least
  // this share of the network's points, not by their own small total (edge basins larger
  // than that keep their own). 0: every basin by its own total, as the paper (fc =
  // accumulation / basin total).
  double edge_basin_min_share = 0.05;
  // fc on a log scale: ln(accumulated) / ln(the basin total above), 0 at a ridge point, 1 at
  // the pit. In a basin of a million points a tributary of a thousand has fc = 0.001 as a
  // share, so the score selects it by slope and light alone and draws pieces of it; on the
  // log scale it has 0.5, its line grows steadily downstream and joins its trunk, and a
  // network reads by orders of magnitude, as rivers are ranked on maps. Off: the share,
  // accumulated / total (the paper).
  bool log_flow = true;
  // On flat ground (a link that does not descend: resolved flats, filled depressions)
  // only the main path of each flat is kept: from where the flow leaves the flat,
  // upstream along the inflow of largest accumulation; the other parallel D8 paths across
  // the flat are left out. Off: every link, as the paper.
  bool one_line_per_flat = true;
  // Valleys: a branch of the network (from a channel head or a junction down to the next
  // junction) is left out where the mesh along it is not concave across the flow: the mean,
  // over its links, of the second difference of the mesh's heights across the link at
  // valley_width on either side, (z(+w) + z(-w) - 2 z) / w^2 (w = valley_width, at least the
  // mesh spacing), at most valley_curvature (1/m). A plane gives exactly 0 whatever way the
  // link runs, so flow down a plane or across a flat, which runs in parallel D8 tracks, is
  // left out; at 30 m and 0.0005 / m a valley's sides lie on average 0.45 m above its line.
  // Measured at 30 m rather than at the mesh's own spacing: the 10 m curvature of a dequantized
  // integer DEM is positive along most D8 tracks (they follow its small folds). Branches
  // draining at least river_share of their basin (main stems, which cross floodplains) are
  // kept. Off: every branch (the paper).
  bool valley_branches = true;
  double valley_curvature = 0.0005;
  double valley_width = 30;
  double river_share = 0.25;
  // Lines as a cartographer draws rivers, not D8 staircases: each crease vertex moves to the
  // Gaussian-weighted mean of the vertices along its line (smooth_crease_lines), sigma this
  // many mesh spacings. 0: the D8 polyline as it is (the paper). The default is terrain-render's.
  double smooth_spacings = 0.5;
  // ... and at least this many drainage samples: the staircase is the network's, one sample
  // sideways per jog, and a network as fine as the mesh (10 m on a 10 m mesh) smoothed over
  // half a mesh spacing keeps it.
  double smooth_min_samples = 1.5;
};

// Every valid drainage point with its D8 link to its downstream point as one segment (the
// branches of a .dv are exactly these links grouped by order), selected and normalized by
// `rules`. Positions are moved from the database's frame to the mesh's; normals are the PN
// normals of `mesh` above each vertex (pn_point_above; the vertex normal of the nearest
// mesh vertex where it has no answer); then the lines are smoothed (rules.smooth_spacings,
// smooth_crease_lines). Error when the database does not overlap the mesh or their CRSs
// differ.
CreaseGeometry build_crease_geometry(const terrain::GridMesh& mesh,
                                     const terrain::DrainageLinks& links,
                                     const CreaseRules& rules = {});

// D8 paths run in steps of 45 degrees: a channel across the grid at any other bearing is
// a staircase of straight and diagonal links. This moves x, y of every vertex on a
// segment to the Gaussian-weighted mean (sigma `sigma_samples` vertices) of the vertices
// along its line: downstream along its segment, upstream along the inflow of largest flow
// (segment_chains' rule), up to 2 sigma each way and the same number each way, so channel
// heads, outlets and the ends of lines stay where they are. z keeps the vertex's height
// above the PN surface of `mesh` (pn_point_above at the old and the new x, y) and the
// normal becomes the PN normal at the new point; a vertex whose new point is off the
// surface keeps its old one. Straight lines (along a row, a column or a diagonal) do not
// move. Segments, sources and flow are unchanged.
// sigma_samples is capped at kMaxSmoothSigma.
inline constexpr int kMaxSmoothSigma = 32;
void smooth_crease_lines(CreaseGeometry& g, const terrain::GridMesh& mesh, double sigma_samples);

// The basin-normalized flow of every point of `links` under `edge_basin_min_share` and
// `log_flow` (CreaseRules): a / T with a its accumulated points and T its basin's total, or
// max(T, share x the network's valid points) for a basin that drains off the grid; with
// log_flow ln(a) / ln(T) instead (1 where T is 1). links.flow when the share is 0 and the
// scale linear. #P values, 0 at invalid points.
std::vector<float> crease_flow(const terrain::DrainageLinks& links, double edge_basin_min_share,
                               bool log_flow = false);

// Whether each point's link is on flat ground (its downstream point is not lower) and is
// not the main path of its flat (CreaseRules::one_line_per_flat): #P flags, 1 = left out.
std::vector<std::uint8_t> off_main_flat_path(const terrain::DrainageLinks& links);

// The mean width (m) of the area draining through each point (CreaseRules::min_width): its
// contributing area over its longest flow path from the divide, its own cell included. A
// D8 track down a plane has the network's spacing. #P values, O(#P).
std::vector<float> contributing_width(const terrain::DrainageLinks& links);

// A warning (empty when none) when the network's sample extent differs from the mesh's
// by more than one network spacing on any side: it was made from another mesh (or a
// crop of it), so its creases will not follow this surface everywhere.
std::string coverage_warning(const terrain::GridMesh& mesh, const terrain::DrainageLinks& links);

// A warning (empty when none) when the crease vertices lie a median of more than
// kSurfaceOffsetShare of the mesh spacing off the mesh's PN surface
// (CreaseGeometry::median_surface_offset): the network was sampled from another surface
// (the terrain at another spacing, say), so its creases do not follow this surface's
// valleys, and sink into it or hover above it.
inline constexpr double kSurfaceOffsetShare = 0.02;
std::string surface_warning(const terrain::GridMesh& mesh, const CreaseGeometry& g);

// rs of one crease vertex (see CreaseScoreParams). `normal` and `light` are unit vectors in
// the exaggerated frame, `distance` is from the eye in that frame.
double crease_score(const Eigen::Vector3d& normal, double flow, const Eigen::Vector3d& light,
                    double distance, const CreaseScoreParams& params);

// The unit normal after scaling z by `exaggeration`: (nx, ny, nz / e) normalized.
Eigen::Vector3d exaggerate_normal(const Eigen::Vector3d& n, double exaggeration);

// How far the DM pass lifts crease vertices towards the eye for their depth test, metres
// (they are drawn where they lie; line_clip in common.glsl):
// style.crease_lift, or half the mesh spacing when it is negative (the default).
double crease_lift(const Style& style, const terrain::GridMesh& mesh);

// The score's distances for an eye: params as given when params.far_distance > 0 (near
// distance as given, 0 by default: the paper's rule); else near_distance from the eye to
// the nearest point of the scene's box lo..hi and far_distance to its farthest corner (all
// in the exaggerated local frame), so that rs_min rises across the scene, from its
// nearest to its farthest point, wherever the eye is. Orthographic (a map, one scale
// throughout): the term of the scene's middle everywhere, rs_min = min + (1 - min) k / 2
// (near and far a million box depths either side of the middle, Viewpoint::distance).
CreaseScoreParams resolve_distances(const CreaseScoreParams& params, const Eigen::Vector3d& lo,
                                    const Eigen::Vector3d& hi, const Viewpoint& viewer);

// Per segment, whether its two ends both score >= 0 seen from `viewer` (exaggerated local
// frame; a perspective eye converts) and light direction `light`: what the DM pass draws
// (#S flags).
std::vector<std::uint8_t> accepted_segments(const CreaseGeometry& g, const Viewpoint& viewer,
                                            const Eigen::Vector3d& light, double exaggeration,
                                            const CreaseScoreParams& params);
// The chains that strokes follow (#S each, kNoSegment where none): next[s] is the segment
// leaving s's downstream vertex; prev[s] the segment entering s's upstream vertex from the
// largest flow (ties: the lower index), the one a stroke continues from.
inline constexpr std::uint32_t kNoSegment = 0xFFFFFFFFu;
struct SegmentChains {
  std::vector<std::uint32_t> prev, next;
};
// With `drawn` (#S), only the segments with drawn[s] > 0 take part (the strokes a frame
// shows: crease_strokes); empty: every segment.
SegmentChains segment_chains(const CreaseGeometry& g, const std::vector<float>& drawn = {});

// Strokes, not dashes (Style::crease_bridge, crease_min_stroke; docs/terrain-render.md,
// "Strokes"), with `length` the segments' lengths (#S, metres): a segment left out whose
// chain has a drawn segment upstream (along prev) and downstream (along next), each
// within `bridge` of left-out segments, is drawn at the lower opacity of those two. Then
// a drawn run shorter than `min_length` is left out; the run of a segment is followed
// upstream along prev, and downstream along next while the next segment continues from
// this one, at most kStrokeReach segments each way. 0 turns a rule off. The DM pass runs
// the same rule (crease_bridge.comp.glsl, crease_select.comp.glsl).
inline constexpr int kStrokeReach = 64;  // TR_STROKE_REACH
struct StrokeRule {
  double bridge = 0;      // metres
  double min_length = 0;  // metres
  // The page's channel initiation (m^2): a vertex draining less than this scores -1 (is
  // not drawn), so channels begin further down on a smaller-scale page (Style::page_min_area).
  double min_area = 0;
};
std::vector<float> apply_stroke_rule(const SegmentChains& chains, const std::vector<float>& opacity,
                                     const std::vector<double>& length, const StrokeRule& rule);

// The stroke rule of a style in metres at a page scale (metres per pixel, page_scale):
// bridge = max(Style::crease_bridge, crease_bridge_px x scale), min_length likewise;
// min_area = Style::page_min_area x sqrt(scale / 10 m), Topfer's radical law (below). The
// mesh's spacing takes no part: a mesh of the same terrain at any spacing draws the same
// strokes at one camera.
inline constexpr double kPageAreaScale = 10.0;  // m a pixel at which page_min_area applies as it is
StrokeRule stroke_rule(const Style& style, double page_scale);

// Each segment's length in metres (local frame, before exaggeration). #S.
std::vector<double> segment_metres(const CreaseGeometry& g);

// Per segment, its opacity as the DM pass draws it (#S): 0 where it is not accepted (an end
// below rule.min_area scores -1); else min(score of its two ends) / fade clamped to 1, or 1
// when fade is 0 (Style::crease_fade); then `rule` (in metres) along segment_chains.
std::vector<float> segment_opacity(const CreaseGeometry& g, const Viewpoint& viewer,
                                   const Eigen::Vector3d& light, double exaggeration,
                                   const CreaseScoreParams& params, double fade,
                                   const StrokeRule& rule = {});
// Levels of detail for the creases (docs/terrain-render.md, "The creases' levels
// of detail"): a network sampled at 10 m drawn at 40 m a pixel has segments of a third of a
// pixel, and DM's cost follows them. A level merges the segments of each run (a path
// between its breaks: channel heads, junctions, outlets, where a vertex has not exactly one
// segment in and one out): from the run's first vertex, it keeps the farthest vertex within
// `step` segments whose dropped vertices all lie within `tolerance` (metres) of the segment
// to it, and so on down the run. Kept vertices keep their own positions, so every segment
// joins two vertices of the fine line and the strokes start, join and end where the fine
// ones do; straight runs merge `step` segments, bends fewer. A kept vertex is scored (its
// normal, flow and area) as the middle vertex of the run its leaving segment replaces, so
// that a merged segment is drawn where the middle of that run is: scored at its own upstream
// vertex, a segment that begins a channel would wait for that vertex to drain the page's
// area, and lines would begin up to a merged segment late. Shares (the widths) and sources
// stay the vertex's own. Segments in the order of the fine segment they begin with.
struct CreaseLevel {
  CreaseGeometry geometry;
  SegmentChains chains;                    // segment_chains(geometry)
  std::vector<std::uint32_t> first, last;  // #S the fine segments each one begins and ends with
  // Its error: the largest distance (metres, local frame) of a dropped vertex from the
  // segment that replaces it (at most the tolerance).
  double error_metres = 0;
  int step = 1;
};
CreaseLevel merge_crease_runs(const CreaseGeometry& g, int step, double tolerance);
// The levels a renderer holds: steps 2, 4, 8, ... up to kMaxCreaseStep, each with a
// tolerance of kCreaseTolerance x step x the median fine segment's length (1.5 m a step for
// a 10 m network), while a level has at most kCreaseLevelShrink of the previous level's
// segments (networks of short runs stop early).
inline constexpr int kMaxCreaseStep = 32;
inline constexpr double kCreaseTolerance = 0.125;
inline constexpr double kCreaseLevelShrink = 0.75;
std::vector<CreaseLevel> coarser_crease_levels(const CreaseGeometry& g);
// The level a frame draws: the coarsest (1 + its index in `error_metres`, the coarser
// levels' CreaseLevel::error_metres; 0 the fine creases) whose error spans at most bound_px
// pixels of `pixel_metres` (the pixel's size at the nearest surface in view; 0 or less: the
// fine creases).
int select_crease_level(const std::vector<double>& error_metres, double pixel_metres,
                        double bound_px);
// The renderer's bound: kCreaseErrorPerLod x Style::lod_error pixels, half a pixel at the
// default 0.25: a line within half a pixel of the fine one, half a 1 px line's width.
inline constexpr double kCreaseErrorPerLod = 2.0;

// How many (accepted_segments).
std::size_t count_accepted_segments(const CreaseGeometry& g, const Viewpoint& viewer,
                                    const Eigen::Vector3d& light, double exaggeration,
                                    const CreaseScoreParams& params);

}  // namespace renderer
