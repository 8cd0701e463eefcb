#pragma once
// The render options' command line, generated from the renderer's option table
// (renderer/core/options.hpp): terrain-render's frame, batch and path, and terrain-view.
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "renderer/core/options.hpp"
#include "renderer/core/vector_file.hpp"

namespace terrain::tools {

// The table's options as CLI11 fills them (text, flags, the eye's three numbers).
struct TableArgs {
  std::map<std::string, std::string> text;
  std::map<std::string, bool> flags;
  std::vector<double> eye;
  std::map<std::string, CLI::Option*> given;
  bool line_stats = false;
  bool was_given(const std::string& name) const {
    return given.count(name) && given.at(name)->count() > 0;
  }
};

// The table for people and programs (a QGIS Processing provider builds its parameters from
// it): `format` tsv, a line an option (name, group, type, default), or json, an array of
// objects with every field (name, group, type, min, max, unit, choices, default, help,
// per_frame); --list-options and --list-options=json of terrain-render and terrain-view.
void print_render_options(std::ostream& out, const std::string& format);
// Adds that flag to `app`: `format` set to tsv or json when given.
void add_list_options_flag(CLI::App* app, std::string& format);

// One option per table row (only the per-frame ones with `per_frame_only`), in the table's
// groups, each checked by renderer::set_option (a bad value is a usage error, exit 2).
void add_table_options(CLI::App* app, TableArgs& a, bool per_frame_only);

// The settings the command line gives: the table's defaults and every option given, then
// renderer::validate.
renderer::RenderSettings settings_of(const TableArgs& a);

// --dpi and --vector-underlay: how an SVG or PDF is written (terrain-render frame and
// batch, terrain-view's save-view).
void add_vector_options(CLI::App* app, renderer::VectorOptions& o);
// --memory: the MiB the mesh's vertices may take, a larger mesh read from its pyramid at the
// level `reads` says (terrain-render frame and batch, terrain-view).
void add_vertex_memory_option(CLI::App* app, double& mib, const std::string& reads);
// The same as command-line text, where they differ from the defaults (" --dpi 300").
std::string vector_options_text(const renderer::VectorOptions& o);

}  // namespace terrain::tools
