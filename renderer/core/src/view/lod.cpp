#include "renderer/core/lod.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace renderer {

namespace {

// Position p of a side of n cells moved to the nearest position kept at step s (ties: the
// lower).
std::uint32_t snap(std::uint32_t p, std::uint32_t n, std::uint32_t s) {
  const std::uint32_t lower = p / s * s, upper = std::min(lower + s, n);
  return p - lower <= upper - p ? lower : upper;
}

Box block_box(const LodBlock& b, double e) {
  return Box{{b.lo.x(), b.lo.y(), e * b.lo.z()}, {b.hi.x(), b.hi.y(), e * b.hi.z()}};
}

}  // namespace

double nearest_depth(const Box& box, const View& view) {
  const Eigen::Matrix4d vp = view.view_projection();
  double nearest = 1e300, farthest = -1e300;
  bool left = true, right = true, below = true, above = true;
  for (const Eigen::Vector3d& p : box_corners(box)) {
    const double depth = (p - view.eye).dot(view.forward);
    nearest = std::min(nearest, depth), farthest = std::max(farthest, depth);
    const Eigen::Vector4d c = vp * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
    left = left && c.x() < -c.w(), right = right && c.x() > c.w(), below = below && c.y() < -c.w(),
    above = above && c.y() > c.w();
  }
  if (left || right || below || above || farthest <= 0)
    return std::numeric_limits<double>::infinity();
  return !view.orthographic() && !(nearest > view.near) ? 0.0 : nearest;
}

namespace {

// Whether a surface over the block's box whose steepest gradient is `slope` faces the eye
// everywhere with the margin kFacingMargin: the eye's elevation seen from anywhere in the
// box (its tangent, at its least: from the box's top at its farthest corner) exceeds the
// margin times the gradient. Then no silhouette crosses it.
bool faces_eye(const LodBlock& b, float slope, const View& view, double e) {
  if (!std::isfinite(slope)) return false;
  double rise, run;
  if (view.orthographic()) {
    rise = -view.forward.z(), run = view.forward.head<2>().norm();
  } else {
    rise = view.eye.z() - e * double(b.hi.z());
    run = 0;
    for (const double x : {double(b.lo.x()), double(b.hi.x())})
      for (const double y : {double(b.lo.y()), double(b.hi.y())})
        run = std::max(run, std::hypot(view.eye.x() - x, view.eye.y() - y));
  }
  return rise > kFacingMargin * e * double(slope) * run;
}

// select_lod's levels before the held grid's clamp (LodHierarchy::base).
std::vector<std::uint8_t> wanted_levels(const LodHierarchy& h, const View& view, double e,
                                        double bound_px, double cell_px) {
  std::vector<std::uint8_t> levels(h.blocks.size(), 0);
  for (std::size_t k = 0; k < h.blocks.size(); ++k) {
    const LodBlock& b = h.blocks[k];
    const double nearest = nearest_depth(block_box(b, e), view);
    if (std::isinf(nearest)) {  // out of view or behind the eye: nothing of it is drawn
      levels[k] = std::uint8_t(b.levels() - 1);
      continue;
    }
    if (nearest == 0) continue;  // reaches the eye: full detail
    const double metres = view.pixel_size(nearest),
                 allowed = bound_px * metres / std::max(e, 1e-12);
    // A level-0 cell's plan diagonal (the box spans the block's cells).
    const double diagonal = std::hypot(double(b.hi.x() - b.lo.x()) / std::max(b.nc, 1u),
                                       double(b.hi.y() - b.lo.y()) / std::max(b.nr, 1u));
    auto fits = [&](std::size_t l) {
      if (cell_px > 0 && double(std::size_t(1) << l) * diagonal > cell_px * metres) return false;
      const bool facing = l < b.slope.size() && faces_eye(b, b.slope[l], view, e);
      return double(b.error[l]) <= (facing ? kFacingLodFactor : 1.0) * allowed;
    };
    int l = 0;
    while (l + 1 < b.levels() && fits(std::size_t(l + 1))) ++l;
    levels[k] = std::uint8_t(l);
  }
  return levels;
}

}  // namespace

