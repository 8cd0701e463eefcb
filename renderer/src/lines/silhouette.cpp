#include "renderer/silhouette.hpp"
#include "renderer/camera.hpp"

#include <algorithm>
#include <cstddef>

namespace renderer {

std::vector<std::uint8_t> toward_away_silhouettes(const std::vector<float>& toward, const std::vector<float>& away,
                                                  int w, int h, bool reversed_z, bool antialias) {
  // As far_of in common.glsl: float arithmetic, so that the comparisons match the GPU's.
  auto far_of = [&](float d) { return far_depth(reversed_z, d); };
  auto inside = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h; };
  auto at = [&](int x, int y) { return std::size_t(y) * std::size_t(w) + std::size_t(x); };
  auto raw = [&](int x, int y) {
    const float t = far_of(toward[at(x, y)]);
    float a = far_of(away[at(x, y)]);
    if (antialias)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (inside(x + dx, y + dy)) a = std::min(a, far_of(away[at(x + dx, y + dy)]));
    if (!(t < a)) return false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if ((dx != 0 || dy != 0) && inside(x + dx, y + dy) && far_of(toward[at(x + dx, y + dy)]) > a) return true;
    return false;
  };
  std::vector<std::uint8_t> s(std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) s[at(x, y)] = raw(x, y);
  if (!antialias) return s;
  std::vector<std::uint8_t> kept(s.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!s[at(x, y)]) continue;
      int n = 0;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) n += inside(x + dx, y + dy) && s[at(x + dx, y + dy)];
      kept[at(x, y)] = n >= 3;
    }
  return kept;
}

MaskPieces mask_pieces(const std::vector<std::uint8_t>& mask, int w, int h) {
  const std::size_t n = std::size_t(w) * std::size_t(h);
  MaskPieces m;
  m.piece.assign(n, 0);
  std::vector<std::size_t> stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (!mask[start] || m.piece[start]) continue;
    m.size.push_back(0);
    const auto id = std::uint32_t(m.size.size());
    stack.assign(1, start);
    m.piece[start] = id;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      ++m.size.back();
      const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const std::size_t j = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
          if (mask[j] && !m.piece[j]) m.piece[j] = id, stack.push_back(j);
        }
    }
  }
  return m;
}

std::vector<float> silhouette_piece_opacity(const std::vector<std::uint8_t>& mask, int w, int h, double min_pixels) {
  const MaskPieces m = mask_pieces(mask, w, h);
  std::vector<float> opacity(m.piece.size(), 0.0f);
  for (std::size_t i = 0; i < opacity.size(); ++i)
    if (m.piece[i]) opacity[i] = piece_opacity(double(m.size[m.piece[i] - 1]), min_pixels);
  return opacity;
}

}  // namespace renderer
