// renderer/core/src/view/timing.cpp: the paper's frame rates from pass times.
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

TEST(Timing, PaperFrameRates) {
  // Creases paper, frames 4-99 on a GTX 780: TFT 3.76 AFT 6.07 DM 6.05 SIL 26.09 LAY 0.04.
  const auto f = renderer::frame_fps({3.76, 6.07, 6.05, 26.09, 0.04});
  EXPECT_NEAR(f.crease, 1000 / 9.85, 1e-9);
  EXPECT_NEAR(f.silhouette, 1000 / 35.96, 1e-9);
  EXPECT_NEAR(f.total, 1000 / 42.01, 1e-9);
  std::vector<renderer::FrameTimings> t(5);
  for (int i = 0; i < 5; ++i) t[i].gpu_ms = {double(i + 1), 1, 1, 1, 1};
  const auto s = renderer::summarize(t, 3, 5, false);
  EXPECT_EQ(s.frames, 2u);
  EXPECT_DOUBLE_EQ(s.mean_ms[renderer::TFT], 4.5);
  EXPECT_NE(renderer::timing_tables(t).find("frames 4-N"), std::string::npos);
  const std::string csv = renderer::timings_csv(t);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 6);
}

// The scene's distances: the near distance is the eye's distance to the box (0 inside it),
// the far one to its farthest corner; rs_min then rises from min at the nearest point to
// min + (1 - min) k at the farthest. A given far distance is kept (near 0: the paper's law).

}  // namespace
