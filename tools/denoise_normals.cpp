// denoise-normals: bilateral normal filtering of a terrain mesh, and the Voronoi weights
// that photic extremum lines need, written into the output mesh.
#include <fmt/format.h>

#include <chrono>
#include <iostream>

#include "common.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/denoise.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/voronoi.hpp"

namespace tt = terrain::tools;

namespace {

void add_options(CLI::App& app, std::string& input, std::string& output,
                 terrain::DenoiseOptions& o) {
  app.add_option("MESH", input, "Input mesh (.ply from dem2mesh)")->required();
  app.add_option("OUTPUT", output, "Output mesh (.ply)")->required();
  app.add_option(
         "--sigma-s", o.sigma_s,
         "Spatial width in metres (face-centroid distance); default: the mean distance between the "
         "centroids of edge-adjacent faces")
      ->check(tt::kPositive);
  app.add_option("--sigma-r", o.sigma_r, "Range width on the normal difference |n_i - n_j| (0..2)")
      ->check(CLI::Range(0.01, 2.0))
      ->capture_default_str();
  app.add_option("--iterations", o.iterations,
                 "Normal filtering rounds; 0: no denoising, only the weights")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  app.add_flag("--update-vertices", o.update_vertices,
               "Also move the vertices (vertically) to agree with the filtered normals");
  app.add_option("--vertex-iterations", o.vertex_iterations, "Rounds of the vertex update")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
}

void print_summary(const std::string& output, const terrain::GridMesh& m,
                   const terrain::DenoiseStats& s, const terrain::DenoiseOptions& o) {
  double total_area = 0;
  for (float a : m.voronoi.vertex_areas) total_area += a;
  std::cout << "output: " << output << "\n"
            << "faces: " << m.n_faces() << "\n"
            << fmt::format("sigma_s: {:.4f}\nsigma_r: {}\niterations: {}\n", s.sigma_s, o.sigma_r,
                           o.iterations)
            << "vertices_updated: " << (o.update_vertices && o.iterations > 0 ? "yes" : "no")
            << "\n"
            << fmt::format("max_vertex_shift: {:.4f}\n", s.max_vertex_shift)
            << fmt::format("normal_change_mean_deg: {:.4f}\nnormal_change_max_deg: {:.4f}\n",
                           s.mean_change_deg, s.max_change_deg)
            << fmt::format("voronoi_area_total: {:.1f}\n", total_area);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Denoise a terrain mesh's normals by bilateral normal filtering (Zheng et al. 2011) and "
      "store\n"
      "the per-corner mixed Voronoi areas, per-vertex 'voronoi_area' and tangent frames (Meyer et\n"
      "al. 2001) in the output: the inputs of photic extremum lines (terrain-render --layers "
      "pels).",
      "denoise-normals"};
  app.footer(
      "Examples:\n"
      "  denoise-normals out/msh_10m.ply out/msh_10m_denoised.ply\n"
      "  denoise-normals msh.ply msh_smooth.ply --sigma-r 0.2 --iterations 30 --update-vertices\n"
      "  denoise-normals msh.ply msh_weights.ply --iterations 0     # only add the Voronoi "
      "weights\n\n"
      "Output: stdout gets 'key: value' lines, among them the mean and maximum change of the\n"
      "vertex normals in degrees. See docs/denoise-normals.md.");
  app.set_version_flag("--version", tt::version());
  std::string input, output;
  terrain::DenoiseOptions o;
  tt::Verbosity verb;
  add_options(app, input, output, o);
  tt::add_verbosity_flags(app, verb);

  return tt::run_main(app, argc, argv, [&]() {
    if (!output.ends_with(".ply"))
      throw terrain::Error("OUTPUT must be a .ply file: '" + output + "'");
    tt::check_distinct_paths({input}, {output});
    tt::warn_stale_temporaries(verb, {output});
    terrain::check_output_path(output);
    using clock = std::chrono::steady_clock;
    auto t0 = clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(clock::now() - t0).count(); };
    terrain::GridMesh m = terrain::read_mesh_ply(input);
    tt::step(verb, fmt::format("read {} x {}: {:.2f} s", m.topo.cols, m.topo.rows, seconds()));
    t0 = clock::now();
    const terrain::DenoiseStats s =
        terrain::denoise_normals(m, o, tt::terminal_progress(verb, "denoise"));
    tt::step(verb, fmt::format("filter: {:.2f} s", seconds()));
    t0 = clock::now();
    m.voronoi = terrain::voronoi_weights(m);
    tt::step(verb, fmt::format("Voronoi weights: {:.2f} s", seconds()));
    m.provenance = tt::provenance(argc, argv);
    terrain::write_mesh_ply(m, output);
    print_summary(output, m, s, o);
    return 0;
  });
}
