#include "render_cli.hpp"

#include "common.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <nlohmann/json.hpp>

#include "terrain/error.hpp"

namespace terrain::tools {

namespace rr = renderer;

// One CLI option per table row (only the per-frame ones for `path`), checked by set_option.
void print_render_options(std::ostream& out, const std::string& format) {
  if (format != "json") {
    for (const rr::OptionSpec& o : rr::render_options())
      out << o.name << "\t" << o.group << "\t" << rr::option_type_name(o.type) << "\t"
          << o.default_text << "\n";
    return;
  }
  nlohmann::json all = nlohmann::json::array();
  for (const rr::OptionSpec& o : rr::render_options()) {
    const bool ranged = o.type == rr::OptionType::Number || o.type == rr::OptionType::Integer;
    nlohmann::json j = {
        {"name", o.name}, {"group", o.group},        {"type", rr::option_type_name(o.type)},
        {"unit", o.unit}, {"choices", o.choices},    {"default", o.default_text},
        {"help", o.help}, {"per_frame", o.per_frame}};
    j["min"] = ranged ? nlohmann::json(o.min) : nlohmann::json();
    j["max"] = ranged && !o.unbounded() ? nlohmann::json(o.max) : nlohmann::json();
    all.push_back(std::move(j));
  }
  out << all.dump(1) << "\n";
}

void add_list_options_flag(CLI::App* app, std::string& format) {
  app->add_flag("--list-options{tsv}", format,
                "Print the render options and exit: a line each (name, group, type, default), "
                "or with =json every field as JSON (for programs: a QGIS Processing provider)")
      ->check(CLI::IsMember({"tsv", "json"}));
}

void add_table_options(CLI::App* app, TableArgs& a, bool per_frame_only) {
  for (const rr::OptionSpec& o : rr::render_options()) {
    if (per_frame_only && !o.per_frame) continue;
    const std::string flag = "--" + o.name;
    CLI::Option* opt = nullptr;
    if (o.type == rr::OptionType::Bool) {
      opt = app->add_flag(flag, a.flags[o.name], o.help);
    } else if (o.type == rr::OptionType::Point) {
      opt = app->add_option(flag, a.eye, o.help)->expected(3);
    } else {
      const bool numeric = o.type == rr::OptionType::Number || o.type == rr::OptionType::Integer;
      const std::string range = !numeric        ? std::string()
                                : o.unbounded() ? o.unit
                                                : fmt::format("{:g} .. {:g}{}", o.min, o.max,
                                                              o.unit.empty() ? "" : " " + o.unit);
      opt = app->add_option(flag, a.text[o.name], o.help)->default_str(o.default_text);
      opt->check(CLI::Validator(
          [&o](std::string& v) {
            rr::RenderSettings scratch;
            try {
              rr::set_option(scratch, o, v);
              return std::string();
            } catch (const terrain::Error& e) {
              return std::string(e.what());
            }
          },
          range));
    }
    opt->group(o.group)->type_name(o.type == rr::OptionType::Bool ? ""
                                                                  : rr::option_type_name(o.type));
    if (o.type == rr::OptionType::Enum)
      opt->type_name("{" + fmt::format("{}", fmt::join(o.choices, ",")) + "}");
    a.given[o.name] = opt;
  }
}

// The settings the command line gives: the table's defaults and every option given.
rr::RenderSettings settings_of(const TableArgs& a) {
  rr::RenderSettings s;
  for (const rr::OptionSpec& o : rr::render_options()) {
    if (!a.was_given(o.name)) continue;
    const std::string v =
        o.type == rr::OptionType::Bool    ? std::string(a.flags.at(o.name) ? "true" : "false")
        : o.type == rr::OptionType::Point ? fmt::format("{} {} {}", a.eye[0], a.eye[1], a.eye[2])
                                          : a.text.at(o.name);
    try {
      rr::set_option(s, o, v);
    } catch (const terrain::Error& e) {
      throw CLI::ValidationError("--" + o.name, e.what());
    }
  }
  try {
    rr::validate(s);
  } catch (const terrain::Error& e) {
    throw CLI::ValidationError(e.what());
  }
  return s;
}

void add_vector_options(CLI::App* app, rr::VectorOptions& o) {
  app->add_option("--dpi", o.dpi,
                  "SVG / PDF: pixels per inch of the page (the frame's size in pixels is the page)")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  app->add_option(
         "--vector-underlay", o.underlay,
         "SVG / PDF: what lies under the lines: none, mask (the surface as filled regions) or "
         "shaded (the "
         "shaded relief as an embedded image); default: shaded when --layers has shaded, else mask")
      ->check(CLI::IsMember({"none", "mask", "shaded"}));
}

std::string vector_options_text(const rr::VectorOptions& o) {
  return (o.dpi != rr::VectorOptions{}.dpi ? fmt::format(" --dpi {:g}", o.dpi) : std::string()) +
         (o.underlay.empty() ? std::string() : " --vector-underlay " + o.underlay);
}

void add_vertex_memory_option(CLI::App* app, double& mib, const std::string& reads) {
  add_memory_option(*app, mib,
                    "MiB the mesh's vertices may take: a larger mesh with a pyramid beside it "
                    "(dem2mesh --pyramid) is read " +
                        reads,
                    0.001);
}

}  // namespace terrain::tools
