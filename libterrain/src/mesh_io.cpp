#include "terrain/mesh_io.hpp"

#include "terrain/dem_io.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <optional>
#include <sstream>
#include <streambuf>
#include <string_view>

#include "mesh_io_internal.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/mesh_digest.hpp"
#include "terrain/ply_header.hpp"

namespace terrain {

using namespace detail;  // mesh_io_internal.hpp: what the PLY files' three sources share

namespace detail {

constexpr int kFormatVersion = 1;
constexpr std::size_t kWktChunk = 200;

std::string escape_ascii(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x80 || ch == '\\' || ch == '\n' || ch == '\r')
      out += fmt::format("\\x{:02X}", u);
    else
      out += ch;
  }
  return out;
}

std::string unescape_ascii(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\\' && i + 3 < text.size() && text[i + 1] == 'x' &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2])) &&
        std::isxdigit(static_cast<unsigned char>(text[i + 3]))) {
      out += char(std::stoi(text.substr(i + 2, 2), nullptr, 16));
      i += 3;
    } else {
      out += text[i];
    }
  }
  return out;
}

std::string header_comments(const GridMesh& m, std::optional<std::uint64_t> digest) {
  std::string out = fmt::format("comment terrain-mesh {}\n", kFormatVersion);
  out += fmt::format("comment grid {} {} {:.17g} {:.17g}\n", m.topo.rows, m.topo.cols, m.geo.dx,
                     m.geo.dy);
  out += fmt::format("comment origin {:.17g} {:.17g} {:.17g}\n", m.geo.origin_x, m.geo.origin_y,
                     m.geo.origin_z);
  out += fmt::format("comment crs_epsg {}\n", m.geo.epsg);
  const std::string wkt = escape_ascii(m.geo.crs_wkt);
  for (std::size_t i = 0; i < wkt.size();) {
    std::size_t n = std::min(kWktChunk, wkt.size() - i);
    for (std::size_t k = 1; k <= 3 && k < n && i + n < wkt.size();
         ++k)  // never split a \xHH escape
      if (wkt[i + n - k] == '\\') {
        n -= k;
        break;
      }
    out += "comment crs_wkt " + wkt.substr(i, n) + "\n";
    i += n;
  }
  if (digest) out += std::string(kDigestComment) + digest_text(*digest) + "\n";
  if (m.normal_fit.fitted)
    out += fmt::format("comment normals_fitted {:.6g} {:.6g} {:.6g} {:.6g} {}\n",
                       m.normal_fit.rmse_before, m.normal_fit.max_before, m.normal_fit.rmse_after,
                       m.normal_fit.max_after, m.normal_fit.samples);
  if (!m.provenance.empty()) out += "comment provenance " + escape_ascii(m.provenance) + "\n";
  return out;
}

std::uint64_t checked_mul(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a)
    return std::numeric_limits<std::uint64_t>::max();
  return a * b;
}

// Checks that the PLY header describes a terrain mesh of `rows` x `cols` samples exactly
// (binary little-endian; elements vertex and face only; float x y z nx ny nz; faces as one
// list of 4-byte indices) and that the file's size is what those counts need, before
// OpenMesh's reader sees the file.
void check_terrain_ply(const PlyHeader& h, const GridTopology& topo, std::uint64_t file_size,
                       const std::string& path) {
  auto fail = [&](const std::string& why) { return Error("cannot read '" + path + "': " + why); };
  if (h.format != "binary_little_endian")
    throw fail("a PLY file in " + h.format +
               " format; terrain meshes are binary little-endian PLY (written by dem2mesh)");
  for (const PlyElement& e : h.elements)
    if (e.name != "vertex" && e.name != "face")
      throw fail("unexpected PLY element '" + e.name +
                 "' (a terrain mesh has only vertex and face)");
  const PlyElement* v = h.find("vertex");
  const PlyElement* f = h.find("face");
  if (!v || !f || h.elements.front().name != "vertex")
    throw fail("the PLY header needs element vertex, then element face");
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz"}) {
    const PlyProperty* p = v->find(name);
    if (!p) throw fail(std::string("the vertices have no property '") + name + "'");
    if (p->count_size || !p->is_float || p->size != 4)
      throw fail(std::string("vertex property '") + name + "' is not a float");
  }
  for (const PlyProperty& p : v->properties)
    if (p.count_size) throw fail("vertex property '" + p.name + "' is a list");
  const PlyProperty* idx = f->find("vertex_indices");
  if (!idx) idx = f->find("vertex_index");
  if (!idx || !idx->count_size || idx->is_float || idx->size != 4)
    throw fail("the faces have no 'list uchar int vertex_indices' property");
  for (const PlyProperty& p : f->properties)
    if (p.count_size && &p != idx) throw fail("face property '" + p.name + "' is a second list");
  if (v->count != topo.n_vertices())
    throw fail(fmt::format("{} vertices, but its {} x {} grid needs {}", v->count, topo.rows,
                           topo.cols, topo.n_vertices()));
  // A mesh with vertices outside the data ('filled' 2) leaves out the faces they touch.
  if (v->find("filled") ? f->count > topo.n_faces() : f->count != topo.n_faces())
    throw fail(fmt::format("{} faces, but its {} x {} grid has {}", f->count, topo.rows, topo.cols,
                           topo.n_faces()));
  const std::uint64_t body = checked_mul(v->count, v->record_bytes(3));
  const std::uint64_t faces = checked_mul(f->count, f->record_bytes(3));
  const std::uint64_t expected = h.header_bytes + body + faces;
  if (expected < body || file_size < expected)
    throw fail(fmt::format("truncated ({} bytes, its counts need {})", file_size, expected));
  if (file_size > expected)
    throw fail(fmt::format("{} unexpected bytes after the faces", file_size - expected));
}

}  // namespace detail

