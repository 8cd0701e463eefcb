#pragma once
// Every option of a rendered frame, declared once: name, type (number with range and unit,
// integer, bool, enum, colour, list, size, point), default, group and help. terrain-render's
// command line and the viewer's panel are generated from this table, a frames CSV's
// columns are its per-frame options, and set_option / validate are the one check of all
// three. RenderSettings{} holds the table's defaults (a test locks that).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "renderer/core/crease.hpp"
#include "renderer/core/frame_params.hpp"

namespace renderer {

// Everything a frame is drawn with besides the mesh and the drainage database.
struct RenderSettings {
  FrameParams frame;
  Style style;
  CreaseRules rules;
  Layers layers;
  int width = 1280, height = 720;
  // Every line width and the pixel lengths of the crease stroke rules (hidden gap, peek)
  // times this (drawn_style): a print-size frame keeps the look of a screen-size one.
  double line_scale = 1.0;
  ViewMode view = ViewMode::Auto;  // --view: the camera when none is given
  std::string view_row;            // ViewMode::Row: "FRAMES.csv:N" as given
};

// The style a frame is drawn with: s.style with its line widths and stroke pixel lengths
// scaled by s.line_scale (the silhouette width rounded; validate keeps it in 1 .. 9).
Style drawn_style(const RenderSettings& s);

enum class OptionType {
  Number,   // a real number in [min, max], in `unit`
  Integer,  // a whole number in [min, max]
  Bool,     // a flag: "true" / "false" (on the command line, given or not)
  Enum,     // one of `choices`
  Colour,   // #rrggbb, r,g,b (0..255) or a name (parse_colour)
  List,     // a comma list of `choices`
  Size,     // WIDTHxHEIGHT in pixels
  Point,    // three numbers E N Z (metres), or "" for none
};

// The type as --help and --list-options write it: NUMBER, INTEGER, FLAG, CHOICE, COLOUR,
// LIST, WxH, "E N Z".
const char* option_type_name(OptionType t);

struct OptionSpec {
  std::string name;   // the command line's --NAME; a frames CSV column NAME with '-' as '_'
  std::string group;  // the --help section and the viewer's panel header
  OptionType type = OptionType::Number;
  double min = 0, max = 0;           // Number and Integer
  std::string unit;                  // Number: "degrees", "pixels", "mesh spacings", "m", ""
  std::vector<std::string> choices;  // Enum and List
  std::string default_text;          // what RenderSettings{} holds, as the command line writes it
  std::string help;
  bool per_frame = false;  // a column of a frames CSV
  // The option's value in `s` as text set_option reads back.
  std::function<std::string(const RenderSettings& s)> get;
  // Stores a checked value (see set_option); unchecked here.
  std::function<void(RenderSettings& s, const std::string& text)> store;
  // Enum: values outside `choices` it also takes (--view's FRAMES.csv:ROW); none when empty.
  std::function<bool(const std::string& text)> accepts;
  // A width or length in pixels that --line-scale multiplies (drawn_style): the range the
  // drawn value must lie in (validate), where the renderer has one.
  struct Range {
    double min, max;
  };
  std::optional<Range> drawn;
  // Changing it rebuilds the creases from the .dv (the crease network's rules).
  bool rebuilds_creases = false;
  // A Number or Integer whose max is no practical bound (--help shows its unit alone, the
  // viewer's panel a drag field instead of a slider).
  bool unbounded() const { return max >= kUnboundedMax; }
  static constexpr double kUnboundedMax = 1e6;
};

// The table, in the order of --help and the panel.
const std::vector<OptionSpec>& render_options();
// By name, "view-alt" or "view_alt"; nullptr when there is none.
const OptionSpec* find_option(const std::string& name);
// A frames CSV column name: "view_alt".
std::string csv_column(const OptionSpec& o);

// Parses and checks `text` for option `o` (type, range, choices) and stores it in `s`.
// Throws terrain::Error with what is wrong ("1000 is outside -90 .. 90 degrees"), without
// the option's name (the caller says where: --view-alt, a CSV line, the panel).
void set_option(RenderSettings& s, const OptionSpec& o, const std::string& text);

// The checks across options: at least one crease-score weight > 0, and each width or length
// --line-scale multiplies within its drawn range (OptionSpec::drawn); throws terrain::Error.
void validate(const RenderSettings& s);

// "--name value" for every option whose value in `s` differs from the default, in table
// order (the viewer's saved command line).
std::string changed_options(const RenderSettings& s);

}  // namespace renderer
