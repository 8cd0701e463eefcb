// The automatic view (renderer::auto_view, default_view), GL-free, on analytic surfaces: every
// vertex inside the frame, the terrain filling at least 60 % of it (its triangles filled at
// the frame's own size, not the view's coarse estimate), the relief's axis, the light from
// the upper left of the image.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/core/camera.hpp"
#include "test_support.hpp"

namespace renderer {
namespace {

using Eigen::Vector3d;

struct Fit {
  std::size_t outside = 0;  // vertices projected outside the frame or behind the eye
  double coverage = 0;      // share of the frame's pixels inside the mesh's projected triangles
};

Fit check(const terrain::GridMesh& mesh, const Camera& cam, int w, int h) {
  const Vector3d origin(mesh.geo.origin_x, mesh.geo.origin_y, mesh.geo.origin_z);
  Box box{Vector3d::Constant(1e300), Vector3d::Constant(-1e300)};
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {
    box.lo = box.lo.cwiseMin(mesh.positions[i].cast<double>());
    box.hi = box.hi.cwiseMax(mesh.positions[i].cast<double>());
  }
  const View v = make_view(cam, origin, box, w, h);
  Fit f;
  std::vector<Projected> p(mesh.n_vertices());
  for (std::size_t i = 0; i < p.size(); ++i) {
    p[i] = project(v, mesh.positions[i].cast<double>());
    f.outside += !p[i].in_front || p[i].u < 0 || p[i].u > w || p[i].v < 0 || p[i].v > h;
  }
  std::vector<std::uint8_t> in(std::size_t(w * h), 0);
  for (std::size_t t = 0; t < mesh.n_faces(); ++t) {
    const auto tri = mesh.topo.face(t);
    const Projected &a = p[tri[0]], &b = p[tri[1]], &c = p[tri[2]];
    const double area = (b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v);
    if (area == 0) continue;
    for (int y = std::max(0, int(std::min({a.v, b.v, c.v})));
         y < std::min(h, int(std::max({a.v, b.v, c.v})) + 1); ++y)
      for (int x = std::max(0, int(std::min({a.u, b.u, c.u})));
           x < std::min(w, int(std::max({a.u, b.u, c.u})) + 1); ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((b.u - px) * (c.v - py) - (c.u - px) * (b.v - py)) / area;
        const double w1 = ((c.u - px) * (a.v - py) - (a.u - px) * (c.v - py)) / area;
        if (w0 >= 0 && w1 >= 0 && w0 + w1 <= 1) in[std::size_t(y * w + x)] = 1;
      }
  }
  f.coverage = double(std::count(in.begin(), in.end(), 1)) / double(in.size());
  return f;
}

// A cone (no preferred axis) and a ramp rising to the east (its gradients all along the
// east-west axis): the whole terrain in the frame and filling it; the ramp's relief axis
// east-west (bearing 90) with anisotropy 1, the cone's anisotropy near 0; the light from
// 45 degrees left of the line of sight.
TEST(AutoView, ConeAndRampAreWholeAndFillTheFrame) {
  const auto cone = terrain::test::function_mesh(81, 101, 50, [](double x, double y) {
    return std::max(0.0, 1500.0 - 0.6 * std::hypot(x - 2500, y + 2000));
  });
  const auto ramp =
      terrain::test::function_mesh(61, 121, 50, [](double x, double) { return 0.15 * x; });
  for (const auto* mesh : {&cone, &ramp}) {
    const bool is_ramp = mesh == &ramp;
    const AutoView av = auto_view(*mesh, 1.0, 35, 16.0 / 9.0, 30.0, true);
    ASSERT_TRUE(av.camera.eye.has_value());
    const Fit f = check(*mesh, av.camera, 640, 360);
    EXPECT_EQ(f.outside, 0u) << is_ramp;
    EXPECT_GE(f.coverage, 0.6) << is_ramp;
    EXPECT_NEAR(f.coverage, av.coverage, 0.05) << "the coarse estimate";
    EXPECT_GE(av.camera.view_alt, 30.0);
    EXPECT_LE(av.camera.view_alt, 55.0);
    EXPECT_NEAR(std::fmod(av.light.azimuth - av.camera.view_az + 720, 360.0), 315.0, 1e-9);
    EXPECT_EQ(av.light.altitude, 45.0);
    if (is_ramp) {
      EXPECT_NEAR(av.relief_axis, 90.0, 1e-6);
      EXPECT_NEAR(av.anisotropy, 1.0, 1e-6);
    } else {
      EXPECT_LT(av.anisotropy, 0.2);
    }
  }
  // A fixed altitude is kept; Top looks straight down with every vertex in the frame.
  EXPECT_EQ(auto_view(cone, 1.0, 35, 16.0 / 9.0, 30.0, false).camera.view_alt, 30.0);
  const DefaultView top = default_view(ramp, ViewMode::Top, 1.0, 35, 16.0 / 9.0);
  EXPECT_EQ(top.camera.view_alt, 90.0);
  EXPECT_EQ(check(ramp, top.camera, 640, 360).outside, 0u);
}

}  // namespace
}  // namespace renderer
