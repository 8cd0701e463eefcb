#pragma once
// The option table's rows (options.cpp puts them together): the row makers and the groups,
// shared by option_rows_view.cpp and option_rows_lines.cpp. Not installed.
#include <fmt/format.h>

#include <functional>
#include <string>
#include <vector>

#include "renderer/core/frames.hpp"
#include "renderer/core/options.hpp"

namespace renderer::detail {

inline std::string text_of(double v) {
  return fmt::format("{}", v);
}  // shortest text that reads back exactly

inline std::string colour_text(const Eigen::Vector3f& c) {
  return fmt::format("{},{},{}", double(c.x()) * 255.0, double(c.y()) * 255.0,
                     double(c.z()) * 255.0);
}

inline std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ",") + s;
  return out;
}

// Table rows. `ref` is a generic lambda returning a reference to the field in a (const or
// not) RenderSettings.
template <class Ref>
OptionSpec number(std::string name, std::string group, double min, double max, std::string unit,
                  std::string def, std::string help, Ref ref, bool per_frame = false) {
  OptionSpec o{std::move(name),
               std::move(group),
               OptionType::Number,
               min,
               max,
               std::move(unit),
               {},
               std::move(def),
               std::move(help),
               per_frame,
               {},
               {},
               {},
               {},
               false};
  o.get = [ref](const RenderSettings& s) { return text_of(double(ref(s))); };
  o.store = [ref](RenderSettings& s, const std::string& t) {
    double v = 0;
    parse_number(t, v);
    ref(s) = static_cast<std::remove_reference_t<decltype(ref(s))>>(v);
  };
  return o;
}

template <class Ref>
OptionSpec integer(std::string name, std::string group, double min, double max, std::string unit,
                   std::string def, std::string help, Ref ref) {
  OptionSpec o = number(std::move(name), std::move(group), min, max, std::move(unit),
                        std::move(def), std::move(help), ref);
  o.type = OptionType::Integer;
  return o;
}

inline OptionSpec flag(std::string name, std::string group, std::string help,
                       std::function<bool(const RenderSettings&)> get,
                       std::function<void(RenderSettings&, bool)> set) {
  OptionSpec o{std::move(name),
               std::move(group),
               OptionType::Bool,
               0,
               0,
               "",
               {},
               "false",
               std::move(help),
               false,
               {},
               {},
               {},
               {},
               false};
  o.get = [get](const RenderSettings& s) { return std::string(get(s) ? "true" : "false"); };
  o.store = [set](RenderSettings& s, const std::string& t) { set(s, t == "true"); };
  return o;
}

inline OptionSpec choice(std::string name, std::string group, OptionType type,
                         std::vector<std::string> choices, std::string def, std::string help,
                         std::function<std::string(const RenderSettings&)> get,
                         std::function<void(RenderSettings&, const std::string&)> store) {
  return {std::move(name),
          std::move(group),
          type,
          0,
          0,
          "",
          std::move(choices),
          std::move(def),
          std::move(help),
          false,
          std::move(get),
          std::move(store),
          {},
          {},
          false};
}

template <class Ref>
OptionSpec colour(std::string name, std::string group, std::string def, std::string help, Ref ref) {
  return choice(
      std::move(name), std::move(group), OptionType::Colour, {}, std::move(def), std::move(help),
      [ref](const RenderSettings& s) { return colour_text(ref(s)); },
      [ref](RenderSettings& s, const std::string& t) { ref(s) = parse_colour(t); });
}

inline std::vector<std::string> layer_names() {
  std::vector<std::string> v;
  for (const LayerName& n : kLayerNames) v.push_back(n.name);
  return v;
}

inline std::string edges_text(std::uint8_t kinds) {
  std::vector<std::string> v;
  if (kinds & 1) v.push_back("contour");
  if (kinds & 2) v.push_back("boundary");
  if (kinds & 4) v.push_back("crease");
  return join(v);
}

// The table's groups: the --help sections and the viewer's panel headers, in order.
struct GroupNames {
  std::string frame = "Frame", camera = "Camera and light", score = "Crease score",
              rules = "Crease network", strokes = "Crease strokes", sil = "Silhouettes",
              pel = "PELs", edges = "Edges", colours = "Colours", surface = "Surface",
              hachure = "Hachures and ridges";
};

// The options of the frame: size, line scale, layers, view.
void add_frame_options(std::vector<OptionSpec>& t, const GroupNames& g);
// The options of the camera, the light and the exaggeration.
void add_camera_options(std::vector<OptionSpec>& t, const GroupNames& g);
// The options of the crease score (and the PEL threshold, per frame too).
void add_score_options(std::vector<OptionSpec>& t, const GroupNames& g);
// The options of the crease network: which branches become creases.
void add_network_options(std::vector<OptionSpec>& t, const GroupNames& g);
// The options of the crease strokes: widths, fades, bridges, hidden runs.
void add_strokes_options(std::vector<OptionSpec>& t, const GroupNames& g);
// The options of silhouettes, PELs and object-space edges.
void add_hachure_options(std::vector<OptionSpec>& t, const GroupNames& g);
void add_lines_options(std::vector<OptionSpec>& t, const GroupNames& g);
// The options of colours and the surface.
void add_look_options(std::vector<OptionSpec>& t, const GroupNames& g);

}  // namespace renderer::detail
