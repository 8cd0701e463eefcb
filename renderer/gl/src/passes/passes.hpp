#pragma once
// The passes of a frame (docs/terrain-render.md), one object each, owning its GL objects
// and its GL timer; TerrainRenderer (terrain_renderer.cpp) builds them and runs them in
// order: TFT, AFT, DM, PEL, EDGE, SIL, LAY. Internal to the renderer library.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/frame_params.hpp"
#include "renderer/core/hachures.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/core/silhouette.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/timing.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/gl_objects.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer::passes {

// What the passes share: the mesh on the GPU (positions, normals, patches), the surface
// program, the frame's uniform buffer, the image size and depth convention, and the
// surface targets later passes read (toward colour and depth, away depth).
// Patches per draw call. llvmpipe (Mesa 22.3) drops patches from a draw call that
// tessellates into more than 65536 triangles: a 50 m mesh lost bands of patches at
// 4961 x 3508 (and at 1280 x 720 with 1.5 px per edge). At the largest level the renderer
// uses (32: 1024 triangles a patch) 64 patches stay within it (116 did not).
inline constexpr std::size_t kPatchesPerDraw = TR_PATCHES_PER_DRAW;
static_assert(kPatchesPerDraw == 65536 / (32 * 32));

struct SceneGpu {
  // With `normals`, TFT also writes the drawn surface's normal (surface_normal, RGBA32F):
  // the hachures' field reads it. With `all_patches`, index_buf holds the mesh's faces;
  // without (levels of detail), none until set_patches. Without `resident`, pos_buf and
  // nrm_buf hold no vertex until set_lod_mesh puts the drawn ones there (levels of detail
  // without the PEL and edge layers, which read the whole mesh).
  SceneGpu(const terrain::GridMesh& mesh, int width, int height, bool reversed,
           bool normals = false, bool all_patches = true, bool resident = true);
  int width, height;
  bool reversed;  // depth 1 at the near plane, 0 at infinity (glClipControl)
  terrain::GridTopology topo;
  GlObject pos_buf, nrm_buf, index_buf, vao, empty_vao, ubo, surface_prog;
  // The patches drawn: the mesh's faces, or (levels of detail, renderer/core/lod.hpp) fewer,
  // set by set_patches into index_buf.
  std::size_t n_patches = 0, patch_capacity = 0;
  // The leading patches that may face away (renderer::facing_blocks): AFT looks at those.
  std::size_t n_away_patches = 0;
  // index_buf grows as needed; `may_face_away`: n_away_patches (all when larger).
  void set_patches(const std::vector<std::uint32_t>& indices, std::size_t may_face_away = SIZE_MAX);
  // The vertices drawn, `m.vertices` of `mesh`, into pos_buf and nrm_buf (they grow as
  // needed), and m.patches as the patches: the scene made without `resident`.
  void set_lod_mesh(const LodMesh& m, const terrain::GridMesh& mesh);
  std::size_t vertex_capacity = 0;
  GlObject surface_colour, toward_depth, away_depth;
  GlObject surface_normal;  // empty unless normals were asked for
  // AFT's marks (r8, one texel per TR_SILHOUETTE_TILE tile): 1 in each tile that holds an
  // away depth; SIL's Toward/Away test runs only beside them.
  GlObject away_tiles;