std::vector<std::uint8_t> select_lod(const LodHierarchy& h, const View& view, double e,
                                     double bound_px, double cell_px) {
  std::vector<std::uint8_t> levels = wanted_levels(h, view, e, bound_px, cell_px);
  if (h.base > 0)  // nothing finer than the grid held (its coarsest level at most)
    for (std::size_t k = 0; k < h.blocks.size(); ++k)
      levels[k] = std::max(levels[k], std::uint8_t(std::min(h.base, h.blocks[k].levels() - 1)));
  return levels;
}

double nearest_pixel_metres(const LodHierarchy* h, const Box& box, const View& view, double e) {
  double nearest = std::numeric_limits<double>::infinity();
  if (h)
    for (const LodBlock& b : h->blocks)
      nearest = std::min(nearest, nearest_depth(block_box(b, e), view));
  else
    nearest = nearest_depth(box, view);
  return std::isinf(nearest) || nearest == 0 ? 0.0 : view.pixel_size(nearest);
}

Box levels_box(const LodHierarchy& h, double exaggeration) {
  if (h.window) {
    const Eigen::Vector3f &lo = h.window->lo, &hi = h.window->hi;
    return Box{{lo.x(), lo.y(), double(lo.z()) * exaggeration},
               {hi.x(), hi.y(), double(hi.z()) * exaggeration}};
  }
  Box box{Eigen::Vector3d::Constant(std::numeric_limits<double>::max()),
          Eigen::Vector3d::Constant(-std::numeric_limits<double>::max())};
  for (const LodBlock& b : h.blocks) {
    box.lo = box.lo.cwiseMin(Eigen::Vector3d(b.lo.x(), b.lo.y(), double(b.lo.z()) * exaggeration));
    box.hi = box.hi.cwiseMax(Eigen::Vector3d(b.hi.x(), b.hi.y(), double(b.hi.z()) * exaggeration));
  }
  return box;
}

namespace {

// A vertex's index in the grid held: level h.base's (every 2^base-th row and column and the
// last ones; a drawn block's lines are among them, see select_lod).
struct HeldGrid {
  explicit HeldGrid(const LodHierarchy& h)
      : rows0(h.topo.rows - 1),
        cols0(h.topo.cols - 1),
        rows(terrain::level_count(rows0, h.base)),
        cols(terrain::level_count(cols0, h.base)),
        base(h.base) {}
  std::uint32_t operator()(std::size_t r, std::size_t c) const {
    const std::size_t hr = r == rows0 ? rows - 1 : r >> base;
    const std::size_t hc = c == cols0 ? cols - 1 : c >> base;
    return std::uint32_t(hr * cols + hc);
  }
  std::size_t rows0, cols0, rows, cols;
  int base;
};

// The steps of a block (its level's, s) and of its four sides (the coarser of this block's
// and the neighbour's across it).
struct BlockSteps {
  std::uint32_t s, north, south, west, east;
};

// Block b at level l: its level grid's vertices (a snapped vertex is on it too: a coarser
// step is a multiple of this one, and the last line is kept) and its patches, those of a
// block facing the eye throughout into `facing_patches` but for the cells on a side snapped
// to a coarser neighbour (their thin triangles are not the level's, whose slope the block
// was found facing by).
void add_block(LodMesh& out, std::vector<std::uint32_t>& facing_patches, const LodBlock& b, int l,
               const BlockSteps& st, bool facing_block, const HeldGrid& held) {
  const std::uint32_t s = st.s, north = st.north, south = st.south, west = st.west, east = st.east;
  const auto rs = terrain::level_lines(b.nr, s), cs = terrain::level_lines(b.nc, s);
  const auto base = std::uint32_t(out.vertices.size());
  for (const std::uint32_t r : rs)
    for (const std::uint32_t c : cs)
      out.vertices.push_back(held(std::size_t(b.r0) + r, std::size_t(b.c0) + c));
  auto line = [&](std::uint32_t p, std::uint32_t n, std::size_t count) {
    return p == n ? std::uint32_t(count - 1) : p >> l;
  };
  auto vertex = [&](std::uint32_t r, std::uint32_t c) {
    if (r == 0)
      c = snap(c, b.nc, north);
    else if (r == b.nr)
      c = snap(c, b.nc, south);
    if (c == 0)
      r = snap(r, b.nr, west);
    else if (c == b.nc)
      r = snap(r, b.nr, east);
    return base + line(r, b.nr, rs.size()) * std::uint32_t(cs.size()) + line(c, b.nc, cs.size());
  };
  for (std::size_t i = 0; i + 1 < rs.size(); ++i)
    for (std::size_t j = 0; j + 1 < cs.size(); ++j) {
      const std::uint32_t nw = vertex(rs[i], cs[j]), sw = vertex(rs[i + 1], cs[j]);
      const std::uint32_t se = vertex(rs[i + 1], cs[j + 1]), ne = vertex(rs[i], cs[j + 1]);
      const bool snapped = (i == 0 && north > s) || (i + 2 == rs.size() && south > s) ||
                           (j == 0 && west > s) || (j + 2 == cs.size() && east > s);
      std::vector<std::uint32_t>& to = facing_block && !snapped ? facing_patches : out.patches;
      for (const std::array<std::uint32_t, 3>& t : {std::array{nw, sw, se}, std::array{nw, se, ne}})
        if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) to.insert(to.end(), t.begin(), t.end());
    }
}

}  // namespace

