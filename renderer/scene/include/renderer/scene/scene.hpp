#pragma once
// What terrain-render and terrain-view draw from: a mesh file and, optionally, a drainage
// database's creases under it, loaded once (load_scene); and the line statistics of a
// drawn frame (frame_line_stats). Built as its own library (terrain::renderer_scene),
// since it reads .dv files through libdrainage, which the GL renderer itself does not need.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/crease.hpp"
#include "renderer/core/hachures.hpp"
#include "renderer/core/line_stats.hpp"
#include "renderer/core/ridges.hpp"
#include "renderer/core/vector_art.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "terrain/drainage_links.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct Scene {
  terrain::GridMesh mesh;
  // The mesh's levels of detail (renderer/core/lod.hpp): its pyramid's when the mesh was read
  // from one, else made by scene_levels on first use; shared by every renderer of it.
  std::shared_ptr<const LodHierarchy> levels;
  std::string mesh_source;  // how the mesh was read: "MESH.tpyr (its pyramid)", or why not
  // The level of the mesh's pyramid that `mesh` holds: 0, the mesh itself, unless
  // load_scene's memory bound made it read a coarser one (then levels->base too).
  int mesh_level = 0;
  // The mesh's own levels (its pyramid's, base 0, every block) when the mesh was read from
  // its pyramid: what hold_views plans on while a coarser level or a window
  // of it is held.
  std::shared_ptr<const LodHierarchy> mesh_levels;
  // The digest of the mesh and pyramid read (terrain::PyramidMesh): a later read of the
  // pyramid must find the same pair.
  std::optional<std::uint64_t> digest;
  std::optional<CreaseGeometry> creases;  // with a database
  SegmentTraits traits;                   // of the creases' segments
  SegmentChains chains;                   // the strokes they follow, as the DM pass holds them
  // Their coarser levels (coarser_crease_levels), shared with every renderer of them
  // (TerrainRenderer's last argument), and each one's traits: a frame drawn at one
  // (FrameResult::crease_level) is followed on its segments (frame_creases).
  std::shared_ptr<const std::vector<CreaseLevel>> crease_levels;
  std::vector<SegmentTraits> crease_level_traits;
  // With a database: its ridge lines between the catchments of branches draining at least
  // kRidgeChannelArea, parting basins of at least kRidgeMinBasin (a frame selects further).
  std::vector<SceneRidge> ridges;
  std::vector<std::string> warnings;             // "'x.dv': ..." for the tool to print
  double mesh_seconds = 0, creases_seconds = 0;  // creases_seconds includes ridges_seconds
  double ridges_seconds = 0;
  // What hold_views needs of a scene read at a coarser level: the creases wait for it.
  struct Deferred {
    std::string mesh_path, dv_path;
    CreaseRules rules;
    std::uint64_t vertex_bytes = 0;
  };
  std::optional<Deferred> deferred;
  std::optional<Deferred>
      bounded;  // the same, kept after the first read: what hold_views reads again
};

// Reads the mesh and, when `dv_path` is not empty, the database's points under it (a large
// tiled .dv is read block by block) and builds their creases with `rules`.
// The mesh comes from its pyramid when one is current beside it (terrain::read_mesh_via_pyramid:
// the tiles read in parallel, the levels of detail with them), else from the PLY.
//
// `vertex_bytes` (0: no bound) bounds what the mesh's vertices take (24 bytes each, the
// position and the normal): when the mesh takes more and has a current pyramid, the mesh
// read is the finest level of the pyramid within a quarter of the bound, a preview to
// resolve the view on (the automatic view and exaggeration), and the creases wait for
// hold_views.
Scene load_scene(const std::string& mesh_path, const std::string& dv_path, const CreaseRules& rules,
                 std::uint64_t vertex_bytes = 0);