  float clear_depth() const { return reversed ? 0.0f : 1.0f; }
  void depth_state() const;
  // The PN patches of the mesh with the surface program; mode 0 toward-facing fragments
  // (TFT), 1 away-facing (AFT).
  void draw_surface(int mode) const;
  // The same patches with another program (mode 2: no facing cull).
  void draw_patches(const GlObject& program, int mode) const;
  // Patches listed in `indices` (after a 16-byte counter) by the indirect draws `draws`
  // (n_draws of at most kPatchesPerDraw patches each; surface_cull.comp.glsl).
  void draw_patch_list(const GlObject& program, int mode, const GlObject& indices,
                       const GlObject& draws, std::size_t n_draws) const;
  // The image in TR_SILHOUETTE_TILE tiles: columns, rows, and an r8 texture of one texel
  // per tile (the marks of draw_near_tiles).
  int tiles_x() const { return (width + TR_SILHOUETTE_TILE - 1) / TR_SILHOUETTE_TILE; }
  int tiles_y() const { return (height + TR_SILHOUETTE_TILE - 1) / TR_SILHOUETTE_TILE; }
  std::size_t tile_count() const { return std::size_t(tiles_x()) * std::size_t(tiles_y()); }
  GlObject make_tile_texture() const;
  // Draws with `program` (its vertex shader tile_rects.vert.glsl) only the pixels within
  // `reach` pixels of a TR_SILHOUETTE_TILE tile that `marks` (r8, one texel per tile)
  // marks, or within reach_x columns and reach_y rows: tile_rects.comp.glsl lists their
  // rectangles and the draw command.
  void draw_near_tiles(const GlObject& marks, int reach, const GlObject& program) const {
    draw_near_tiles(marks, reach, reach, program);
  }
  void draw_near_tiles(const GlObject& marks, int reach_x, int reach_y,
                       const GlObject& program) const;
  GlObject tile_rects_buf, tile_rects_prog;
};

// A framebuffer over the given colour and depth textures (either may be null) and, given,
// a second colour attachment (fragment output 1).
GlObject make_framebuffer(const GlObject* colour, const GlObject* depth,
                          const GlObject* colour1 = nullptr);

// The coverage (r8) and depth targets of a line layer (creases, PELs, edges) and their
// framebuffer; clear() empties them (coverage 0, depth far). Anti-aliased lines keep no
// depth (draw_indirect), and have no depth target.
struct LineTarget {
  explicit LineTarget(const SceneGpu& scene, bool antialias = false);
  void clear(const SceneGpu& scene) const;
  // The segments of an indirect draw command (6 vertices each, no vertex attributes) drawn
  // with `program` into the target: pixel-exact, depth-tested; anti-aliased, coverage
  // blended with MAX and no depth test (the program reads the toward depth, bound here).
  void draw_indirect(const SceneGpu& scene, const GlObject& program, const GlObject& command) const;
  GlObject colour, depth, fbo;
  bool antialias;
};

// Segments an indirect draw command (vertex count, instances, first, base) draws: two
// triangles, 6 vertices, per segment.
std::size_t indirect_segments(const GlObject& command);

// The inputs of one frame.
struct FrameInputs {
  const FrameParams& frame;
  const View& view;
  Eigen::Vector3d light;  // unit vector towards the light, mesh frame
};

class PassBase {
 public:
  explicit PassBase(Pass id) : id_(id), query_(GlKind::Query, GL_TIME_ELAPSED) {}
  virtual ~PassBase() = default;
  PassBase(const PassBase&) = delete;
  PassBase& operator=(const PassBase&) = delete;
  Pass id() const { return id_; }
  // Runs the pass inside its GL timer query and waits for it (glFinish): the wall time
  // goes to t.wall_ms.
  void run(const FrameInputs& in, FrameTimings& t);
  // The GL timer of the last run into t.gpu_ms (after every pass of the frame ran).
  void read_timer(FrameTimings& t) const;

 protected:
  virtual void execute(const FrameInputs& in) = 0;

 private:
  Pass id_;
  GlObject query_;
};

// A list of patches that a compute pass writes (patch_list.glsl) and draw_patch_list
// draws: a counter and the patches' indices, and draws of kPatchesPerDraw patches each.
struct PatchList {
  GlObject indices, draws;
  std::size_t capacity = 0;  // patches they hold; they grow with the scene's
  // Room for the scene's patches, the list emptied, bound where patch_list.glsl writes.
  void reset(const SceneGpu& scene);
  // Draws the listed patches with `program` in `mode` (after the compute pass's barrier).
  void draw(const SceneGpu& scene, const GlObject& program, int mode) const;
};