bool is_ply_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  return in && std::string(magic, 3) == "ply" && (magic[3] == '\n' || magic[3] == '\r');
}

namespace detail {

// Throws "WHAT: ..." unless every header field that sizes or places something is what a
// projected mesh can be (the lattice itself is checked against the vertices on reading):
// georef_in_range, and a CRS whose WKT and EPSG code agree. The writer checks the same, so no
// tool writes a mesh that another refuses.
void check_mesh_georef(const GridMesh& m, const std::string& what) {
  if (!georef_in_range(m.topo, m.geo))
    throw Error(
        fmt::format("{}: its grid comment (spacing {:g} x {:g} m, {} x {} vertices) or origin "
                    "({:g}, {:g}, {:g}) is outside what a terrain mesh can be",
                    what, m.geo.dx, m.geo.dy, m.topo.cols, m.topo.rows, m.geo.origin_x,
                    m.geo.origin_y, m.geo.origin_z));
  if (const std::string crs = crs_fields_problem(m.geo.crs_wkt, m.geo.epsg); !crs.empty())
    throw Error(what + ": " + crs);
}

}  // namespace detail

namespace detail {

// The georeferencing and records of a terrain mesh's header comments, checked.
GridMesh mesh_of_header(const PlyHeader& header, const std::string& path) {
  GridMesh m;
  int version = -1;
  bool has_grid = false, has_origin = false;
  for (const std::string& c : header.comments) {
    std::istringstream ss(c);
    std::string key;
    ss >> key;
    const std::string rest =
        c.size() > key.size() + 1 ? c.substr(key.size() + 1) : std::string();  // after "key "
    if (key == "terrain-mesh")
      ss >> version;
    else if (key == "grid" || key == "origin") {
      const bool ok = key == "grid"
                          ? bool(ss >> m.topo.rows >> m.topo.cols >> m.geo.dx >> m.geo.dy)
                          : bool(ss >> m.geo.origin_x >> m.geo.origin_y >> m.geo.origin_z);
      if (!ok)
        throw Error("cannot read '" + path + "': invalid '" + key + "' comment: '" + c + "'");
      (key == "grid" ? has_grid : has_origin) = true;
    } else if (key == "crs_epsg")
      ss >> m.geo.epsg;
    else if (key == "crs_wkt")
      m.geo.crs_wkt += rest;
    else if (key == "provenance")
      m.provenance = unescape_ascii(rest);
    else if (key == "normals_fitted") {
      NormalFitInfo& f = m.normal_fit;
      if (!(ss >> f.rmse_before >> f.max_before >> f.rmse_after >> f.max_after >> f.samples))
        throw Error("cannot read '" + path + "': invalid 'normals_fitted' comment: '" + c + "'");
      f.fitted = true;
    }
  }
  m.geo.crs_wkt = unescape_ascii(m.geo.crs_wkt);
  if (version < 0 || !has_grid || !has_origin)
    throw Error(
        "cannot read '" + path +
        "': a PLY file but not a terrain mesh (no georeferencing comments; make it with dem2mesh)");
  if (version > kFormatVersion)
    throw Error(
        fmt::format("cannot read '{}': terrain-mesh version {} is newer than this tool's ({})",
                    path, version, kFormatVersion));
  if (m.topo.rows < 2 || m.topo.cols < 2 || m.topo.rows > (1u << 30) || m.topo.cols > (1u << 30) ||
      !(m.geo.dx > 0) || !(m.geo.dy > 0) || !std::isfinite(m.geo.dx) || !std::isfinite(m.geo.dy) ||
      !std::isfinite(m.geo.origin_x) || !std::isfinite(m.geo.origin_y) ||
      !std::isfinite(m.geo.origin_z))
    throw Error("cannot read '" + path + "': invalid grid or origin comment");
  return m;
}

// Every vertex finite, every normal of unit length, every vertex on the lattice the grid
// comment states.
// `level` > 0: m holds that level of a pyramid (read_mesh_via_pyramid), whose vertex
// (r, c) is the mesh's (level_index(r), level_index(c)) on the lattice of `fine`, the mesh's
// own grid and spacing.
void check_vertices(const GridMesh& m, const std::string& path, int level, const GridMesh* fine) {
  for (std::size_t i = 0; i < m.n_vertices(); ++i) {
    if (!m.positions[i].allFinite())
      throw Error(
          fmt::format("cannot read '{}': vertex {} (row {}, column {}) is not a finite number",
                      path, i, i / m.topo.cols, i % m.topo.cols));
    if (!(std::abs(m.normals[i].squaredNorm() - 1.0f) < 1e-3f))
      throw Error(fmt::format(
          "cannot read '{}': the normal of vertex {} is not unit length (corrupt file?)", path, i));
  }
  // The vertices lie on the lattice the grid comment states (x = column * dx, y = -row * dy
  // about the origin), within 1 % of a spacing and float rounding: a spacing that disagrees
  // with the vertices would place and index every sample wrongly downstream.
  const GridMesh& f = fine ? *fine : m;
  const double tol_x = 0.01 * f.geo.dx, tol_y = 0.01 * f.geo.dy;
  for (std::size_t r = 0; r < m.topo.rows; ++r)
    for (std::size_t c = 0; c < m.topo.cols; ++c) {
      const Eigen::Vector3f& p = m.positions[r * m.topo.cols + c];
      const double x = double(level_index(c, f.topo.cols - 1, level)) * f.geo.dx,
                   y = -double(level_index(r, f.topo.rows - 1, level)) * f.geo.dy;
      if (std::abs(double(p.x()) - x) > tol_x + 1e-6 * std::abs(x) ||
          std::abs(double(p.y()) - y) > tol_y + 1e-6 * std::abs(y))
        throw Error(fmt::format(
            "cannot read '{}': vertex {} (row {}, column {}) at ({:g}, {:g}) is not on the grid "
            "comment's {:g} x {:g} m lattice (expected ({:g}, {:g})): the header disagrees with "
            "the vertices",
            path, r * m.topo.cols + c, r, c, p.x(), p.y(), f.geo.dx, f.geo.dy, x, y));
    }
}

}  // namespace detail

