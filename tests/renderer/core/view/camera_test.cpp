// renderer/core/src/view/camera.cpp: the default view (the relief from its open side; the crater
// and the dome of Mount St. Helens), projection and framing.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include <map>
#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/pipeline.hpp"
#include "renderer/core/camera.hpp"
#include "renderer/core/crease.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/line_stats.hpp"
#include "renderer/core/pel.hpp"
#include "renderer/core/silhouette.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/core/timing.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/shader.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/pn_surface.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace {

using Eigen::Vector3d;
using renderer::CreaseGeometry;
using renderer::FrameParams;
using renderer::TerrainRenderer;

// The automatic exaggeration on ramps z = k x over 1 km x 1 km (10 m samples): the relief
// between the 1st and 99th percentiles is 0.98 x 1000 k, so e = 0.03 / (0.98 k), to the
// nearest 0.5 within 1 .. 5; a 2 km x 0.5 km extent is the same 1 km geometric mean; a
// flat sheet keeps 1.
TEST(Camera, AutomaticExaggerationFollowsReliefAgainstExtent) {
  auto ramp = [](std::size_t rows, std::size_t cols, double k) {
    return terrain::test::function_mesh(rows, cols, 10, [k](double x, double) { return k * x; });
  };
  EXPECT_EQ(renderer::auto_exaggeration(ramp(101, 101, 0.1)), 1.0);     // ratio 0.098
  EXPECT_EQ(renderer::auto_exaggeration(ramp(101, 101, 0.01)), 3.0);    // 3.06
  EXPECT_EQ(renderer::auto_exaggeration(ramp(101, 101, 0.0075)), 4.0);  // 4.08
  EXPECT_EQ(renderer::auto_exaggeration(ramp(101, 101, 0.001)), 5.0);   // 30.6, at most 5
  EXPECT_EQ(renderer::auto_exaggeration(ramp(51, 201, 0.005)),
            3.0);  // 2000 m x 500 m; relief 9.8 m: 3.06
  EXPECT_EQ(renderer::auto_exaggeration(ramp(101, 101, 0.0)), 1.0);
}

TEST(Camera, DefaultViewFramesTheReliefFromItsOpenSide) {
  const double cx = 6000, cy = -3000;  // local frame: x east, y north (rows go south)
  const auto mesh = terrain::test::function_mesh(161, 201, 50, [&](double x, double y) {
    const double r = std::hypot(x - cx, y - cy);
    const double cone = std::max(0.0, 1200.0 * (1 - r / 2500));
    const double crater = r < 800 ? 600.0 * (1 - r * r / (800.0 * 800.0)) : 0.0;
    // The breach: a trench north from the crater through the rim, 80 % of the cone deep.
    const double breach =
        (y > cy && std::abs(x - cx) < 400) ? 0.8 * cone * (1 - std::abs(x - cx) / 400) : 0.0;
    return cone - crater - breach;
  });
  const auto rv = renderer::relief_view(mesh, 1.0, 35, 16.0 / 9.0);
  EXPECT_LT(std::hypot(rv.centre.x() - cx, rv.centre.y() - cy), 1500) << rv.centre.transpose();
  EXPECT_EQ(rv.camera.view_az, 180.0);
  EXPECT_EQ(rv.light.azimuth, 270.0);  // from the right of a view towards the south: west
  ASSERT_TRUE(rv.camera.eye.has_value());
  EXPECT_GT(rv.camera.eye->y(), cy);  // north of the cone
  EXPECT_NO_THROW(renderer::check_eye_above_terrain(mesh, *rv.camera.eye, 1.0));
  renderer::Box box{Vector3d(0, -8000, 0), Vector3d(10000, 0, 1200)};
  const auto v = renderer::make_view(rv.camera, Vector3d::Zero(), box, 1280, 720);
  const auto c = renderer::project(v, Vector3d(cx, cy, 800));
  EXPECT_GT(c.u, 1280 / 3.0);
  EXPECT_LT(c.u, 2 * 1280 / 3.0);
  EXPECT_GT(c.v, 720 / 3.0);
  EXPECT_LT(c.v, 2 * 720 / 3.0);
}