// TFT: shaded colour and toward depth. With `flat_patches` the patches in view are split
// first (surface_split.comp.glsl): those that tessellate into their own flat triangle are
// drawn as triangles (surface_flat.vert.glsl), the others tessellated.
inline constexpr std::size_t kMaxSplitPatches = std::size_t(4)
                                                << 20;  // TFT splits frames of at most 4 M patches
class TowardPass : public PassBase {
 public:
  // `clear`: the colour where no surface is drawn (RGBA).
  TowardPass(const SceneGpu& scene, bool flat_patches, const Eigen::Vector4f& clear);

 private:
  void execute(const FrameInputs&) override;
  const SceneGpu& s_;
  bool flat_patches_;
  Eigen::Vector4f clear_;
  GlObject fbo_;
  GlObject split_prog_, flat_prog_;
  PatchList tess_;  // the patches tessellated
  GlObject flat_;   // the flat ones (surface_split.comp.glsl's FlatPatches)
  std::size_t flat_capacity_ = 0;
};

// AFT: away depth and the away tiles (only when silhouettes are drawn; cleared always).
class AwayPass : public PassBase {
 public:
  AwayPass(const SceneGpu& scene, bool enabled);

 private:
  void execute(const FrameInputs&) override;
  const SceneGpu& s_;
  bool enabled_;
  GlObject fbo_;
  GlObject cull_prog_, prog_;  // prog_: the surface program that marks the away tiles
  PatchList patches_;          // the patches that may face away in view (surface_cull.comp.glsl)
};

// DM: crease vertices scored, segments selected (indirect draw), drawn as quads.
class CreasePass : public PassBase {
 public:
  // `creases` may be null or empty: the pass then only clears its targets. With `merged`,
  // it holds the coarser levels of the creases too, one of which each frame draws
  // (set_level): `levels` (coarser_crease_levels(*creases)), made here when null.
  CreasePass(const SceneGpu& scene, const CreaseGeometry* creases, bool enabled, bool antialias,
             std::shared_ptr<const std::vector<CreaseLevel>> levels, bool merged);
  bool active() const { return enabled_ && n_segments() > 0; }
  std::size_t segments_drawn() const;  // of the last frame
  // The level the next frame draws: 0 the creases as given, l > 0 coarser_crease_levels' l - 1.
  void set_level(int level) { level_ = level; }
  int level() const { return level_; }
  // Each coarser level's CreaseLevel::error_metres (select_crease_level).
  const std::vector<double>& level_errors() const { return errors_; }
  std::size_t n_segments() const {
    return levels_.empty() ? 0 : levels_[std::size_t(level_)].n_segments;
  }
  std::size_t n_vertices() const {
    return levels_.empty() ? 0 : levels_[std::size_t(level_)].n_vertices;
  }
  const GlObject& colour() const { return target_.colour; }
  const GlObject& depth() const { return target_.depth; }
  // Anti-aliased lines: every segment's samples of the last frame (stroke_visibility.hpp;
  // n = 0 where it was not drawn). Empty otherwise.
  std::vector<SegmentSamples> read_samples() const;
  // 1 in each TR_SILHOUETTE_TILE tile a crease fragment of the last frame covers (r8).
  const GlObject& tiles() const { return tiles_; }

 private:
  void execute(const FrameInputs&) override;
  struct Level {  // what the GPU holds of one level
    std::size_t n_vertices = 0, n_segments = 0;
    GlObject cv, seg, chain;
  };
  Level upload(const CreaseGeometry& creases, const SegmentChains& chains) const;
  const SceneGpu& s_;
  bool enabled_, antialias_;
  std::vector<Level> levels_;  // the creases as given, then the coarser levels
  std::vector<double> errors_;
  int level_ = 0;
  GlObject score_buf_, opacity_buf_, cmd_buf_, selected_buf_,
      samples_buf_;  // sized for level 0, the largest
  GlObject score_prog_, bridge_prog_, select_prog_, draw_prog_, visibility_prog_;
  GlObject tiles_;
  LineTarget target_;
};