namespace detail {

// A terrain PLY's header, checked, and the mesh it describes (no vertices yet), read from
// `in`, opened here on `path`: its size is that same file's, and its body is read from it
// too (a file renamed over the path meanwhile is not seen).
GridMesh read_terrain_header(const std::string& path, PlyHeader& header, std::ifstream& in) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error("cannot read '" + path + "': it is a directory");
  in.open(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "': no such file or not readable");
  in.seekg(0, std::ios::end);
  const auto size = std::uint64_t(in.tellg());
  in.seekg(0);
  header = read_ply_header(in, path);
  GridMesh m = mesh_of_header(header, path);
  check_mesh_georef(m, "cannot read '" + path + "'");
  check_terrain_ply(header, m.topo, size, path);
  in.clear();
  in.seekg(0);
  return m;
}

// The digest the header states (comment mesh_digest), if any.
std::optional<std::uint64_t> header_digest(const PlyHeader& header) {
  const std::string key(kDigestComment.substr(8));  // without "comment "
  for (const std::string& c : header.comments)
    if (c.starts_with(key) && c.size() == key.size() + 16) {
      std::uint64_t d = 0;
      const char* first = c.data() + key.size();
      if (std::from_chars(first, first + 16, d, 16).ptr == first + 16) return d;
    }
  return std::nullopt;
}