// The default view on Mount St. Helens (the bundled 2007 DEM as the demo's 50 m mesh):
// it looks into the crater through its breach to the north, the lava dome (summit 2310 m
// at 562490 E 5116070 N in the DEM) in the middle third across and in the upper two thirds
// of the image, the highest point of the crater rim (2538 m, 562060 E 5115640 N) in the
// image beyond it, and the eye above the terrain.
TEST(Camera, DefaultViewOfMountStHelensShowsTheCraterAndTheDome) {
  const terrain::GridMesh& mesh = terrain::test::msh_50m_mesh();
  const int w = 1280, h = 720;
  const auto rv = renderer::relief_view(mesh, 1.0, 35, double(w) / h);
  EXPECT_GE(rv.camera.view_az, 150.0);  // towards the south, through the breach
  EXPECT_LE(rv.camera.view_az, 210.0);
  ASSERT_TRUE(rv.camera.eye.has_value());
  EXPECT_NO_THROW(renderer::check_eye_above_terrain(mesh, *rv.camera.eye, 1.0));
  const auto& g = mesh.geo;
  const Vector3d origin(g.origin_x, g.origin_y, g.origin_z);
  const renderer::Box box{Vector3d(0, -double(mesh.topo.rows - 1) * g.dy, 1300),
                          Vector3d(double(mesh.topo.cols - 1) * g.dx, 0, 2600)};
  const auto v = renderer::make_view(rv.camera, origin, box, w, h);
  const auto dome = renderer::project(v, Vector3d(562490, 5116070, 2310) - origin);
  const auto rim = renderer::project(v, Vector3d(562060, 5115640, 2538) - origin);
  EXPECT_TRUE(dome.in_front);
  EXPECT_GT(dome.u, w / 3.0);
  EXPECT_LT(dome.u, 2 * w / 3.0);
  EXPECT_GT(dome.v, 0.0);
  EXPECT_LT(dome.v, 2 * h / 3.0);
  EXPECT_TRUE(rim.in_front);
  EXPECT_GT(rim.u, 0.0);
  EXPECT_LT(rim.u, double(w));
  EXPECT_GT(rim.v, 0.0);
  EXPECT_LT(rim.v, dome.v);  // the rim beyond the dome
}

// The page scale is the metres a pixel spans at the depth of the scene's centre: a segment
// of 100 m there, across the view, is 100 / scale pixels long on the image, at any view;
// an eye inside the box (a low flight) takes at least 1 m of depth, never a negative one.
TEST(Camera, PageScaleIsMetresPerPixelAtTheScenesCentre) {
  const renderer::Box box{{0, -3000, 100}, {4000, 0, 900}};
  const Vector3d centre = 0.5 * (box.lo + box.hi);
  for (double alt : {10.0, 45.0, 90.0}) {
    renderer::Camera cam;
    cam.view_az = 30;
    cam.view_alt = alt;
    cam.fov = 40;
    for (int height : {360, 720}) {
      const auto v = renderer::make_view(cam, Vector3d::Zero(), box, 2 * height, height);
      const double s = renderer::page_scale(v, box);
      const auto a = renderer::project(v, centre - 50 * v.right),
                 b = renderer::project(v, centre + 50 * v.right);
      EXPECT_NEAR(std::hypot(b.u - a.u, b.v - a.v), 100 / s, 1e-6) << alt << " " << height;
    }
  }
  renderer::Camera inside;
  inside.eye = centre;
  inside.view_alt = 0;
  const auto v = renderer::make_view(inside, Vector3d::Zero(), box, 640, 360);
  EXPECT_DOUBLE_EQ(renderer::page_scale(v, box),
                   2 * std::tan(0.5 * inside.fov * std::numbers::pi / 180) / 360);
}

TEST(Camera, ProjectionAndFraming) {
  renderer::Box box{{0, -3000, 100}, {4000, 0, 900}};
  for (double az : {0.0, 135.0, 225.0}) {
    for (double alt : {5.0, 30.0, 90.0}) {
      renderer::Camera cam;
      cam.view_az = az;
      cam.view_alt = alt;
      const auto v = renderer::make_view(cam, Vector3d::Zero(), box, 640, 360);
      // A point straight ahead projects to the image centre.
      const auto c = renderer::project(v, v.eye + 500 * v.forward);
      EXPECT_NEAR(c.u, 320, 1e-6);
      EXPECT_NEAR(c.v, 180, 1e-6);
      EXPECT_NEAR(c.depth, v.near / 500, 1e-12);  // reversed z
      // Every corner of the framed box is in the image.
      for (int i = 0; i < 8; ++i) {
        const Vector3d p((i & 1) ? box.hi.x() : box.lo.x(), (i & 2) ? box.hi.y() : box.lo.y(),
                         (i & 4) ? box.hi.z() : box.lo.z());
        const auto q = renderer::project(v, p);
        EXPECT_TRUE(q.in_front);
        EXPECT_GE(q.u, -1e-6) << az << " " << alt;
        EXPECT_LE(q.u, 640 + 1e-6);
        EXPECT_GE(q.v, -1e-6);
        EXPECT_LE(q.v, 360 + 1e-6);
      }
    }
  }
  // Up in the world is up in the image; east is right when looking north.
  renderer::Camera north;
  north.view_az = 0;
  north.view_alt = 0;
  north.eye = Vector3d(0, 0, 0);
  const auto v = renderer::make_view(north, Vector3d::Zero(), box, 100, 100);
  EXPECT_LT(renderer::project(v, {0, 100, 10}).v, 50);
  EXPECT_GT(renderer::project(v, {10, 100, 0}).u, 50);
}

}  // namespace

