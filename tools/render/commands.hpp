#pragma once
// terrain-render's subcommands (tools/terrain_render.cpp parses, these run): frame, batch,
// path and --device, over the renderer and the frame resolved by renderer/scene/frame_setup.hpp.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "common.hpp"
#include "render_cli.hpp"
#include "renderer/scene/frame_setup.hpp"

namespace terrain::tools::render {

// The options besides the render options' table: vector page and underlay, formats; the
// frame's memory bound on the mesh.
struct OutputArgs {
  renderer::VectorOptions vector;
  std::string formats = "png";
  double memory_mib = 1024;
};
void add_output_options(CLI::App* cmd, OutputArgs& o, bool batch);

// --device: the EGL devices and the renderer chosen.
int list_devices();
// path: a straight flight as a frames CSV.
int run_path(const TableArgs& a, const std::vector<double>& from, const std::vector<double>& to,
             int frames, const std::string& out, const std::string& prov);
// frame: one frame to a PNG, SVG or PDF.
int run_frame(const TableArgs& a, const OutputArgs& o, const std::string& mesh,
              const std::string& dv, const std::string& out, const std::string& prov,
              const Verbosity& verb);
// batch: every frame of a frames CSV, timings.csv and the timing tables.
int run_batch(const TableArgs& a, const OutputArgs& o, const std::vector<std::string>& inputs,
              const std::string& out_dir, const std::string& prov, const Verbosity& verb);

}  // namespace terrain::tools::render