// PEL: per-vertex fields, zero-crossing segments (indirect draw), drawn as quads.
class PelPass : public PassBase {
 public:
  // Enabled: the mesh must carry its Voronoi weights. With anti-aliased lines, `smooth`
  // iterations smooth the lines (renderer::smooth_pels), then, piece_min_m > 0, the piece
  // rule (pel_pieces.comp.glsl, renderer::pel_piece_opacity) gives each segment the
  // opacity of its piece's length against it.
  PelPass(const SceneGpu& scene, const terrain::GridMesh& mesh, bool enabled, double width,
          bool antialias, double piece_min_m, int smooth);
  bool active() const { return enabled_; }
  std::size_t segments_drawn() const;
  // The segments of the last frame: 8 floats each (a xyz, face bits, b xyz, opacity).
  std::vector<float> read_segments() const;
  const GlObject& colour() const { return target_.colour; }
  const GlObject& depth() const { return target_.depth; }

 private:
  void execute(const FrameInputs&) override;
  void pieces() const;
  const SceneGpu& s_;
  bool enabled_;
  double width_, piece_min_m_;
  int smooth_;
  GlObject corner_buf_, varea_buf_, tangent_buf_, field_buf_, maxm_buf_, cmd_buf_, seg_buf_;
  GlObject face_seg_buf_, labels_buf_, sizes_buf_,
      smoothed_buf_;  // the piece rule's and the smoothing's
  GlObject field_prog_, extract_prog_, draw_prog_, pieces_prog_;
  LineTarget target_;
};

// EDGE: object-space contour, boundary and crease edges of the mesh (classified per frame
// in a compute pass, appended, one indirect draw of quads with the chosen caps).
class EdgePass : public PassBase {
 public:
  EdgePass(const SceneGpu& scene, bool enabled, const Style& style);
  bool active() const { return enabled_; }
  std::size_t edges_drawn() const;  // of the last frame
  // Of the last frame: the kinds of every edge (mesh_edges() order; EdgeKind bits), and the
  // drawn edges (v0, v1, join vertex at v0, at v1).
  std::vector<std::uint32_t> read_kinds() const;
  std::vector<std::array<std::uint32_t, 4>> read_drawn() const;
  const GlObject& colour() const { return target_.colour; }
  const GlObject& depth() const { return target_.depth; }

 private:
  void execute(const FrameInputs&) override;
  const SceneGpu& s_;
  bool enabled_;
  Style style_;
  std::size_t n_edges_ = 0;
  GlObject edge_buf_, kinds_buf_, slots_buf_, cmd_buf_, list_buf_, classify_prog_, draw_prog_;
  LineTarget target_;
};

// Adjacency silhouettes, first pass (in the AFT slot, which the Adjacency method does not
// need): the nearest tessellated triangle's ID per pixel and the list of triangles.
class TriangleIdPass : public PassBase {
 public:
  TriangleIdPass(const SceneGpu& scene, bool enabled, std::size_t capacity);
  const GlObject& ids() const { return ids_; }
  const GlObject& depth() const { return depth_; }
  const GlObject& triangles() const { return triangles_; }
  std::size_t triangles_drawn() const;  // of the last frame (may exceed the capacity)
  std::size_t capacity() const { return capacity_; }

 private:
  void execute(const FrameInputs&) override;
  const SceneGpu& s_;
  bool enabled_;
  std::size_t capacity_;
  GlObject ids_, depth_, fbo_, triangles_, prog_;
};

