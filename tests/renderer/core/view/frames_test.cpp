// renderer/core/src/view/frames.cpp: frames CSVs (columns, defaults, errors naming the line), the
// straight path, the layer list.
#include <gtest/gtest.h>

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

TEST(Frames, ParsesColumnsAndDefaults) {
  FrameParams d;
  d.camera.fov = 22;
  const auto f = renderer::parse_frames_csv(
      "# comment\neasting,northing,elevation,view_az\n1,2,3,45\n\n4,5,6,90\n", d, "f.csv");
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(*f[1].camera.eye, Vector3d(4, 5, 6));
  EXPECT_EQ(f[1].camera.view_az, 90);
  EXPECT_EQ(f[0].camera.fov, 22);  // missing column: the default
  const auto g = renderer::parse_frames_csv("min_score\n0.3\n", d, "g.csv");
  EXPECT_FALSE(g[0].camera.eye.has_value());
  EXPECT_EQ(g[0].score.min_score, 0.3);
}

TEST(Frames, ErrorsNameTheLine) {
  const FrameParams d;
  auto message = [&](const std::string& text) {
    try {
      renderer::parse_frames_csv(text, d, "f.csv");
    } catch (const terrain::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("view_az,foo\n1,2\n").find("f.csv:1: unknown column 'foo'"), std::string::npos);
  EXPECT_NE(message("# c\nview_az,fov\n1,2\n3\n").find("f.csv:4: expected 2 fields, found 1"),
            std::string::npos);
  EXPECT_NE(message("view_az,fov\n1,abc\n").find("f.csv:2: field 'fov': 'abc' is not a number"),
            std::string::npos);
  EXPECT_NE(message("easting,northing\n1,2\n").find("f.csv:1:"), std::string::npos);
  EXPECT_NE(message("view_az\n").find("f.csv:1: no frames"), std::string::npos);
  EXPECT_NE(message("fov\n0\n").find("f.csv:2:"), std::string::npos);
}

TEST(Frames, StraightPath) {
  renderer::FlightPath p{{0, 0, 100}, {300, 400, 200}, 3, {}};
  p.params.camera.view_az = std::nan("");
  const auto frames = renderer::parse_frames_csv(renderer::path_csv(p), FrameParams{}, "path");
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(*frames[1].camera.eye, Vector3d(150, 200, 150));
  EXPECT_NEAR(frames[2].camera.view_az, std::atan2(300, 400) * 180 / std::numbers::pi, 1e-9);
}

TEST(Layers, Parse) {
  const auto l = renderer::parse_layers("shaded, creases");
  EXPECT_TRUE(l.shaded && l.creases && !l.mask && !l.silhouettes);
  // Only the layers named, whatever Layers{} draws by default (hachures among them), and
  // every layer reads back from its name.
  for (const renderer::LayerName& n : renderer::kLayerNames) {
    const renderer::Layers one = renderer::parse_layers(n.name);
    for (const renderer::LayerName& m : renderer::kLayerNames)
      EXPECT_EQ(one.*(m.flag), &m == &n || (std::string(n.name) == "silhouettes-adjacency" &&
                                            std::string(m.name) == "silhouettes"))
          << n.name << " sets " << m.name;
  }
  EXPECT_EQ(renderer::layers_text(renderer::Layers{}), "mask,creases,silhouettes,hachures,ridges");
  EXPECT_THROW(renderer::parse_layers("mask,contours"), terrain::Error);
  EXPECT_TRUE(renderer::parse_layers("mask,pels").pels);
  EXPECT_THROW(renderer::parse_layers("shaded,mask"), terrain::Error);
  EXPECT_EQ(renderer::parse_colour("#ff8000"), Eigen::Vector3f(1, 128 / 255.f, 0));
  EXPECT_THROW(renderer::parse_colour("#zz0000"), terrain::Error);
}

}  // namespace
