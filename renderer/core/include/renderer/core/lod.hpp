#pragma once
// Levels of detail for the PN surface (docs/terrain-render.md, "Levels of
// detail"), GL-free. The grid's cells are grouped into square blocks (kLodBlock cells a
// side; the last row and column of blocks may be smaller). Level l of a block keeps every
// 2^l-th row and column of its vertices (and its last ones): the same vertices, with the
// fine mesh's own positions and normals, so a coarse level's shading and silhouettes come
// from the fine normals, not from the coarse grid's differences. Each frame a block is
// drawn at the coarsest level whose error, seen from the eye at the block's nearest point,
// spans at most the bound in pixels; where two blocks at different levels meet, both use
// the coarser one's vertices on their shared edge (the finer block's edge vertices snap to
// the nearest kept one), so the PN patches on either side share their edge curves: no
// cracks.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "renderer/core/camera.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/mesh_pyramid.hpp"

namespace renderer {

// The blocks and their levels' errors: libterrain's (terrain/mesh_pyramid.hpp), which the
// mesh pyramid on disk stores too.
inline constexpr std::size_t kLodBlock = terrain::kLevelBlock;  // cells a side of a block
using LodBlock = terrain::MeshLevelBlock;
using LodHierarchy = terrain::MeshLevels;
inline LodHierarchy build_lod(const terrain::GridMesh& mesh, std::size_t block = kLodBlock) {
  return terrain::build_mesh_levels(mesh, block);
}

// A block's level that no silhouette can cross is held to kFacingLodFactor times the
// bound: there its error moves shading and depth only, not the silhouettes, whose places
// the strict bound keeps. It can cross none when the eye's elevation seen from anywhere in
// the block's box (its tangent: at its least from the box's top at its farthest corner;
// the view's own in the orthographic view) exceeds kFacingMargin times the exaggeration
// times the level's steepest gradient (LodBlock::slope, measured at exaggeration 1): then
// every normal the level draws faces the eye. The margin covers what the slope does not
// measure: a tessellated triangle is a chord of the PN cubic, which the slope samples at
// the fine vertices' parameters, and the exaggerated cubic is not the cubic exaggerated.
inline constexpr double kFacingLodFactor = 4, kFacingMargin = 1.25;

// Per block, the coarsest level l with error[l] x exaggeration <= bound_px pixels (times
// kFacingLodFactor where level l faces the eye throughout) and, with cell_px > 0, whose
// cell's plan diagonal spans at most cell_px pixels (Style's lod_cell_px) at the block's
// nearest point (View::pixel_size of its distance along the line of sight; the
// eye inside the box: level 0); never finer than h.base (the grid held), unless that is
// coarser than the block's coarsest.
std::vector<std::uint8_t> select_lod(const LodHierarchy& h, const View& view, double exaggeration,
                                     double bound_px, double cell_px = 0);

// The nearest depth of `box` along the line of sight of `view`: infinity when it is out of
// view or behind the eye, 0 when it reaches the eye (perspective).
double nearest_depth(const Box& box, const View& view);

// The metres a pixel spans at the nearest surface in view: at the nearest block of `h` in
// view (heights times `exaggeration`), or of `box` without levels (h null); 0 when the
// surface reaches the eye or none is in view. What the creases' level is chosen by
// (select_crease_level).
double nearest_pixel_metres(const LodHierarchy* h, const Box& box, const View& view,
                            double exaggeration);

// The box of the mesh the levels describe (the union of their blocks' boxes), heights times
// `exaggeration`: the mesh's own box, also when a coarser level of it is held (base > 0),
// and the whole mesh's when only a window of it is held (LodHierarchy::window).
Box levels_box(const LodHierarchy& h, double exaggeration);

// `patches` (triangles of indices into `vertices` when given, else of held vertices) less
// those with a vertex outside the data (`outside`, per held vertex: non-zero outside; empty:
// none is), `*may_face_away` (the leading patches that may face away) counted again.
void drop_outside_patches(std::vector<std::uint32_t>& patches,
                          const std::vector<std::uint8_t>& outside,
                          const std::vector<std::uint32_t>* vertices, std::size_t* may_face_away);

// The blocks (rows br0 .. br1 - 1, columns bc0 .. bc1 - 1 of h's) that hold every block in
// any of `views` (nearest_depth finite, heights times `exaggeration`) and one more around
// them, for a PN patch's bulge past its block's box; empty (br1 = 0) when none is in view.
// What a frame needs of the mesh (hold_views's window): the terrain that hides a point of
// the view lies between it and the eye, in the view too.
struct BlockRange {
  std::size_t br0 = 0, bc0 = 0, br1 = 0, bc1 = 0;
  bool empty() const { return br1 == 0; }
};
BlockRange blocks_in_view(const LodHierarchy& h, const std::vector<View>& views,
                          double exaggeration);

// What part of a mesh is held, against the whole mesh it is part of: the mesh itself, a
// coarser level of its pyramid (LodHierarchy::base > 0) or a window of it
// (LodHierarchy::window). Every question about the whole is answered here: its grid, its
// spacing, its extent and box, and where the held part lies in it.
class MeshHolding {
 public:
  // `levels`: the held mesh's levels of detail, or null when none were made.
  MeshHolding(const terrain::GridMesh& held, const LodHierarchy* levels)
      : held_(held), levels_(levels) {}
  // A coarser level or a window is held: drawn with levels of detail, whatever the style.
  bool part() const { return levels_ && (levels_->base > 0 || levels_->window); }
  bool window() const { return levels_ && levels_->window; }
  // The whole mesh's grid, without vertices: its origin and extent, on level 0's spacing
  // when a window is held and on the held level's when the whole of a coarser one is.
  terrain::GridMesh whole_grid() const;
  // The whole mesh's own spacing (metres), level 0's also when a coarser level is held.
  Eigen::Vector2d fine_spacing() const;
  // The held window's first vertex in the whole mesh's local frame (zero without a window).
  Eigen::Vector2d window_origin() const;
  // The whole mesh's extent in the held mesh's local frame: xmin, ymin, xmax, ymax.
  Eigen::Vector4f local_extent() const;
  // The whole mesh's box, heights times `exaggeration` (levels_box when a part is held); of
  // the vertices drawn: those outside the data left out.
  Box box(double exaggeration) const;
  // Whether it is drawn with levels of detail: always when a part is held, else with a
  // positive bound (Style::levels_of_detail) on a mesh of more than one block.
  bool uses_lod(bool levels_of_detail) const;
  // The blocks of the whole mesh's levels `whole` (base 0) that are held: the window's or all.
  BlockRange held_blocks(const LodHierarchy& whole) const;

