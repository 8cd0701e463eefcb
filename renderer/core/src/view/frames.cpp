#include "renderer/core/frames.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "renderer/core/options.hpp"
#include "terrain/error.hpp"

namespace renderer {

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

}  // namespace

bool parse_number(std::string_view text, double& v) {
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e && b != e && std::isfinite(v);
}

Layers parse_layers(const std::string& list) {
  Layers l;
  for (const LayerName& n : kLayerNames) l.*(n.flag) = false;  // only the layers named
  bool any = false;
  std::string names;
  for (const LayerName& n : kLayerNames) names += (names.empty() ? "" : ", ") + std::string(n.name);
  for (const auto& raw : split(list, ',')) {
    const std::string name = trim(raw);
    const auto* known = std::find_if(std::begin(kLayerNames), std::end(kLayerNames),
                                     [&](const LayerName& n) { return name == n.name; });
    if (known == std::end(kLayerNames))
      throw terrain::Error("unknown layer '" + name + "' (layers: " + names + ")");
    l.*(known->flag) = true;
    any = true;
  }
  if (!any) throw terrain::Error("--layers is empty (layers: " + names + ")");
  if (l.shaded && l.mask) throw terrain::Error("--layers: choose shaded or mask, not both");
  if (l.silhouettes && l.adjacency)
    throw terrain::Error(
        "--layers: choose silhouettes (Toward/Away) or silhouettes-adjacency, not both");
  if (l.adjacency) l.silhouettes = true;  // the silhouette layer, found by the Adjacency method
  return l;
}

std::string layers_text(const Layers& l) {
  std::string out;
  for (const LayerName& n : kLayerNames) {
    // silhouettes-adjacency sets both flags: it is written alone.
    if (n.flag == &Layers::silhouettes && l.adjacency) continue;
    if (!(l.*(n.flag))) continue;
    if (!out.empty()) out += ',';
    out += n.name;
  }
  return out;
}

std::uint8_t parse_edge_kinds(const std::string& list) {
  std::uint8_t kinds = 0;
  for (const auto& raw : split(list, ',')) {
    const std::string name = trim(raw);
    if (name.empty()) continue;
    if (name == "contour")
      kinds |= 1;
    else if (name == "boundary")
      kinds |= 2;
    else if (name == "crease")
      kinds |= 4;
    else
      throw terrain::Error("unknown edge kind '" + name + "' (kinds: contour, boundary, crease)");
  }
  if (!kinds) throw terrain::Error("--edges is empty (kinds: contour, boundary, crease)");
  return kinds;
}

Eigen::Vector3f parse_colour(const std::string& text) {
  static const std::map<std::string, Eigen::Vector3f> names = {
      {"white", {1, 1, 1}},           {"black", {0, 0, 0}},           {"grey", {0.5f, 0.5f, 0.5f}},
      {"gray", {0.5f, 0.5f, 0.5f}},   {"blue", {0.05f, 0.2f, 0.55f}}, {"red", {0.75f, 0.1f, 0.1f}},
      {"brown", {0.45f, 0.3f, 0.15f}}};
  const std::string t = trim(text);
  if (auto it = names.find(t); it != names.end()) return it->second;
  if (t.size() == 7 && t[0] == '#') {
    unsigned v = 0;
    const auto r = std::from_chars(t.data() + 1, t.data() + 7, v, 16);
    if (r.ec == std::errc() && r.ptr == t.data() + 7)
      return Eigen::Vector3f(float((v >> 16) & 255), float((v >> 8) & 255), float(v & 255)) /
             255.0f;
  }
  const auto parts = split(t, ',');
  if (parts.size() == 3) {
    Eigen::Vector3f c;
    bool ok = true;
    for (int i = 0; i < 3; ++i) {
      double v = 0;
      ok = ok && parse_number(trim(parts[i]), v) && v >= 0 && v <= 255;
      c[i] = float(v / 255.0);
    }
    if (ok) return c;
  }
  throw terrain::Error("bad colour '" + text +
                       "' (use #rrggbb, r,g,b in 0..255, or white, black, grey, blue, red, brown)");
}

namespace {

// The columns of FRAMES.csv: the eye's coordinates, then the per-frame options of the
// option table (options.hpp) under their CSV names, each checked as its command-line
// option is (set_option).
const char* const kEyeColumns[] = {"easting", "northing", "elevation"};

std::vector<const OptionSpec*> per_frame_options() {
  std::vector<const OptionSpec*> v;
  for (const OptionSpec& o : render_options())
    if (o.per_frame) v.push_back(&o);
  return v;
}

int eye_index(const std::string& name) {
  for (int k = 0; k < 3; ++k)
    if (name == kEyeColumns[k]) return k;
  return -1;
}

}  // namespace

