// renderer/gl/src/gl/shader.cpp: a shader's log names its file.
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

TEST(Shader, LogLocationsNameTheFile) {
  EXPECT_EQ(renderer::map_log_locations("1:12(3): error: x", {"a.glsl", "b.glsl"}),
            "a.glsl:12: error: x");
  EXPECT_EQ(renderer::map_log_locations("2(7) : error C0000", {"a.glsl", "b.glsl"}),
            "b.glsl:7 : error C0000");
}

}  // namespace