LodMesh lod_mesh(const LodHierarchy& h, const std::vector<std::uint8_t>& levels,
                 const std::vector<std::uint8_t>& facing) {
  LodMesh out;
  const HeldGrid held(h);
  auto step = [&](std::size_t br, std::size_t bc) {
    return std::uint32_t(1) << levels[br * h.block_cols + bc];
  };
  // The patches of blocks that face the eye throughout (facing_blocks) go after the others.
  std::vector<std::uint32_t> facing_patches;
  for (std::size_t br = 0; br < h.block_rows; ++br)
    for (std::size_t bc = 0; bc < h.block_cols; ++bc) {
      const std::size_t k = br * h.block_cols + bc;
      const std::uint32_t s = step(br, bc);
      const BlockSteps st{s, br > 0 ? std::max(s, step(br - 1, bc)) : s,
                          br + 1 < h.block_rows ? std::max(s, step(br + 1, bc)) : s,
                          bc > 0 ? std::max(s, step(br, bc - 1)) : s,
                          bc + 1 < h.block_cols ? std::max(s, step(br, bc + 1)) : s};
      add_block(out, facing_patches, h.blocks[k], levels[k], st,
                k < facing.size() && facing[k] != 0, held);
    }
  out.may_face_away = out.patches.size() / 3;
  out.patches.insert(out.patches.end(), facing_patches.begin(), facing_patches.end());
  return out;
}

std::vector<std::uint32_t> lod_patches(const LodHierarchy& h,
                                       const std::vector<std::uint8_t>& levels,
                                       const std::vector<std::uint8_t>& facing,
                                       std::size_t* may_face_away) {
  std::vector<std::uint32_t> out;
  if (h.base == 0 &&
      std::all_of(levels.begin(), levels.end(), [](std::uint8_t l) { return l == 0; })) {
    out.resize(3 * h.topo.n_faces());
    for (std::size_t f = 0; f < h.topo.n_faces(); ++f) {
      const auto t = h.topo.face(f);
      std::copy(t.begin(), t.end(), out.begin() + long(3 * f));
    }
    if (may_face_away) *may_face_away = h.topo.n_faces();
    return out;
  }
  LodMesh m = lod_mesh(h, levels, facing);
  for (std::uint32_t& v : m.patches) v = m.vertices[v];
  if (may_face_away) *may_face_away = m.may_face_away;
  return std::move(m.patches);
}

void drop_outside_patches(std::vector<std::uint32_t>& patches,
                          const std::vector<std::uint8_t>& outside,
                          const std::vector<std::uint32_t>* vertices, std::size_t* may_face_away) {
  if (outside.empty()) return;
  const auto out = [&](std::uint32_t i) { return outside[vertices ? (*vertices)[i] : i] != 0; };
  std::size_t kept = 0, away = 0;
  for (std::size_t t = 0; t + 2 < patches.size(); t += 3) {
    if (out(patches[t]) || out(patches[t + 1]) || out(patches[t + 2])) continue;
    if (may_face_away && t / 3 < *may_face_away) ++away;
    std::copy_n(patches.begin() + long(t), 3, patches.begin() + long(3 * kept++));
  }
  patches.resize(3 * kept);
  if (may_face_away) *may_face_away = away;
}