const std::vector<std::string>& frame_columns() {
  static const std::vector<std::string> cols = [] {
    std::vector<std::string> v(std::begin(kEyeColumns), std::end(kEyeColumns));
    for (const OptionSpec* o : per_frame_options()) v.push_back(csv_column(*o));
    return v;
  }();
  return cols;
}

// The frames CSV's columns, checked: each an eye column (nullptr) or a per-frame option's;
// `eye_columns` gets how many eye columns there are (0 or 3).
static std::vector<const OptionSpec*> header_columns(const std::vector<std::string>& header,
                                                     const std::string& name, int line_no,
                                                     int& eye_columns) {
  auto fail = [&](const std::string& what) {
    throw terrain::Error(fmt::format("{}:{}: {}", name, line_no, what));
  };
  std::vector<const OptionSpec*> columns;
  for (std::size_t i = 0; i < header.size(); ++i) {
    const OptionSpec* o = find_option(header[i]);
    if (eye_index(header[i]) < 0 && (!o || !o->per_frame || csv_column(*o) != header[i]))
      fail(fmt::format("unknown column '{}' (columns: {})", header[i],
                       fmt::join(frame_columns(), " ")));
    if (std::find(header.begin(), header.begin() + long(i), header[i]) != header.begin() + long(i))
      fail(fmt::format("column '{}' appears twice", header[i]));
    eye_columns += eye_index(header[i]) >= 0;
    columns.push_back(eye_index(header[i]) >= 0 ? nullptr : o);
  }
  if (eye_columns != 0 && eye_columns != 3)
    fail("columns easting, northing and elevation go together (all three or none)");
  return columns;
}

std::vector<FrameParams> parse_frames_csv(const std::string& text, const FrameParams& defaults,
                                          const std::string& name) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> header;
  std::vector<FrameParams> frames;
  std::vector<const OptionSpec*> columns;  // nullptr: an eye column
  int line_no = 0, header_line = 0, eye_columns = 0;
  auto fail = [&](int at, const std::string& what) {
    throw terrain::Error(fmt::format("{}:{}: {}", name, at, what));
  };
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    auto fields = split(t, ',');
    for (auto& f : fields) f = trim(f);
    if (header.empty()) {
      header = fields;
      header_line = line_no;
      columns = header_columns(header, name, line_no, eye_columns);
      continue;
    }
    if (fields.size() != header.size())
      fail(line_no, fmt::format("expected {} fields, found {}", header.size(), fields.size()));
    RenderSettings s;
    s.frame = defaults;
    Eigen::Vector3d eye = defaults.camera.eye.value_or(Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (!columns[i]) {
        double v = 0;
        if (!parse_number(fields[i], v))
          fail(line_no, fmt::format("field '{}': '{}' is not a number", header[i], fields[i]));
        eye[eye_index(header[i])] = v;
        continue;
      }
      try {
        set_option(s, *columns[i], fields[i]);
      } catch (const terrain::Error& e) {
        fail(line_no,
             fmt::format("field '{}': {} (as for --{})", header[i], e.what(), columns[i]->name));
      }
    }
    if (eye_columns == 3) s.frame.camera.eye = eye;
    frames.push_back(s.frame);
  }
  if (header.empty()) throw terrain::Error(name + ": no header row");
  if (frames.empty()) fail(header_line, "no frames after the header row");
  return frames;
}

std::vector<FrameParams> read_frames_csv(const std::string& path, const FrameParams& defaults) {
  std::ifstream in(path);
  if (!in) throw terrain::Error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_frames_csv(ss.str(), defaults, path);
}

namespace {

// "FRAMES.csv:N" -> (FRAMES.csv, N); "FRAMES.csv" -> (FRAMES.csv, 0); otherwise no path.
std::pair<std::string, long> split_view_row(const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon != std::string::npos && colon + 1 < text.size() &&
      text.substr(0, colon).ends_with(".csv")) {
    const std::string n = text.substr(colon + 1);
    if (n.find_first_not_of("0123456789") == std::string::npos && n.size() <= 9)
      return {text.substr(0, colon), std::stol(n)};
    return {};
  }
  if (text.ends_with(".csv") && text.size() > 4) return {text, 0};
  return {};
}

}  // namespace

