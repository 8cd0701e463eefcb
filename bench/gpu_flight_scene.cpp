// gpu-flight-scene MESH [DV] OUT.scene [terrain-render options]: the mesh and the creases that
// terrain-render would draw from MESH and DV (with the options' crease rules), as one raw
// file for gpu-flight (gpu_scene.hpp), which is carried to a GPU machine without the
// libraries that read PLY and .dv files. bench/gpu_flight.sh makes the carried folder.
#include <cstdio>
#include <exception>

#include "gpu_scene.hpp"
#include "renderer/scene/scene.hpp"

int main(int argc, char** argv) {
  try {
    renderer::RenderSettings s;
    const auto args = gpu_scene::parse_args(argc, argv, s);
    if (args.size() < 2 || args.size() > 3) {
      std::fprintf(stderr,
                   "usage: gpu-flight-scene MESH [DV] OUT.scene [terrain-render options]\n");
      return 2;
    }
    const renderer::Scene scene =
        renderer::load_scene(args[0], args.size() == 3 ? args[1] : "", s.rules);
    gpu_scene::write(args.back(), scene.mesh, scene.creases ? &*scene.creases : nullptr);
    std::printf("scene: %zu vertices, %zu crease segments -> %s\n", scene.mesh.n_vertices(),
                scene.creases ? scene.creases->n_segments() : std::size_t(0), args.back().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gpu-flight-scene: %s\n", e.what());
    return 1;
  }
}