// SIL: Toward/Away silhouettes from the toward and away depths, or, given `ids`, the
// Adjacency method over the triangle IDs (vertices closer than `tolerance` are one). With
// piece_min_px > 0 (anti-aliased lines), then the piece rule (silhouette_pieces.comp.glsl,
// renderer::silhouette_piece_opacity): each pixel's opacity from the size of its piece.
class SilhouettePass : public PassBase {
 public:
  // With `style.formulated` and without `ids` (Toward/Away; the scene then made with
  // normals), the formulated silhouettes (formulated.frag.glsl) first, into the same mask.
  SilhouettePass(const SceneGpu& scene, bool enabled, double piece_min_px, const Style& style,
                 const TriangleIdPass* ids = nullptr, double tolerance = 0,
                 const Eigen::Vector4f& extent = Eigen::Vector4f::Zero());
  // The silhouette pixels (0/1), before the piece rule.
  const GlObject& mask() const { return mask_; }
  // What LAY draws: each pixel's opacity (the mask itself without the piece rule).
  const GlObject& opacity() const { return piece_min_px_ > 0 ? opacity_ : mask_; }
  // 1 in each tile of TR_SILHOUETTE_TILE^2 pixels that holds a silhouette pixel.
  const GlObject& tiles() const { return tiles_; }
  // Mesa llvmpipe reports a meaningless time for the first GL_TIME_ELAPSED query of a
  // context that has drawn nothing yet: one small timed draw first.
  void warm_up_timer() const;

 private:
  void execute(const FrameInputs&) override;
  void draw(double pixel_angle, const FormulatedView& formulated) const;
  void draw_formulated(const FormulatedView& f) const;
  void clear_pieces() const;
  void pieces() const;
  const SceneGpu& s_;
  bool enabled_;
  double piece_min_px_;
  const TriangleIdPass* ids_;
  double tolerance_;
  Eigen::Vector4f extent_;  // the mesh's local extent: xmin, ymin, xmax, ymax
  GlObject mask_, fbo_, prog_, tiles_;
  bool formulated_ = false;
  double formulated_altitude_ = 0, formulated_strength_ = 0;
  GlObject formulated_prog_, facing_prog_, facing_,
      facing_fbo_;                                  // facing_: formulated_facing.frag.glsl's (r32f)
  GlObject formulated_classes_, formulated_tiles_;  // formulated_tiles.comp.glsl's classes, marks
  GlObject formulated_classes_prog_, formulated_tiles_prog_;
  GlObject opacity_, labels_, sizes_, list_, pieces_prog_;  // the piece rule (piece_min_px > 0)
};

// LAY: the composite of the chosen layers, surface first, lines not behind the surface.
// Where the surface TFT drew is the composite without lines (surface_is_base), it is
// copied, and the lines composited over it only where they are.
class CompositePass : public PassBase {
 public:
  // Whether the composite of a pixel without lines is TFT's colour as drawn over the
  // background (the shaded layer on an opaque frame, TFT's colour cleared to the
  // background; the creases the only lines besides the silhouettes).
  static bool surface_is_base(const Layers& layers, const Style& style);
  CompositePass(const SceneGpu& scene, const Layers& layers, const Style& style,
                const CreasePass& creases, const PelPass& pels, const EdgePass& edges,
                const SilhouettePass& silhouettes);
  const GlObject& colour() const { return colour_; }

 private:
  void execute(const FrameInputs&) override;
  std::string defines() const;  // the layers the frame does not draw, compiled out
  const SceneGpu& s_;
  Layers layers_;
  Style style_;
  const CreasePass& creases_;
  const PelPass& pels_;
  const EdgePass& edges_;
  const SilhouettePass& silhouettes_;
  bool copy_base_;
  GlObject colour_, fbo_, prog_, silhouettes_prog_, creases_prog_;
};

// HACH: the hachures' field of the last frame (hachure_pass.cpp), computed when asked for
// (TerrainRenderer::hachure_field), not in the timed sequence. The scene must have been made
// with `normals`.
class HachurePass {
 public:
  explicit HachurePass(const SceneGpu& scene);
  // The last frame's (`view`: its view); the tone the light's (`light_tone`) or the slope's.
  HachureField field(const View& view, bool light_tone);

 private:
  const SceneGpu& s_;
  GlObject prog_, buf_;  // built on the first field
};

}  // namespace renderer::passes
