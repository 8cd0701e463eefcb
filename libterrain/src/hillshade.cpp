#include "terrain/hillshade.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "terrain/grid_mesh.hpp"

namespace terrain {

Eigen::Vector3d light_direction(double azimuth_deg, double altitude_deg) {
  const double az = azimuth_deg * std::numbers::pi / 180.0,
               alt = altitude_deg * std::numbers::pi / 180.0;
  return {std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt)};
}

std::vector<std::uint8_t> hillshade(std::span<const Eigen::Vector3f> normals, double azimuth_deg,
                                    double altitude_deg) {
  const Eigen::Vector3f l = light_direction(azimuth_deg, altitude_deg).cast<float>();
  std::vector<std::uint8_t> out(normals.size());
  std::transform(normals.begin(), normals.end(), out.begin(), [&](const Eigen::Vector3f& n) {
    return std::uint8_t(std::lround(255.0f * std::clamp(n.dot(l), 0.0f, 1.0f)));
  });
  return out;
}

std::vector<std::uint8_t> colour_ramp(std::span<const float> values, double lo, double hi) {
  // Five stops of viridis.
  static const double stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  std::vector<std::uint8_t> out(3 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::isnan(values[i])) continue;
    const double t = hi > lo ? std::clamp((double(values[i]) - lo) / (hi - lo), 0.0, 1.0) : 0.0;
    const double x = t * 4;
    const int k = std::min(int(x), 3);
    const double f = x - k;
    for (int c = 0; c < 3; ++c)
      out[3 * i + std::size_t(c)] =
          std::uint8_t(std::lround(stops[k][c] * (1 - f) + stops[k + 1][c] * f));
  }
  return out;
}

std::vector<std::uint8_t> hillshade_grid(const Grid& g, double azimuth_deg, double altitude_deg,
                                         double z_factor) {
  double sx = g.geo.dx, sy = g.geo.dy;
  if (g.geo.crs_kind == CrsKind::Geographic) {
    const double lat = g.geo.y_of_row(double(g.rows) / 2) * std::numbers::pi / 180.0;
    sx *= 111320.0 * std::cos(lat);
    sy *= 110574.0;
  }
  BigVector<Eigen::Vector3f> pos(g.size());
  for (std::size_t r = 0; r < g.rows; ++r)
    for (std::size_t c = 0; c < g.cols; ++c)
      pos[g.index(r, c)] = {float(double(c) * sx), float(-double(r) * sy),
                            float(z_factor * g.at(r, c))};
  std::vector<std::uint8_t> shade = hillshade(
      vertex_normals(pos, {g.rows, g.cols}, NormalWeighting::Area), azimuth_deg, altitude_deg);
  for (std::size_t i = 0; i < g.size(); ++i)
    if (!g.valid(i)) shade[i] = 0;
  return shade;
}

}  // namespace terrain