// What a scene read under load_scene's memory bound holds for the views of `cameras`
// (Scene::deferred, Scene::bounded; a scene read whole holds everything: nothing to do).
// The level read is the finest that any block of the views is drawn at (select_lod with the
// style's bound: what the frame draws, unchanged) or, when that takes more than the bound,
// the finest within it (the nearest blocks then drawn coarser; every level with
// --lod-error 0); the creases are built on it. With a window, only the blocks any view
// draws (nearest_depth) and one more around them are read (terrain::read_mesh_via_pyramid's
// part, LodHierarchy::window): what lies outside cannot show, since the terrain that hides a
// point of the view lies between it and the eye, in the view too. The scene's box stays
// the whole mesh's (MeshHolding), and with it the view, the page scale and the strokes.
// Returns a line for -v, empty when nothing was read.
enum class HoldFor {
  Frames,      // a batch's frames, after the preview: the whole mesh
  Frame,       // one frame, after the preview (terrain-render frame, the viewer's start): a window
  StillView,   // the viewer before a full frame: as Frame, read only when what is held does not
               // hold the blocks in view at that level (or finer, where that is the finest drawn)
  MovingView,  // the viewer before a cheap frame: the whole mesh as Frames reads it, once,
               // when the view first leaves a window held (the terrain never shown cut)
};
std::string hold_views(Scene& scene, const std::vector<Camera>& cameras, int width, int height,
                       const Style& style, HoldFor what);

// The scene's levels of detail for `style`: none without levels of detail
// (Style::lod_error 0), else Scene::levels, made here once when the mesh brought none.
std::shared_ptr<const LodHierarchy> scene_levels(Scene& scene, const Style& style);

// The creases the frame `res` drew: the scene's own, or the coarser level the DM pass drew
// (FrameResult::crease_level). The CPU references below follow its segments; #S is theirs.
struct SceneCreases {
  const CreaseGeometry& geometry;
  const SegmentTraits& traits;
  const SegmentChains& chains;
};
SceneCreases frame_creases(const Scene& scene, const FrameResult& res);

// Each crease segment's opacity in the frame `res` (#S): what the DM pass draws, as the
// GL-free score, fade and stroke rule give it (segment_opacity).
std::vector<float> frame_opacity(const Scene& scene, const TerrainRenderer& r,
                                 const FrameResult& res, const FrameParams& fp, const Style& style);

// The creases one frame draws (what the DM pass accepts, as the GL-free score gives it),
// with each segment's pixels left after hidden-line removal (its own line against the
// toward depth of `buffers`, the frame's read_buffers()).
struct FrameLines {
  std::vector<float> drawn;
  std::vector<double> pixels;
};
FrameLines frame_lines(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                       const FrameBuffers& buffers, const FrameParams& fp, const Style& style);

// A frame's lines on the scene's own (fine) segments, what a flight compares from frame to
// frame whatever level each drew (flicker): a merged segment's opacity on each fine
// segment it replaces, its pixels shared among them by their lengths. As given at level 0.
FrameLines fine_lines(const Scene& scene, const FrameResult& res, FrameLines lines);

// The line art of the frame `res` just drawn by `r` (its buffers: r.read_buffers()), for
// the SVG / PDF writer (vector_file.hpp): the layers the composite draws, bottom up (PELs,
// creases, edges, silhouettes), from the strokes, samples, segments and masks the frame
// drew; the crease samples are the DM pass's own (read_crease_samples; the CPU reference
// with pixel-exact lines).
VectorArt frame_vector_art(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                           const FrameBuffers& buffers, const FrameParams& fp, const Style& style,
                           const Layers& layers, VectorUnderlay underlay);

