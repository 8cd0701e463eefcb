#include "terrain/hillshade.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace terrain {

Eigen::Vector3d light_direction(double azimuth_deg, double altitude_deg) {
  const double az = azimuth_deg * std::numbers::pi / 180.0, alt = altitude_deg * std::numbers::pi / 180.0;
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

}  // namespace terrain
