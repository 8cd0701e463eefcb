#include "terrain/ply_header.hpp"

#include <charconv>
#include <sstream>

#include "terrain/error.hpp"

namespace terrain {

namespace {

constexpr std::size_t kMaxLine = 64 * 1024;
constexpr std::uint64_t kMaxHeader = 16u << 20;
constexpr std::uint64_t kMaxCount = std::uint64_t(1) << 40;

// Size of a PLY scalar type (both the old and the sized names), 0 if unknown.
int type_size(const std::string& t, bool* is_float) {
  *is_float = t == "float" || t == "float32" || t == "double" || t == "float64";
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

}  // namespace

std::uint64_t PlyElement::record_bytes(int list_items) const {
  std::uint64_t n = 0;
  for (const PlyProperty& p : properties)
    n += p.count_size
             ? std::uint64_t(p.count_size) + std::uint64_t(list_items) * std::uint64_t(p.size)
             : std::uint64_t(p.size);
  return n;
}

const PlyProperty* PlyElement::find(const std::string& property) const {
  for (const PlyProperty& p : properties)
    if (p.name == property) return &p;
  return nullptr;
}

const PlyElement* PlyHeader::find(const std::string& element) const {
  for (const PlyElement& e : elements)
    if (e.name == element) return &e;
  return nullptr;
}

// The rest of a format line: the format, or "" when it is none PLY knows (version 1.0).
static std::string format_of(std::istringstream& ss) {
  std::string a, b;
  ss >> a >> b;
  if ((a != "ascii" && a != "binary_little_endian" && a != "binary_big_endian") || b != "1.0")
    return {};
  return a;
}

// The rest of an element line (NAME COUNT) into `e`: "" or why it is wrong.
static std::string parse_element(std::istringstream& ss, PlyElement& e) {
  std::string a, b, extra;
  if (!(ss >> a >> b) || (ss >> extra)) return "expected 'element NAME COUNT'";
  std::uint64_t count = 0;
  const auto [end, ec] = std::from_chars(b.data(), b.data() + b.size(), count);
  if (ec != std::errc() || end != b.data() + b.size() || count >= kMaxCount)
    return "element '" + a + "' has no valid count ('" + b + "')";
  e = PlyElement{a, count, {}};
  return {};
}

// The rest of a property line (TYPE NAME, or list COUNT_TYPE TYPE NAME) into `p`: "" or why
// it is wrong.
static std::string parse_property(std::istringstream& ss, PlyProperty& p) {
  std::string a, b, c, extra;
  if (!(ss >> a)) return "expected 'property TYPE NAME'";
  if (a == "list") {
    bool count_float = false;
    if (!(ss >> b >> c >> p.name) || (ss >> extra))
      return "expected 'property list COUNT_TYPE TYPE NAME'";
    p.count_size = type_size(b, &count_float);
    p.size = type_size(c, &p.is_float);
    if (p.count_size == 0 || count_float || p.size == 0)
      return "unknown list types '" + b + " " + c + "'";
  } else {
    if (!(ss >> p.name) || (ss >> extra)) return "expected 'property TYPE NAME'";
    p.size = type_size(a, &p.is_float);
    if (p.size == 0) return "unknown property type '" + a + "'";
  }
  return {};
}

PlyHeader read_ply_header(std::istream& in, const std::string& name) {
  auto fail = [&](const std::string& why, std::size_t line_no) -> Error {
    return Error("cannot read '" + name + "': " +
                 (line_no ? "PLY header line " + std::to_string(line_no) + ": " : "") + why);
  };
  PlyHeader h;
  std::string line;
  std::size_t line_no = 0;
  auto next = [&]() {
    line.clear();
    for (int c; (c = in.get()) != std::char_traits<char>::eof();) {
      ++h.header_bytes;
      if (c == '\n') {
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return true;
      }
      if (line.size() >= kMaxLine) throw fail("line longer than 64 KiB", line_no + 1);
      if (h.header_bytes > kMaxHeader) throw fail("header longer than 16 MiB (no end_header?)", 0);
      line.push_back(char(c));
    }
    return false;
  };
  if (!next() || line != "ply") throw fail("not a PLY file", 0);
  while (true) {
    if (!next()) throw fail("PLY header has no end_header (truncated file?)", 0);
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "end_header") break;
    if (key.empty() || key == "comment" || key == "obj_info") {
      if (key == "comment") h.comments.push_back(line.size() > 8 ? line.substr(8) : std::string());
      continue;
    }
    if (key == "format") {
      if (!h.format.empty()) throw fail("a second format line", line_no);
      if (h.format = format_of(ss); h.format.empty())
        throw fail("unknown format '" + line + "'", line_no);
    } else if (key == "element") {
      PlyElement e;
      if (const std::string why = parse_element(ss, e); !why.empty()) throw fail(why, line_no);
      if (h.find(e.name)) throw fail("element '" + e.name + "' appears twice", line_no);
      h.elements.push_back(e);
    } else if (key == "property") {
      if (h.elements.empty()) throw fail("property before any element", line_no);
      PlyProperty p;
      if (const std::string why = parse_property(ss, p); !why.empty()) throw fail(why, line_no);
      PlyElement& e = h.elements.back();
      if (e.find(p.name))
        throw fail("property '" + p.name + "' appears twice in element '" + e.name + "'", line_no);
      e.properties.push_back(p);
    } else {
      throw fail("unknown keyword '" + key + "'", line_no);
    }
  }
  if (h.format.empty()) throw fail("PLY header has no format line", 0);
  return h;
}

}  // namespace terrain