// The hachures of the frame `res` (renderer/core/hachures.hpp): the fall-line field of
// its toward depth (the light's tone with Style::hachure_light_tone, else the slope's),
// traced at Style::hachure_spacing, stopped at the crease and silhouette pixels the frame
// drew and at the lines of `over` drawn over it (the ridge lines, ridge_layer's: they hang
// from the crest, which stands clear of them; the heavier silhouettes), in rows with
// Style::hachure_rows (form lines at row_interval_for the page's scale). The renderer `r` drew
// `res` (the field is its GPU's).
struct TracedHachures {
  HachureField field;
  HachureRule rule;
  std::vector<Hachure> hachures;
};
TracedHachures trace_frame_hachures(const Scene& scene, const TerrainRenderer& r,
                                    const FrameResult& res, const FrameBuffers& buffers,
                                    const Style& style,
                                    const std::vector<const VectorLayer*>& over = {});
// The ridge lines the frame `res` draws (Layers::ridges, Style::ridge_*): the scene's ridges
// whose smaller basin drains at least ridge_min_area x sqrt(page scale / 10) m^2 and that rise
// at least ridge_min_relief of the scene's relief above its outlet, and at least
// kRidgeMinPixels long in plan at the page's scale (no stubs), their hidden parts
// removed against the frame's toward depth (segment_paths), one path per visible run.
VectorLayer ridge_layer(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                        const FrameBuffers& buffers, const Style& style);

// The lines a frame draws on the CPU over the GL picture, made once for the PNG, the vector
// files and the viewer: the ridge lines, the silhouettes that hide most drawn heavier
// (silhouette_layer's paths wider than the composite's band), then the hachures stopped at
// both (traced, and as one path per hachure). Each is empty where `layers` and `style` do
// not draw it (the ridges also without a database).
// `outline`: with the silhouettes layer, on a mesh with holes (docs/dem2mesh.md, "No-data"),
// the data's outline where it shows (a coast, a catchment's divide): every edge between a
// face drawn and one outside the data, hidden parts left out, in the silhouettes' colour.
struct FrameOverlays {
  std::optional<TracedHachures> traced;
  std::optional<VectorLayer> hachures, ridges, silhouettes, outline;
  bool any() const { return hachures || ridges || silhouettes || outline; }
};
// Whether a frame of `layers` over `scene` has any (it needs the frame's buffers).
bool draws_overlays(const Scene& scene, const Layers& layers, const Style& style);
FrameOverlays frame_overlays(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                             const FrameBuffers& buffers, const Style& style, const Layers& layers);
// The silhouettes of the frame `res` as lines (silhouette_paths): the composite's band
// wide, and wider by Style::silhouette_depth_width times the depth they hide
// (silhouette_hidden_share of the frame's toward depth) when anti-aliased.
VectorLayer silhouette_layer(const FrameResult& res, const FrameBuffers& buffers,
                             const Style& style);
// Draws them over `rgba` (width x height): the hachures, the heavier silhouettes, the ridges on
// top.
void draw_overlays(const FrameOverlays& o, int width, int height, std::vector<std::uint8_t>& rgba);

// --line-stats of one frame: the creases' figures and, with the silhouettes layer, the
// silhouettes'.
struct FrameStats {
  FrameLines lines;
  LineStats creases;
  std::optional<SilhouetteStats> silhouettes;
  std::optional<HachureStats> hachures;  // with the hachures layer
  Coherence hachure_coherence;           // against the previous frame's hachures, when given
};
// `traced`: the frame's hachures as write_frame_files traced them (else traced here);
// `previous_hachures`: the last frame's HachureStats::surface (a flight's frames in turn),
// for hachure_coherence.
FrameStats frame_line_stats(const Scene& scene, const TerrainRenderer& r, const FrameResult& res,
                            const FrameParams& fp, const Style& style, const Layers& layers,
                            const TracedHachures* traced = nullptr,
                            const std::vector<Eigen::Vector3f>* previous_hachures = nullptr);
// The figures as `terrain-render frame --line-stats` prints them, one "name: value" a line.
std::string line_stats_text(const FrameStats& s);
// batch's line_stats.csv: its header line and frame i's row.
std::string line_stats_csv_header();
std::string line_stats_csv_row(std::size_t i, const FrameStats& s);

}  // namespace renderer