bool is_view_row(const std::string& text) { return !split_view_row(text).first.empty(); }

FrameParams view_row_frame(const std::string& spec, const FrameParams& defaults) {
  const auto [path, row] = split_view_row(spec);
  if (path.empty())
    throw terrain::Error("--view: '" + spec + "' is not FRAMES.csv or FRAMES.csv:ROW");
  const std::vector<FrameParams> frames = read_frames_csv(path, defaults);
  if (std::size_t(row) >= frames.size())
    throw terrain::Error(
        fmt::format("--view: {} has frames 0 .. {}, not {}", path, frames.size() - 1, row));
  return frames[std::size_t(row)];
}

std::string path_csv(const FlightPath& p) {
  if (p.frames < 2) throw terrain::Error("--frames must be at least 2");
  double az = p.params.camera.view_az;
  const Eigen::Vector3d d = p.to - p.from;
  if (std::isnan(az)) {
    if (std::hypot(d.x(), d.y()) == 0)
      throw terrain::Error("--from and --to are vertically aligned: give --view-az");
    az = std::fmod(std::atan2(d.x(), d.y()) * 180.0 / std::numbers::pi + 360.0, 360.0);
  }
  std::vector<FrameParams> frames(std::size_t(p.frames), p.params);
  for (int i = 0; i < p.frames; ++i) {
    frames[std::size_t(i)].camera.view_az = az;
    frames[std::size_t(i)].camera.eye = p.from + d * (double(i) / double(p.frames - 1));
  }
  return frames_csv(frames);
}

std::string frames_csv(const std::vector<FrameParams>& frames) {
  std::string out = fmt::format("{}\n", fmt::join(frame_columns(), ","));  // all columns
  RenderSettings s;
  for (const FrameParams& f : frames) {
    if (!f.camera.eye) throw terrain::Error("frames_csv: a frame without its eye");
    s.frame = f;
    const Eigen::Vector3d& eye = *f.camera.eye;
    out += fmt::format("{:.3f},{:.3f},{:.3f}", eye.x(), eye.y(), eye.z());
    for (const OptionSpec* o : per_frame_options()) {
      out += ',';  // appended piece by piece: `"," + std::string` trips GCC 12's -Wrestrict (PR
                   // 105329)
      out += o->get(s);
    }
    out += "\n";
  }
  return out;
}

std::vector<FrameParams> keyframe_path(const std::vector<FrameParams>& keys, int count) {
  if (keys.size() < 2) throw terrain::Error("a keyframe path needs at least 2 keyframes");
  if (count < 2 || count > kMaxPathFrames)
    throw terrain::Error(
        fmt::format("a keyframe path has 2 .. {} frames, not {}", kMaxPathFrames, count));
  // Per key: eye x, y, z, bearing (unwrapped), altitude.
  std::vector<Eigen::Matrix<double, 5, 1>> k(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (!keys[i].camera.eye) throw terrain::Error("a keyframe without its eye");
    double az = keys[i].camera.view_az;
    if (i > 0) az = k[i - 1][3] + std::remainder(az - k[i - 1][3], 360.0);
    k[i] << keys[i].camera.eye->x(), keys[i].camera.eye->y(), keys[i].camera.eye->z(), az,
        keys[i].camera.view_alt;
  }
  const auto at = [&](long i) {
    return k[std::size_t(std::clamp<long>(i, 0, long(k.size()) - 1))];
  };
  std::vector<FrameParams> out;
  const double segments = double(keys.size() - 1);
  for (int f = 0; f < count; ++f) {
    const double u = double(f) / double(count - 1) * segments;
    const long i = std::min(long(u), long(keys.size()) - 2);
    const double t = u - double(i), t2 = t * t, t3 = t2 * t;
    const auto p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
    const Eigen::Matrix<double, 5, 1> v =
        0.5 * (2 * p1 + (p2 - p0) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 +
               (3 * p1 - p0 - 3 * p2 + p3) * t3);
    FrameParams fp = keys[std::size_t(i)];
    fp.camera.eye = Eigen::Vector3d(v[0], v[1], v[2]);
    fp.camera.view_az = std::fmod(std::fmod(v[3], 360.0) + 360.0, 360.0);
    fp.camera.view_alt = std::clamp(v[4], -90.0, 90.0);
    out.push_back(fp);
  }
  return out;
}

}  // namespace renderer
