// gpu-flight SCENE FRAMES.csv [terrain-render options]: the renderer's flight on whatever
// GPU EGL gives, as `terrain-render batch` times it (issue 40, target 5): every frame of
// FRAMES.csv drawn with the options' layers and style, then the device (GPU and driver), the
// paper's Tables 3 and 4 (GL timer queries and wall clock) and, when the PEL layer is drawn,
// the PEL pass in triangles per second. No images are written.
// SCENE comes from gpu-flight-scene (gpu_scene.hpp). Like gpu-strokes, this links only the
// renderer, epoxy, fmt and gomp, so bench/gpu_flight.sh can carry it to a machine with a
// GPU but without the project's other dependencies.
#include <cstdio>
#include <exception>

#include "gpu_scene.hpp"
#include "renderer/core/frames.hpp"
#include "renderer/core/timing.hpp"
#include "renderer/gl/gl_context.hpp"
#include "renderer/gl/terrain_renderer.hpp"

using namespace renderer;

int main(int argc, char** argv) {
  try {
    RenderSettings s;
    const auto args = gpu_scene::parse_args(argc, argv, s);
    if (args.size() != 2) {
      std::fprintf(stderr, "usage: gpu-flight SCENE FRAMES.csv [terrain-render options]\n");
      return 2;
    }
    const gpu_scene::Scene scene = gpu_scene::read(args[0]);
    const std::vector<FrameParams> frames = read_frames_csv(args[1], s.frame);
    GlContext ctx;
    const Style style = drawn_style(s);
    TerrainRenderer r(ctx, scene.mesh, scene.creases ? &*scene.creases : nullptr, s.width, s.height,
                      s.layers, style);
    std::vector<FrameTimings> timings;
    for (const FrameParams& f : frames) timings.push_back(r.render(f).timings);
    std::printf("renderer: %s (%s, OpenGL %s)\n", ctx.info().renderer.c_str(),
                ctx.info().platform.c_str(), ctx.info().version.c_str());
    std::printf("scene: %zu vertices, %zu faces, %zu crease segments; %zu frames at %d x %d\n",
                scene.mesh.n_vertices(), scene.mesh.n_faces(),
                scene.creases ? scene.creases->n_segments() : std::size_t(0), frames.size(),
                s.width, s.height);
    std::fputs(timing_tables(timings).c_str(), stdout);
    if (s.layers.pels && frames.size() > 3) {
      const TimingSummary t = summarize(timings, 3, timings.size(), false);
      std::printf("PEL pass, frames 4-N (GL timer): %.3f ms, %.1f M triangles/s (%zu triangles)\n",
                  t.mean_ms[PEL], double(scene.mesh.n_faces()) / (t.mean_ms[PEL] * 1e3),
                  scene.mesh.n_faces());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gpu-flight: %s\n", e.what());
    return 1;
  }
}