BlockRange blocks_in_view(const LodHierarchy& h, const std::vector<View>& views, double e) {
  BlockRange r{h.block_rows, h.block_cols, 0, 0};
  for (std::size_t k = 0; k < h.blocks.size(); ++k) {
    const Box box = block_box(h.blocks[k], e);
    if (std::none_of(views.begin(), views.end(),
                     [&](const View& v) { return std::isfinite(nearest_depth(box, v)); }))
      continue;
    const std::size_t br = k / h.block_cols, bc = k % h.block_cols;
    r.br0 = std::min(r.br0, br), r.bc0 = std::min(r.bc0, bc);
    r.br1 = std::max(r.br1, br + 1), r.bc1 = std::max(r.bc1, bc + 1);
  }
  if (r.empty()) return {};
  return {r.br0 > 0 ? r.br0 - 1 : 0, r.bc0 > 0 ? r.bc0 - 1 : 0, std::min(r.br1 + 1, h.block_rows),
          std::min(r.bc1 + 1, h.block_cols)};
}

std::vector<std::uint8_t> facing_blocks(const LodHierarchy& h, const View& view, double e,
                                        const std::vector<std::uint8_t>& levels) {
  std::vector<std::uint8_t> facing(h.blocks.size(), 0);
  for (std::size_t k = 0; k < h.blocks.size(); ++k) {
    const LodBlock& b = h.blocks[k];
    const std::size_t l = levels[k];
    facing[k] = l < b.slope.size() && faces_eye(b, b.slope[l], view, e);
  }
  return facing;
}

terrain::GridMesh MeshHolding::whole_grid() const {
  terrain::GridMesh g;
  g.geo = window() ? levels_->window->geo : held_.geo;
  g.topo = window() ? levels_->window->whole : held_.topo;
  return g;
}

Eigen::Vector2d MeshHolding::fine_spacing() const {
  if (!levels_ || levels_->base == 0) return {held_.geo.dx, held_.geo.dy};
  if (levels_->window) return {levels_->window->geo.dx, levels_->window->geo.dy};
  return {held_.geo.dx * double(held_.topo.cols - 1) / double(levels_->topo.cols - 1),
          held_.geo.dy * double(held_.topo.rows - 1) / double(levels_->topo.rows - 1)};
}

Eigen::Vector2d MeshHolding::window_origin() const {
  if (!window()) return Eigen::Vector2d::Zero();
  const auto& w = *levels_->window;
  return {double(w.c0) * w.geo.dx, -double(w.r0) * w.geo.dy};
}

Eigen::Vector4f MeshHolding::local_extent() const {
  if (!window())
    return {0, -float(double(held_.topo.rows - 1) * held_.geo.dy),
            float(double(held_.topo.cols - 1) * held_.geo.dx), 0};
  const auto& w = *levels_->window;
  const Eigen::Vector2d cell = fine_spacing();
  return {-float(double(w.c0) * cell.x()), -float(double(w.whole.rows - 1 - w.r0) * cell.y()),
          float(double(w.whole.cols - 1 - w.c0) * cell.x()), float(double(w.r0) * cell.y())};
}

Box MeshHolding::box(double exaggeration) const {
  if (part()) return levels_box(*levels_, exaggeration);
  Box box{Eigen::Vector3d::Constant(std::numeric_limits<double>::max()),
          Eigen::Vector3d::Constant(-std::numeric_limits<double>::max())};
  const bool holes = held_.filled.size() == held_.n_vertices();
  for (std::size_t i = 0; i < held_.n_vertices(); ++i) {
    if (holes && held_.filled[i] == terrain::kOutside) continue;  // not drawn
    Eigen::Vector3d p = held_.positions[i].cast<double>();
    p.z() *= exaggeration;
    box.lo = box.lo.cwiseMin(p);
    box.hi = box.hi.cwiseMax(p);
  }
  return box;
}

bool MeshHolding::uses_lod(bool levels_of_detail) const {
  if (part()) return true;
  return levels_of_detail && held_.topo.rows > kLodBlock + 1 && held_.topo.cols > kLodBlock + 1;
}

BlockRange MeshHolding::held_blocks(const LodHierarchy& whole) const {
  if (!window()) return {0, 0, whole.block_rows, whole.block_cols};
  const auto& w = *levels_->window;
  return {w.r0 / whole.block, w.c0 / whole.block, w.r0 / whole.block + levels_->block_rows,
          w.c0 / whole.block + levels_->block_cols};
}

}  // namespace renderer
