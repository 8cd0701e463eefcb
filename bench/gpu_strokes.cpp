// The renderer on whatever GPU EGL gives (docs/terrain-render.md, "Hidden runs and
// peeks"): every GLSL program compiles and links there, the DM pass's stroke-visibility
// samples equal the CPU reference (renderer::stroke_visibility) on an analytic terrain with
// 38 polylines of creases seen at 10 degrees, and the DM pass's GPU time, anti-aliased and
// pixel-exact. Exit status 1 when a mask differs in more than 0.01 % of the samples, as in
// RendererGl.StrokeVisibilityMatchesCpu.
// It links only the renderer, epoxy and fmt (no GDAL), so it can be carried to a machine
// with a GPU but without the project's dependencies: build/bin/gpu-strokes with
// libepoxy.so.0, libfmt.so.9 and libgomp.so.1 beside it, run with LD_LIBRARY_PATH there.
#include <cmath>
#include <cstdio>

#include "renderer/core/crease.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/programs.hpp"
#include "renderer/gl/terrain_renderer.hpp"
#include "terrain/grid_mesh.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/pn_surface.hpp"

using namespace renderer;
int main() {
  GlContext ctx;
  std::printf("renderer: %s (%s, %s)\n", ctx.info().renderer.c_str(), ctx.info().platform.c_str(),
              ctx.info().version.c_str());
  for (ProgramId id : kAllPrograms) build_program(id);
  std::printf("all %zu programs built\n", kAllPrograms.size());
  const std::size_t R = 201, C = 201;
  const double h = 20;
  terrain::Georef geo;
  geo.dx = geo.dy = h;
  geo.x0 = -0.5 * h;
  geo.y0 = 0.5 * h;
  geo.crs_kind = terrain::CrsKind::Projected;
  terrain::Grid grid(R, C, geo);
  auto f = [](double x, double y) {
    return 300 * std::sin(x / 500) * std::cos(y / 700) +
           120 * std::abs(std::sin(x / 230 + y / 410)) + 0.05 * y;
  };
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t c = 0; c < C; ++c) grid.at(r, c) = float(f(double(c) * h, -double(r) * h));
  const auto mesh = terrain::make_grid_mesh(grid, terrain::NormalWeighting::Area);
  // Crease lines: north-south polylines every 100 m, 5 m steps, following the surface.
  CreaseGeometry g;
  for (int line = 0; line < 38; ++line) {
    const std::uint32_t first = std::uint32_t(g.positions.size());
    const int n = 780;
    for (int i = 0; i < n; ++i) {
      const auto sp = terrain::pn_point_above(mesh, 100.0 + 100.0 * line, -50.0 - 5.0 * i);
      g.positions.push_back(sp->position.cast<float>());
      g.normals.push_back(sp->normal.cast<float>());
      g.flow.push_back(float(i + 1) / float(n));
      g.share.push_back(g.flow.back());
      g.source.push_back(first + std::uint32_t(i));
      if (i > 0)
        g.segments.insert(g.segments.end(),
                          {first + std::uint32_t(i) - 1, first + std::uint32_t(i)});
    }
  }
  Style style;
  style.crease_bridge = style.crease_bridge_px = 0;
  style.crease_min_stroke = style.crease_min_stroke_px = 0;
  style.page_min_area = 0;
  const int w = 1280, hgt = 720;
  TerrainRenderer r(ctx, mesh, &g, w, hgt, Layers{false, true, true, false}, style);
  FrameParams fp;
  fp.camera.view_az = 200;
  fp.camera.view_alt = 10;
  fp.score.min_score = 0;
  fp.score.falloff = 0;
  FrameResult res;
  for (int k = 0; k < 6; ++k) {
    res = r.render(fp);
    std::printf("anti-aliased, frame %d: DM %.3f ms (GL timer), crease segments %zu\n", k,
                res.timings.gpu_ms[DM], res.crease_segments);
  }
  const auto gpu = r.read_crease_samples();
  const auto buffers = r.read_buffers();
  const Eigen::Vector3d light = terrain::light_direction(fp.light.azimuth, fp.light.altitude);
  const auto score = resolve_distances(fp.score, r.box().lo, r.box().hi, res.view.viewpoint());
  const auto drawn = segment_opacity(g, res.view.viewpoint(), light, 1.0, score, style.crease_fade,
                                     stroke_rule(style, page_scale(res.view, r.box())));
  const auto cpu =
      stroke_visibility(g, segment_chains(g), drawn, res.view, 1.0, crease_lift(style, mesh),
                        buffers.toward_depth, stroke_visibility_rule(style, mesh));
  const SampleComparison c = compare_samples(cpu, gpu);
  std::printf(
      "%zu segments drawn, %zu with another sample count; of %zu samples: %zu / %zu / %zu / %zu "
      "differ "
      "(visible, bridgeable, closed, shown); %zu hidden drawn, %zu peek samples left out\n",
      c.segments, c.other_count, c.samples, c.differ[0], c.differ[1], c.differ[2], c.differ[3],
      c.hidden_drawn, c.peeks);
  Style aliased = style;
  aliased.antialias = false;
  TerrainRenderer ra(ctx, mesh, &g, w, hgt, Layers{false, true, true, false}, aliased);
  for (int k = 0; k < 3; ++k)
    std::printf("pixel-exact, frame %d: DM %.3f ms (GL timer)\n", k,
                ra.render(fp).timings.gpu_ms[DM]);
  bool agree = c.segments > 0 && double(c.other_count) <= 0.005 * double(c.segments);
  for (int j = 0; j < 4; ++j) agree = agree && double(c.differ[j]) <= 1e-4 * double(c.samples);
  return agree ? 0 : 1;
}
