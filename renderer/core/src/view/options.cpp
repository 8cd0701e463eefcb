#include "renderer/core/options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>

#include "option_rows.hpp"
#include "renderer/core/frames.hpp"
#include "terrain/error.hpp"

namespace renderer {

namespace {

using namespace detail;

std::vector<OptionSpec> make_table() {
  const GroupNames g;
  const std::string& rules = g.rules;
  std::vector<OptionSpec> t;
  add_frame_options(t, g);
  add_camera_options(t, g);
  add_score_options(t, g);
  add_network_options(t, g);
  add_strokes_options(t, g);
  add_lines_options(t, g);
  add_look_options(t, g);
  add_hachure_options(t, g);
  // What --line-scale multiplies with a range the renderer draws it in (terrain_renderer.cpp's
  // buffers and pixel loops), and what rebuilds the creases.
  const std::map<std::string, OptionSpec::Range> drawn = {
      {"silhouette-width", {1, 9}},    {"edge-width", {0, 64}},
      {"crease-hidden-gap", {0, 256}}, {"crease-min-peek", {0, 256}},
      {"crease-bridge-px", {0, 256}},  {"crease-min-stroke-px", {0, 256}},
      {"hachure-spacing", {1, 256}},   {"hachure-width", {0.1, 64}},
      {"ridge-width", {0.1, 64}}};
  for (OptionSpec& o : t) {
    if (const auto d = drawn.find(o.name); d != drawn.end()) {
      o.drawn = d->second;
      o.help += fmt::format(" (drawn, times --line-scale: {:g} .. {:g} {})", d->second.min,
                            d->second.max, o.unit);
    }
    o.rebuilds_creases = o.group == rules;
  }
  return t;
}

}  // namespace

Style drawn_style(const RenderSettings& s) {
  Style st = s.style;
  const double k = s.line_scale;
  st.crease_width *= k;
  st.crease_width_max *= k;
  st.silhouette_width = int(std::lround(st.silhouette_width * k));  // validate keeps it in 1 .. 9
  st.pel_width *= k;
  st.edge_width *= k;
  st.crease_hidden_gap *= k;
  st.crease_min_peek *= k;
  st.crease_bridge_px *= k;
  st.hachure_spacing *= k;
  st.hachure_width *= k;
  st.ridge_width *= k;
  st.crease_min_stroke_px *= k;
  return st;
}

const char* option_type_name(OptionType t) {
  static const char* const kNames[] = {"NUMBER", "INTEGER", "FLAG", "CHOICE",
                                       "COLOUR", "LIST",    "WxH",  "E N Z"};
  return kNames[int(t)];
}

const std::vector<OptionSpec>& render_options() {
  static const std::vector<OptionSpec> table = make_table();
  return table;
}

std::string csv_column(const OptionSpec& o) {
  std::string c = o.name;
  std::replace(c.begin(), c.end(), '-', '_');
  return c;
}

const OptionSpec* find_option(const std::string& name) {
  for (const OptionSpec& o : render_options())
    if (o.name == name || csv_column(o) == name) return &o;
  return nullptr;
}

void set_option(RenderSettings& s, const OptionSpec& o, const std::string& text) {
  switch (o.type) {
    case OptionType::Number:
    case OptionType::Integer: {
      if (text == "auto" && o.default_text == "auto") break;  // an option whose default is computed
      double v = 0;
      if (!parse_number(text, v) || !std::isfinite(v))
        throw terrain::Error("'" + text + "' is not a number");
      if (o.type == OptionType::Integer && v != std::floor(v))
        throw terrain::Error("'" + text + "' is not a whole number");
      if (v < o.min || v > o.max)
        throw terrain::Error(fmt::format("{} is outside {:g} .. {:g}{}", text, o.min, o.max,
                                         o.unit.empty() ? "" : " " + o.unit));
      break;
    }
    case OptionType::Bool:
      if (text != "true" && text != "false")
        throw terrain::Error("'" + text + "' is not true or false");
      break;
    case OptionType::Enum:
      if (o.accepts && o.accepts(text)) break;
      if (std::find(o.choices.begin(), o.choices.end(), text) == o.choices.end())
        throw terrain::Error(fmt::format("'{}' is not one of {}", text, join(o.choices)));
      break;
    case OptionType::Size: {
      int w = 0, h = 0;
      char x = 0, extra = 0;
      if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
        throw terrain::Error("expected WIDTHxHEIGHT, e.g. 1280x720, got '" + text + "'");
      if (w < kMinFrameSide || h < kMinFrameSide || w > kMaxFrameSide || h > kMaxFrameSide)
        throw terrain::Error(
            fmt::format("width and height must be in {} .. {}", kMinFrameSide, kMaxFrameSide));
      break;
    }
    case OptionType::Point: {
      double v[3];
      char extra = 0;
      if (!text.empty() &&
          std::sscanf(text.c_str(), "%lf %lf %lf %c", &v[0], &v[1], &v[2], &extra) != 3)
        throw terrain::Error("expected three numbers E N Z, got '" + text + "'");
      if (!text.empty() && !(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])))
        throw terrain::Error("'" + text + "' is not three finite numbers");
      break;
    }
    case OptionType::Colour:
      if (!(o.accepts && o.accepts(text))) (void)parse_colour(text);  // throws with the forms
      break;
    case OptionType::List:
      break;  // stored below: parse_layers / parse_edge_kinds check names and combinations before
              // they assign
  }
  o.store(s, text);
}

void validate(const RenderSettings& s) {
  const auto& sc = s.frame.score;
  if (sc.sw + sc.iw + sc.fw <= 0)
    throw terrain::Error("--sw/--iw/--fw: at least one weight must be > 0");
  // The widths and lengths --line-scale multiplies, drawn: within what the renderer draws.
  for (const OptionSpec& o : render_options()) {
    if (!o.drawn) continue;
    const double v = std::stod(o.get(s));
    const double drawn =
        o.type == OptionType::Integer ? double(std::lround(v * s.line_scale)) : v * s.line_scale;
    if (drawn < o.drawn->min || drawn > o.drawn->max)
      throw terrain::Error(fmt::format(
          "--{} {:g} x --line-scale {:g} = {:g} {} is outside the {:g} .. {:g} {} drawn", o.name, v,
          s.line_scale, drawn, o.unit, o.drawn->min, o.drawn->max, o.unit));
  }
}

std::string changed_options(const RenderSettings& s) {
  const RenderSettings defaults;
  std::string out;
  for (const OptionSpec& o : render_options()) {
    const std::string v = o.get(s);
    if (v == o.get(defaults)) continue;
    if (o.type == OptionType::Bool) {
      if (v == "true") out += " --" + o.name;
      continue;
    }
    out += " --" + o.name + " " + (o.type == OptionType::Point ? v : "'" + v + "'");
  }
  return out;
}

}  // namespace renderer
