// The scene a tool draws from: the mesh (or a level or window of its pyramid) and the
// .dv's creases and ridge lines, read and focused on the views drawn.
#include "renderer/scene/scene.hpp"

#include "renderer/core/camera.hpp"
#include "renderer/core/silhouette.hpp"
#include "renderer/gl/gl_contract.hpp"

#include <fmt/format.h>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

#include "drainage/dv_views.hpp"
#include "renderer/core/hachures.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/vector_file.hpp"
#include "renderer/core/vector_lines.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"

namespace renderer {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

namespace {

// The whole mesh's grid (MeshHolding::whole_grid).
terrain::GridMesh whole_grid(const Scene& s) {
  return MeshHolding(s.mesh, s.levels.get()).whole_grid();
}

// The database's points under the mesh and their creases, on scene.mesh. Under the whole
// mesh when a window of it is held (LodHierarchy::window): the rules see the basins, flats and
// channels of the network the mesh's frame draws, not the window's pieces of them (its flow
// normalized by a basin cut at the window's edge); the lines outside the window are out of view.
void build_creases(Scene& s, const std::string& dv_path, const CreaseRules& rules) {
  const auto t0 = Clock::now();
  const terrain::GridMesh extent = whole_grid(s);  // what the database should cover
  const terrain::DrainageLinks links = links_under(dv_path, extent);
  s.creases = build_crease_geometry(s.mesh, links, rules);
  std::string w = coverage_warning(extent, links);
  if (w.empty())
    w = surface_warning(s.mesh, *s.creases);  // one warning: the extent says it already
  if (!w.empty()) s.warnings.push_back("'" + dv_path + "': " + w);
  s.traits = segment_traits(s.mesh, links, *s.creases);
  const auto t_ridges = Clock::now();
  s.ridges = scene_ridges(links, extent.geo);
  s.ridges_seconds = since(t_ridges);
  s.chains = segment_chains(*s.creases);
  s.crease_levels =
      std::make_shared<const std::vector<CreaseLevel>>(coarser_crease_levels(*s.creases));
  s.crease_level_traits.clear();
  for (const CreaseLevel& l : *s.crease_levels)
    s.crease_level_traits.push_back(merged_traits(s.traits, l));
  s.creases_seconds = since(t0);
}

constexpr std::uint64_t kVertexBytes = 2 * sizeof(Eigen::Vector3f);  // a position and a normal

// What level l of the blocks in `r` takes: its grid's vertices over them.
std::uint64_t window_bytes(const LodHierarchy& h, const BlockRange& r, int l) {
  const std::size_t rows0 = h.topo.rows - 1, cols0 = h.topo.cols - 1, B = h.block;
  auto count = [&](std::size_t a, std::size_t b,
                   std::size_t n) {  // level l's lines over cells a*B .. min(b*B, n)
    return terrain::level_count(std::min(b * B, n), l) - ((a * B) >> l);
  };
  return std::uint64_t(count(r.br0, r.br1, rows0)) * count(r.bc0, r.bc1, cols0) * kVertexBytes;
}

// The finest of levels `from` .. count - 1 whose grid over the blocks in `r` takes at most
// `bytes` (the coarsest when none does).
int finest_within(const LodHierarchy& h, const BlockRange& r, int from, int count,
                  std::uint64_t bytes) {
  int l = from;
  while (l + 1 < count && window_bytes(h, r, l) > bytes) ++l;
  return l;
}

BlockRange all_blocks(const LodHierarchy& h) { return {0, 0, h.block_rows, h.block_cols}; }

// Reads scene.mesh from its pyramid at the level `level` chooses; false when the pyramid
// is not current (scene.mesh_source says why).
bool read_level(Scene& s, const std::string& mesh_path,
                const std::function<terrain::PyramidPart(const terrain::MeshPyramid&)>& level) {
  std::string why;
  std::shared_ptr<const LodHierarchy> own;
  std::optional<terrain::PyramidMesh> p =
      terrain::read_mesh_via_pyramid(mesh_path, why, [&](const terrain::MeshPyramid& pyramid) {
        own = std::make_shared<const LodHierarchy>(pyramid.levels());
        return level(pyramid);
      });
  if (!p) {
    s.mesh_source = why.empty() ? "the PLY" : "the PLY: " + why;
    return false;
  }
  // A scene that reads its pyramid again (hold_views) reads the pair it read first.
  if (s.digest && *s.digest != p->digest)
    throw terrain::Error("'" + mesh_path +
                         "' and its pyramid changed while they were read (rewritten by dem2mesh?); "
                         "run again");
  s.digest = p->digest;
  s.mesh = std::move(p->mesh);
  s.mesh_level = p->levels.base;
  s.mesh_levels = std::move(own);
  s.levels = std::make_shared<const LodHierarchy>(std::move(p->levels));
  const auto& w = s.levels->window;
  s.mesh_source = fmt::format(
      "'{}' (its pyramid{}{})", terrain::pyramid_path_of(mesh_path),
      s.mesh_level > 0 ? fmt::format(", level {}", s.mesh_level) : "",
      w ? fmt::format(", the window of rows {} .. {}, columns {} .. {}", w->r0,
                      w->r0 + s.levels->topo.rows - 1, w->c0, w->c0 + s.levels->topo.cols - 1)
        : "");
  return true;
}

}  // namespace

Scene load_scene(const std::string& mesh_path, const std::string& dv_path, const CreaseRules& rules,
                 std::uint64_t vertex_bytes) {
  const auto t0 = Clock::now();
  Scene s;
  const bool from_pyramid =
      vertex_bytes > 0 && read_level(s, mesh_path, [&](const terrain::MeshPyramid& p) {
        const LodHierarchy& h = p.levels();
        return window_bytes(h, all_blocks(h), 0) > vertex_bytes
                   ? finest_within(h, all_blocks(h), 0, p.level_count(), vertex_bytes / 4)
                   : 0;
      });
  s.mesh_seconds = since(t0);
  if (s.mesh_level > 0) {  // a preview: the creases wait for hold_views
    s.deferred = s.bounded = Scene::Deferred{mesh_path, dv_path, rules, vertex_bytes};
    return s;
  }
  if (!from_pyramid) {
    LodHierarchy levels;
    std::string unused;  // why a pyramid beside it was not used
    s.mesh = terrain::read_terrain_mesh(mesh_path, &s.mesh_source, &levels, &unused);
    if (!unused.empty()) s.warnings.push_back(unused);
    if (!levels.blocks.empty()) s.levels = std::make_shared<const LodHierarchy>(std::move(levels));
    s.mesh_seconds = since(t0);
    if (vertex_bytes > 0 && s.mesh.n_vertices() * kVertexBytes > vertex_bytes)
      s.warnings.push_back(
          fmt::format("'{}': its vertices take {:.1f} MB, more than the memory bound ({:.1f} MB), "
                      "and no current pyramid is beside it ({}): read whole; dem2mesh --pyramid "
                      "makes one",
                      mesh_path, double(s.mesh.n_vertices() * kVertexBytes) / 1e6,
                      double(vertex_bytes) / 1e6, s.mesh_source));
  }
  if (!dv_path.empty()) build_creases(s, dv_path, rules);
  return s;
}

namespace {

// What hold_views reads for `views` over the mesh's own levels `h` (base 0): the finest
// level any block of them is drawn at (`needed`), over the blocks in view (`range`, with
// `window`; else all), coarser (`level`) while that takes more than `bytes`.
struct FocusPlan {
  int level = 0, needed = 0;
  BlockRange range;
  bool part = false;  // range is not every block
};
FocusPlan focus_plan(const LodHierarchy& h, const std::vector<View>& views, const Style& style,
                     bool window, std::uint64_t bytes) {
  int count = 1;  // the pyramid's levels: to the coarsest of any block
  for (const LodBlock& b : h.blocks) count = std::max(count, b.levels());
  FocusPlan f;
  f.needed = count - 1;
  for (const View& v : views)
    for (const std::uint8_t l :
         select_lod(h, v, style.exaggeration, style.lod_error, lod_cell_px(style)))
      f.needed = std::min(f.needed, int(l));
  const BlockRange in_view = window ? blocks_in_view(h, views, style.exaggeration) : all_blocks(h);
  f.range = in_view.empty() ? all_blocks(h) : in_view;
  f.part = f.range.br0 > 0 || f.range.bc0 > 0 || f.range.br1 < h.block_rows ||
           f.range.bc1 < h.block_cols;
  f.level = finest_within(h, f.range, f.needed, count, bytes);
  return f;
}

// The views of `cameras` over the whole mesh of the levels `h` (its frame's world origin
// `g`).
std::vector<View> whole_views(const LodHierarchy& h, const terrain::MeshGeoref& g,
                              const std::vector<Camera>& cameras, int width, int height,
                              double exaggeration) {
  const Eigen::Vector3d origin(g.origin_x, g.origin_y, g.origin_z);
  const Box box = levels_box(h, exaggeration);
  std::vector<View> views;
  for (const Camera& camera : cameras)
    views.push_back(make_view(camera, origin, box, width, height));
  return views;
}

// The blocks of the mesh that the scene holds (its window, or all).
BlockRange held_blocks(const Scene& s) {
  return MeshHolding(s.mesh, s.levels.get()).held_blocks(*s.mesh_levels);
}

bool covers(const BlockRange& a, const BlockRange& b) {
  return a.br0 <= b.br0 && a.bc0 <= b.bc0 && a.br1 >= b.br1 && a.bc1 >= b.bc1;
}

// hold_views's read, in place of a preview (load_scene's) or of a level held before.
std::string read_for_views(Scene& s, const std::vector<Camera>& cameras, int width, int height,
                           const Style& style, bool window, bool preview) {
  if (!s.deferred) return {};
  const Scene::Deferred d = *s.deferred;
  s.deferred.reset();
  const int held = s.mesh_level;
  std::string note;
  const auto t0 = Clock::now();
  const bool read =
      read_level(s, d.mesh_path, [&](const terrain::MeshPyramid& p) -> terrain::PyramidPart {
        s.mesh = {};  // the level held goes before the next is read
        if (!style.levels_of_detail()) return 0;
        const LodHierarchy& h = p.levels();  // the mesh's own levels, base 0
        const std::vector<View> views =
            whole_views(h, p.georef(), cameras, width, height, style.exaggeration);
        const FocusPlan f = focus_plan(h, views, style, window, d.vertex_bytes);
        const BlockRange& r = f.range;
        note = fmt::format(
            "{} level {} at its finest{}{}",
            cameras.size() > 1 ? "the views draw" : "the view draws", f.needed,
            f.part
                ? fmt::format(
                      "; the blocks in view, rows {} .. {} and columns {} .. {} of {} x {}, read",
                      r.br0, r.br1 - 1, r.bc0, r.bc1 - 1, h.block_rows, h.block_cols)
                : "",
            f.level > f.needed
                ? fmt::format("; level {} read, the finest within the memory bound", f.level)
                : "");
        return {f.level, r.br0, r.bc0, r.br1, r.bc1};
      });
  if (!read)
    throw terrain::Error("'" + d.mesh_path + "' and its pyramid changed while they were read (" +
                         s.mesh_source + "); run again");
  s.mesh_seconds += since(t0);
  if (!d.dv_path.empty()) build_creases(s, d.dv_path, d.rules);
  return fmt::format("mesh read at level {} of its pyramid {} level {}: {}", s.mesh_level,
                     preview ? "after the preview at" : "in place of", held,
                     note.empty() ? "--lod-error 0 draws every cell" : note);
}

// A still view: read when what is held does not serve it.
std::string hold_still_view(Scene& s, const Camera& camera, int width, int height,
                            const Style& style) {
  if (!s.bounded || !s.mesh_levels || !style.levels_of_detail()) return {};
  const LodHierarchy& h = *s.mesh_levels;
  const std::vector<View> views =
      whole_views(h, whole_grid(s).geo, {camera}, width, height, style.exaggeration);
  const FocusPlan f = focus_plan(h, views, style, true, s.bounded->vertex_bytes);
  // What is held draws what a Frame would read when it holds the blocks in view at
  // that level, or at a finer one where that level is the finest the view draws (no
  // block drawn finer than it wants).
  const int held = s.mesh_level;
  if (covers(held_blocks(s), f.range) &&
      (held == f.level || (held < f.level && f.level == f.needed)))
    return {};
  s.deferred = s.bounded;
  return (f.level < held ? "the view came nearer: " : "the view moved: ") +
         read_for_views(s, {camera}, width, height, style, true, false);
}

// A moving view: the whole mesh when it leaves the window held.
std::string hold_moving_view(Scene& s, const Camera& camera, int width, int height,
                             const Style& style) {
  if (!s.bounded || !s.mesh_levels || !MeshHolding(s.mesh, s.levels.get()).window()) return {};
  const LodHierarchy& h = *s.mesh_levels;
  const std::vector<View> views =
      whole_views(h, whole_grid(s).geo, {camera}, width, height, style.exaggeration);
  const BlockRange r = blocks_in_view(h, views, style.exaggeration);
  if (r.empty() || covers(held_blocks(s), r)) return {};
  s.deferred = s.bounded;
  return "the view left the blocks held: " +
         read_for_views(s, {camera}, width, height, style, false, false);
}

}  // namespace

std::string hold_views(Scene& s, const std::vector<Camera>& cameras, int width, int height,
                       const Style& style, HoldFor what) {
  switch (what) {
    case HoldFor::Frames:
    case HoldFor::Frame:
      return read_for_views(s, cameras, width, height, style, what == HoldFor::Frame, true);
    case HoldFor::StillView:
      return hold_still_view(s, cameras.at(0), width, height, style);
    case HoldFor::MovingView:
      return hold_moving_view(s, cameras.at(0), width, height, style);
  }
  return {};
}

std::shared_ptr<const LodHierarchy> scene_levels(Scene& scene, const Style& style) {
  if (!style.levels_of_detail()) return nullptr;
  if (!scene.levels) scene.levels = std::make_shared<const LodHierarchy>(build_lod(scene.mesh));
  return scene.levels;
}

}  // namespace renderer