 private:
  const terrain::GridMesh& held_;
  const LodHierarchy* levels_;
};

// Per block, 1 where it faces the eye throughout at its level (levels[k]) by the test
// select_lod's looser bound uses: no fragment of it faces away, so AFT need not look at its
// patches.
std::vector<std::uint8_t> facing_blocks(const LodHierarchy& h, const View& view,
                                        double exaggeration,
                                        const std::vector<std::uint8_t>& levels);

// The patches (3 vertex indices each, counter-clockwise as GridTopology::face) of every
// block at its level, joined without cracks (above): first those that may face away
// (*may_face_away of them), then those of the blocks marked in `facing` (facing_blocks;
// empty: none) but for their cells on a side snapped to a coarser neighbour, whose thin
// triangles are not the level's. All blocks at level 0: the mesh's own faces, in order.
std::vector<std::uint32_t> lod_patches(const LodHierarchy& h,
                                       const std::vector<std::uint8_t>& levels,
                                       const std::vector<std::uint8_t>& facing = {},
                                       std::size_t* may_face_away = nullptr);

// The same patches as a mesh of their own, what the GPU holds when the whole mesh is not
// resident: `vertices` lists mesh vertex indices, each block's level grid in turn (a
// block's border vertices again in its neighbour), and `patches` indexes `vertices`, 3
// a patch, in lod_patches' order. So the vertices drawn follow the view, not the mesh.
struct LodMesh {
  std::vector<std::uint32_t> vertices, patches;
  std::size_t may_face_away = 0;  // the leading patches that may face away (lod_patches)
};
LodMesh lod_mesh(const LodHierarchy& h, const std::vector<std::uint8_t>& levels,
                 const std::vector<std::uint8_t>& facing = {});

}  // namespace renderer
