#pragma once
// A camera 100 m above the local origin looking straight down, north up, w x h pixels: the
// view the GL-free line tests lay their strokes and depths out under, and its depths.
#include <string>
#include <vector>

#include "renderer/core/camera.hpp"

namespace renderer::test {

inline View top_view(int w, int h, bool reversed = true) {
  Camera camera;
  camera.eye = Eigen::Vector3d(0, 0, 100);
  camera.view_az = 0;
  camera.view_alt = 90;
  return make_view(camera, Eigen::Vector3d::Zero(), Box{{-30, -30, -60}, {30, 30, 60}}, w, h,
                   reversed);
}

// Toward depths by column of a top_view (`columns`: one character a column): 'G' ground
// (z = 0), 'N' a near wall 10 m above it, 'R' a ridge 50 m above it, '.' no surface.
inline std::vector<float> toward_of(const View& view, const std::string& columns) {
  auto depth_at = [&](double z) { return float(project(view, Eigen::Vector3d(0, 0, z)).depth); };
  std::vector<float> t(std::size_t(view.width) * std::size_t(view.height));
  for (int v = 0; v < view.height; ++v)
    for (int u = 0; u < view.width; ++u) {
      const char c = columns[std::size_t(u)];
      t[std::size_t(v * view.width + u)] = c == 'G'   ? depth_at(0)
                                           : c == 'N' ? depth_at(10)
                                           : c == 'R' ? depth_at(50)
                                                      : (view.reversed_z ? 0.0f : 1.0f);
    }
  return t;
}

}  // namespace renderer::test
