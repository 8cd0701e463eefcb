#pragma once
// The renderer of the Creases paper (Appendix A) on a PN-triangle terrain, headless.
// Passes per frame (docs/terrain-render.md):
//   TFT  PN patches tessellated adaptively (about Style::pixels_per_edge pixels per edge,
//        so the level falls with distance; patches outside the view are culled by the
//        convex hull of their control points); toward-facing fragments (PN normal towards
//        the eye) write colour and the TOWARD depth.
//   AFT  the same surface, away-facing fragments, AWAY depth only.
//   DM   a compute pass scores every crease vertex and keeps the segments whose two ends
//        score >= 0 (a rejected vertex breaks the strip); they are drawn as screen-space
//        quads where they lie, their depth lifted towards the eye, wider where the flow is
//        larger; anti-aliased, hidden by samples smoothed along their strokes
//        (stroke_visibility.hpp).
//   SIL  Toward/Away (Mower 2015): a pixel with toward depth t < away depth a and an
//        8-neighbour whose toward depth is beyond a; anti-aliased, then the piece rule
//        (silhouette.hpp): pieces shorter than Style::silhouette_min_length fade out.
//   PEL  photic extremum lines (pel.hpp): compute passes for the per-vertex fields and the
//        zero-crossing segments (appended with an indirect draw command), drawn like the
//        creases.
//   EDGE object-space contour, boundary and crease edges of the mesh facets (McGuire &
//        Hughes 2004): a compute pass classifies every edge for the eye and appends the
//        drawn ones (indirect draw command); they are drawn as screen-space quads with
//        cheap or exact caps (Style::edge_caps), their depth lifted like the creases'.
//   LAY  composite of the chosen layers: surface, then PEL, crease, edge and silhouette
//        pixels that are not behind the nearest toward surface.
// Depth is reversed (1 at the near plane, 0 at infinity) where glClipControl exists.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/frame_params.hpp"
#include "renderer/core/hachures.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/timing.hpp"
#include "renderer/gl/gl_context.hpp"
#include "terrain/grid_mesh.hpp"

namespace renderer {

struct FrameResult {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width x height x 4, row 0 at the top
  FrameTimings timings;
  std::size_t crease_segments = 0;  // segments the DM pass drew (both ends accepted)
  std::size_t pel_segments = 0;     // segments the PEL pass drew
  std::size_t edges = 0;            // object-space edges the EDGE pass drew
  std::size_t patches = 0;  // surface patches drawn (the mesh's faces, fewer with levels of detail)
  // The creases' level the DM pass drew (select_crease_level): 0 the creases as given, l > 0
  // coarser_crease_levels(creases)[l - 1], whose segments the CPU references then follow.
  int crease_level = 0;
  View view;  // the view used (for projection by callers)
};

// Per-pixel buffers of the last frame, for tests and diagnostics (row 0 at the top).
struct FrameBuffers {
  std::vector<float> toward_depth, away_depth;         // window depth (clear: far)
  std::vector<std::uint8_t> silhouette, crease, edge;  // 0/1 masks before compositing
  std::vector<std::uint8_t>
      silhouette_opacity;  // what LAY draws of the silhouettes (0..255; the piece rule)
  std::vector<std::uint8_t> surface_rgba;  // the shaded surface TFT drew (RGBA; where toward_depth
                                           // shows surface; elsewhere transparent black or,
                                           // CompositePass::surface_is_base, the opaque background)
  // The drawn surface's unit normal (4 floats a pixel, the 4th 1 on the terrain), when asked
  // for and TFT writes it (hachures, formulated silhouettes); else empty.
  std::vector<float> surface_normal;
  // Adjacency silhouettes only: the triangle ID per pixel (0 none, 0xFFFFFFFF unknown) and
  // the triangle list (9 floats per ID from 1: three vertices, exaggerated mesh frame).
  std::vector<std::uint32_t> triangle_id;
  std::vector<float> triangles;
};

class TerrainRenderer {
 public:
  // Uploads the mesh (positions, normals, faces) and, when given, the creases. The
  // context must stay alive and current while the renderer is used, and the mesh too:
  // with levels of detail (Style::lod_error, renderer/core/lod.hpp) and neither the PEL nor the
  // edge layer, only the vertices a frame draws go to the GPU, from `mesh` at each frame
  // whose levels change. `levels`: the mesh's levels of detail when already made (the
  // mesh pyramid's, or another renderer's: LodHierarchy), else they are built here; so
  // too `crease_levels`, the creases' coarser levels (coarser_crease_levels(*creases)).
  TerrainRenderer(const GlContext& context, const terrain::GridMesh& mesh,
                  const CreaseGeometry* creases, int width, int height, const Layers& layers,
                  const Style& style, std::shared_ptr<const LodHierarchy> levels = nullptr,
                  std::shared_ptr<const std::vector<CreaseLevel>> crease_levels = nullptr);
  ~TerrainRenderer();
  TerrainRenderer(const TerrainRenderer&) = delete;
  TerrainRenderer& operator=(const TerrainRenderer&) = delete;

  FrameResult render(const FrameParams& frame);
  // With `normals`, FrameBuffers::surface_normal too (16 bytes a pixel; the tests').
  FrameBuffers read_buffers(bool normals = false) const;
  // The hachures' field of the last frame (`view`: its FrameResult::view), computed on the
  // GPU (hachure_field.comp.glsl) from TFT's depth and the normals it drew; the tone the
  // light's (light_tone) or the slope's. The renderer must have been made with the hachures
  // layer. renderer::hachure_field (hachures.hpp) is the CPU reference.
  HachureField hachure_field(const View& view, bool light_tone) const;

  // The scene's bounding box in the exaggerated local frame, and its world origin.
  const Box& box() const;
  Eigen::Vector3d origin() const;

  // GLSL PN evaluation read back through transform feedback: every patch of `faces`
  // tessellated at the uniform `level`, each generated vertex as
  // (face, b1, b2, b3, position xyz, normal xyz) in the mesh's local frame (exaggeration 1).
  struct PnSample {
    std::uint32_t face;
    float b1, b2, b3;
    Eigen::Vector3f position, normal;
  };
  static_assert(sizeof(PnSample) == 40);
  std::vector<PnSample> capture_pn(const std::vector<std::uint32_t>& faces, int level);

  // The PEL segments of the last frame: two points (mesh local frame) and the face each.
  struct PelSegmentOut {
    Eigen::Vector3f a, b;
    std::uint32_t face;
    float opacity;  // the piece rule's (1 without it)
  };
  std::vector<PelSegmentOut> read_pels() const;

  // The object-space edges of the last frame: the kinds of every edge of mesh_edges()
  // (EdgeKind bits, feature_edges.hpp) and the drawn edges (v0, v1, and the join vertex at
  // each end, MeshEdge::kNoVertex where there is none).
  struct EdgesOut {
    std::vector<std::uint32_t> kinds;
    std::vector<std::array<std::uint32_t, 4>> drawn;
  };
  EdgesOut read_edges() const;
  // Anti-aliased creases: every segment's samples of the last frame, as the DM pass found
  // which of them show (stroke_visibility.hpp; n = 0 where it was not drawn). Empty with
  // pixel-exact lines or without creases.
  std::vector<SegmentSamples> read_crease_samples() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace renderer
