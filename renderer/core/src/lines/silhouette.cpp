#include "renderer/core/silhouette.hpp"
#include "renderer/core/camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

namespace renderer {

std::vector<std::uint8_t> toward_away_silhouettes(const std::vector<float>& toward,
                                                  const std::vector<float>& away, int w, int h,
                                                  bool reversed_z, bool antialias) {
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
        if ((dx != 0 || dy != 0) && inside(x + dx, y + dy) &&
            far_of(toward[at(x + dx, y + dy)]) > a)
          return true;
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

FormulatedView formulated_view(const View& view, double altitude_deg, double strength_deg) {
  FormulatedView f;
  const double rad = std::numbers::pi / 180.0;
  f.strength = float(std::sin(strength_deg * rad));
  Eigen::Vector3d a = view.forward + view.up;
  a.z() = 0;
  if (!(a.norm() > 1e-9)) return f;
  a.normalize();
  const double alt = altitude_deg * rad;
  f.direction = (std::cos(alt) * a - std::sin(alt) * Eigen::Vector3d::UnitZ()).cast<float>();
  // The bearing's image: its components along the screen's right and up.
  const double sx = a.dot(view.right), sy = a.dot(view.up);
  if (!(std::hypot(sx, sy) > 1e-6)) return f;
  const double octant =
      std::round(std::atan2(sy, sx) / (0.25 * std::numbers::pi)) * 0.25 * std::numbers::pi;
  f.step_x = int(std::lround(std::cos(octant)));
  f.step_up = int(std::lround(std::sin(octant)));
  return f;
}

std::vector<std::uint8_t> formulated_silhouettes(const std::vector<float>& normals, int w, int h,
                                                 const FormulatedView& f) {
  std::vector<std::uint8_t> s(std::size_t(w) * std::size_t(h), 0);
  if (!f.active()) return s;
  // As formulated_facing in formulated.glsl, in float.
  auto normal = [&](int x, int y) {
    return &normals[4 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
  };
  auto on = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && normal(x, y)[3] > 0.5f;
  };
  auto g = [&](int x, int y) {
    if (!on(x, y)) return 2.0f;
    float sum = 0, count = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!on(x + dx, y + dy)) continue;
        const float* n = normal(x + dx, y + dy);
        sum += -(n[0] * f.direction.x() + n[1] * f.direction.y() + n[2] * f.direction.z());
        count += 1;
      }
    return sum / count;
  };
  const int dx = f.step_x, dy = -f.step_up;  // rows from the top
  auto ground_in_front = [&](int x, int y) {
    for (int j = 1; j <= kFormulatedReach; ++j)
      if (!on(x - j * dx, y - j * dy)) return false;
    return true;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!(g(x, y) > 0.0f) || !ground_in_front(x, y)) continue;
      float m = g(x + dx, y + dy);
      if (!(m <= 0.0f)) continue;
      for (int j = 2; j <= kFormulatedReach && m > -f.strength; ++j)
        m = std::min(m, g(x + j * dx, y + j * dy));
      s[std::size_t(y) * std::size_t(w) + std::size_t(x)] = m <= -f.strength;
    }
  return s;
}

MaskPieces mask_pieces(const std::vector<std::uint8_t>& mask, int w, int h, int join) {
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
      for (int dy = -join; dy <= join; ++dy)
        for (int dx = -join; dx <= join; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const std::size_t j = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
          if (mask[j] && !m.piece[j]) m.piece[j] = id, stack.push_back(j);
        }
    }
  }
  return m;
}

std::vector<float> silhouette_hidden_share(const std::vector<std::uint8_t>& mask,
                                           const std::vector<float>& distance, int w, int h) {
  std::vector<float> out(mask.size(), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
      if (!mask[i] || !(distance[i] < std::numeric_limits<float>::infinity())) continue;
      float far = distance[i];
      for (int dy = -kHiddenReach; dy <= kHiddenReach; ++dy)
        for (int dx = -kHiddenReach; dx <= kHiddenReach; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < w && yy < h)
            far = std::max(far, distance[std::size_t(yy) * std::size_t(w) + std::size_t(xx)]);
        }
      out[i] = (far - distance[i]) / distance[i];
    }
  return out;
}

std::vector<float> silhouette_piece_opacity(const std::vector<std::uint8_t>& mask, int w, int h,
                                            double min_pixels) {
  const MaskPieces m = mask_pieces(mask, w, h, kSilhouetteJoin);
  std::vector<float> opacity(m.piece.size(), 0.0f);
  for (std::size_t i = 0; i < opacity.size(); ++i)
    if (m.piece[i])
      opacity[i] = piece_opacity(double(m.size[m.piece[i] - 1]), min_pixels, kSilhouetteFade);
  return opacity;
}

}  // namespace renderer