// The orthographic view (--view top): rays are parallel, so a point and the same point
// 500 m lower fall on one pixel; map_scale 0 fits the box's footprint (2 % margin) centred;
// the geotransform takes a pixel back to the world point; window depth is linear in the
// distance from the eye plane (View::depth_distance inverts it) and unproject inverts
// project; the page scale is the map scale. Both depth conventions.
TEST(Camera, OrthographicTopViewIsAMap) {
  const renderer::Box box{{-1000, -3000, 100}, {3000, 0, 900}};
  const Vector3d origin(500000, 4000000, 0);
  for (const bool reversed : {true, false}) {
    renderer::Camera cam;
    cam.view_az = 0;
    cam.view_alt = 90;
    cam.orthographic = true;
    const auto v = renderer::make_view(cam, origin, box, 640, 360, reversed);
    ASSERT_TRUE(v.orthographic());
    EXPECT_DOUBLE_EQ(v.map_scale, 1.02 * 3000 / 360);  // the box's 3000 m north-south in 360 rows
    EXPECT_DOUBLE_EQ(renderer::page_scale(v, box), v.map_scale);
    const auto gt = renderer::map_geotransform(v, origin);
    ASSERT_TRUE(gt.has_value());
    EXPECT_NEAR((*gt)[0] + 320 * (*gt)[1], origin.x() + 1000,
                1e-6);  // the image centred on the box
    EXPECT_NEAR((*gt)[3] + 180 * (*gt)[5], origin.y() - 1500, 1e-6);
    const Eigen::Matrix4d inverse = v.view_projection().inverse();
    for (const Vector3d& p :
         {Vector3d(-1000, -3000, 100), Vector3d(2500, -10, 900), Vector3d(123.4, -2345.6, 512)}) {
      const auto a = renderer::project(v, p), b = renderer::project(v, p - Vector3d(0, 0, 500));
      EXPECT_TRUE(a.in_front);
      EXPECT_NEAR(a.u, b.u, 1e-9);
      EXPECT_NEAR(a.v, b.v, 1e-9);
      EXPECT_GT(renderer::far_depth(reversed, b.depth),
                renderer::far_depth(reversed, a.depth));  // lower is farther
      EXPECT_NEAR(origin.x() + p.x(), (*gt)[0] + a.u * (*gt)[1], 1e-6);
      EXPECT_NEAR(origin.y() + p.y(), (*gt)[3] + a.v * (*gt)[5], 1e-6);
      EXPECT_GE(a.u, 0.0);
      EXPECT_LE(a.u, 640.0);
      EXPECT_GE(a.v, 0.0);
      EXPECT_LE(a.v, 360.0);
      EXPECT_NEAR(v.depth_distance(a.depth), v.viewpoint().distance(p), 1e-6);
      EXPECT_NEAR(v.viewpoint().distance(p), v.eye.z() - p.z(), 1e-9);
      const Vector3d back = renderer::unproject(v, inverse, a.u, a.v, a.depth);
      EXPECT_NEAR((back - p).head<2>().norm(), 0.0,
                  0.5 * std::sqrt(2.0) * v.map_scale + 1e-6);  // the pixel's centre
      EXPECT_NEAR(back.z(), p.z(), 1e-6);
    }
    // The whole box lies between the eye plane and the far plane.
    for (double z : {box.lo.z(), box.hi.z()}) {
      const double d = v.viewpoint().distance({0, 0, z});
      EXPECT_GT(d, 0.0);
      EXPECT_LT(d, v.far);
    }
  }
  // A given scale is kept, centred on the eye; a view turned from north up has no geotransform.
  renderer::Camera cam;
  cam.view_az = 0;
  cam.view_alt = 90;
  cam.orthographic = true;
  cam.map_scale = 2.5;
  cam.eye = origin + Vector3d(100, -200, 5000);
  const auto v = renderer::make_view(cam, origin, box, 640, 360);
  EXPECT_DOUBLE_EQ(v.map_scale, 2.5);
  const auto c = renderer::project(v, {100, -200, 300});
  EXPECT_NEAR(c.u, 320, 1e-9);
  EXPECT_NEAR(c.v, 180, 1e-9);
  cam.view_az = 30;
  EXPECT_FALSE(renderer::map_geotransform(renderer::make_view(cam, origin, box, 640, 360), origin)
                   .has_value());
  // Orthographic facing: the way to the viewer is against the line of sight, wherever the point.
  EXPECT_NEAR((v.viewpoint().to_eye({-900, -50, 100}) - Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
}