// A file whose faces are not the grid's triangulation: `read` faces, `differ` of them not as
// GridTopology::face has them (both readers).
Error faces_error(const std::string& path, const GridTopology& topo, std::size_t read,
                  std::size_t differ) {
  return Error(fmt::format(
      "cannot read '{}': its faces are not the {} x {} grid triangulation ({} faces, {} differ)",
      path, topo.rows, topo.cols, read, differ));
}

// The body of a PLY in the toolkit's own plain layout (write_mesh_ply without optional
// data: binary little-endian, the vertices' x y z nx ny nz as floats, the faces as uchar-int
// lists, nothing else), read in large blocks from `in` at the body: its vertices, and its
// faces checked to be the grid's triangulation, as GridMeshImporter checks them (OpenMesh's
// reader parses every property of every record, several times slower). False, nothing
// read, for any other layout (OpenMesh reads those).
bool read_plain_body(std::ifstream& in, const PlyHeader& h, GridMesh& m, const std::string& path) {
  if constexpr (std::endian::native != std::endian::little) return false;
  const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
  if (h.format != "binary_little_endian" || h.elements.size() != 2 ||
      h.elements[0].name != "vertex" || h.elements[0].properties.size() != 6 ||
      h.elements[1].name != "face" || h.elements[1].properties.size() != 1)
    return false;
  for (int k = 0; k < 6; ++k) {
    const PlyProperty& p = h.elements[0].properties[std::size_t(k)];
    if (p.name != names[k] || p.size != 4 || p.count_size != 0 || !p.is_float) return false;
  }
  const PlyProperty& f = h.elements[1].properties[0];
  if (f.name != "vertex_indices" || f.count_size != 1 || f.size != 4 || f.is_float) return false;
  const std::size_t nv = m.topo.n_vertices(), nf = m.topo.n_faces();
  if (h.elements[0].count != nv || h.elements[1].count != nf)
    return false;  // check_terrain_ply says why
  in.clear();
  in.seekg(std::streamoff(h.header_bytes));
  constexpr std::size_t kChunk = std::size_t(1) << 16;  // records a read
  std::vector<char> buf(kChunk * 24);
  m.positions.resize(nv);
  m.normals.resize(nv);
  auto read = [&](std::size_t bytes) {
    if (!in.read(buf.data(), std::streamsize(bytes)))
      throw Error("cannot read '" + path + "': the file ends before its last record (truncated?)");
  };
  for (std::size_t i0 = 0; i0 < nv; i0 += kChunk) {
    const std::size_t n = std::min(kChunk, nv - i0);
    read(n * 24);
    for (std::size_t k = 0; k < n; ++k) {
      std::memcpy(m.positions[i0 + k].data(), &buf[k * 24], 12);
      std::memcpy(m.normals[i0 + k].data(), &buf[k * 24 + 12], 12);
    }
  }
  std::size_t bad = 0;
  for (std::size_t f0 = 0; f0 < nf; f0 += kChunk) {
    const std::size_t n = std::min(kChunk, nf - f0);
    read(n * 13);
    for (std::size_t k = 0; k < n; ++k) {
      const char* r = &buf[k * 13];
      std::int32_t v[3];
      std::memcpy(v, r + 1, 12);
      const auto t = m.topo.face(f0 + k);
      bad += std::uint8_t(r[0]) != 3 || v[0] != std::int32_t(t[0]) || v[1] != std::int32_t(t[1]) ||
             v[2] != std::int32_t(t[2]);
    }
  }
  if (bad != 0) throw faces_error(path, m.topo, nf, bad);
  return true;
}

}  // namespace detail

GridMesh read_mesh_ply(const std::string& path) {
  PlyHeader header;
  std::ifstream in;
  GridMesh m = read_terrain_header(path, header, in);
  if (read_plain_body(in, header, m, path)) {
    check_vertices(m, path);
    return m;
  }
  read_body_openmesh(in, m, path);
  return m;
}

GridMesh read_terrain_mesh(const std::string& ply_path, std::string* source, MeshLevels* levels,
                           std::string* warning) {
  std::string why;
  if (std::optional<PyramidMesh> p = read_mesh_via_pyramid(ply_path, why)) {
    if (source) *source = fmt::format("'{}' (its pyramid)", pyramid_path_of(ply_path));
    if (levels) *levels = std::move(p->levels);
    return std::move(p->mesh);
  }
  if (source) *source = why.empty() ? std::string("the PLY") : fmt::format("the PLY: {}", why);
  if (warning)
    *warning = why.empty() ? std::string()
                           : fmt::format("'{}' read whole, not its pyramid: {}", ply_path, why);
  return read_mesh_ply(ply_path);
}

}  // namespace terrain
