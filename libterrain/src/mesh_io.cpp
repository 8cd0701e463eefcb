#include "terrain/mesh_io.hpp"
#include "terrain/dem_io.hpp"

#include <fmt/format.h>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/IO/writer/OBJWriter.hh>
#include <OpenMesh/Core/IO/writer/PLYWriter.hh>
#include <OpenMesh/Core/Mesh/BaseKernel.hh>
#include <OpenMesh/Core/System/omstream.hh>

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

#include "terrain/atomic_file.hpp"
#include "terrain/error.hpp"
#include "terrain/mesh_digest.hpp"
#include "terrain/ply_header.hpp"

namespace terrain {

namespace {

namespace OM = OpenMesh;
using OM::IO::BaseExporter;
using OM::IO::BaseImporter;

constexpr int kFormatVersion = 1;
constexpr std::size_t kWktChunk = 200;

// Property container without connectivity: OpenMesh's PLY writer and reader move custom
// vertex and face properties (the Voronoi weights, the normal change) through it.
class PropertyKernel : public OM::BaseKernel {
 public:
  PropertyKernel(std::size_t nv, std::size_t nf) : nv_(nv), nf_(nf) {}
  size_t n_vertices() const override { return nv_; }
  size_t n_faces() const override { return nf_; }

  template <class Get>
  void add_vertex_floats(const char* name, std::size_t n, Get get) {
    OM::VPropHandleT<float> h;
    add_property(h, name);
    property(h).set_persistent(true);
    for (std::size_t i = 0; i < n; ++i) property(h, OM::VertexHandle(int(i))) = get(i);
  }
  template <class Get>
  void add_face_floats(const char* name, std::size_t n, Get get) {
    OM::FPropHandleT<float> h;
    add_property(h, name);
    property(h).set_persistent(true);
    for (std::size_t i = 0; i < n; ++i) property(h, OM::FaceHandle(int(i))) = get(i);
  }
  // Calls set(i, value) for every vertex (face) with the named float property; false when
  // the file has no such property.
  template <class Out>
  bool vertex_floats(const char* name, Out&& set) {
    OM::VPropHandleT<float> h;
    if (!get_property_handle(h, name)) return false;
    for (std::size_t i = 0; i < nv_; ++i) set(i, property(h, OM::VertexHandle(int(i))));
    return true;
  }
  template <class Out>
  bool face_floats(const char* name, Out&& set) {
    OM::FPropHandleT<float> h;
    if (!get_property_handle(h, name)) return false;
    for (std::size_t i = 0; i < nf_; ++i) set(i, property(h, OM::FaceHandle(int(i))));
    return true;
  }

 private:
  std::size_t nv_, nf_;
};

// PLY property names of the optional data (docs/formats.md).
constexpr const char* kTangent[3] = {"tangent_x", "tangent_y", "tangent_z"};
constexpr const char* kCornerArea[3] = {"corner_area_0", "corner_area_1", "corner_area_2"};

// Presents a GridMesh to OpenMesh's writers (PLY, OBJ) without building a half-edge mesh.
class GridMeshExporter : public BaseExporter {
 public:
  explicit GridMeshExporter(const GridMesh& m) : m_(m), kernel_(m.n_vertices(), m.n_faces()) {
    const std::size_t nv = m.n_vertices(), nf = m.n_faces();
    if (!m.voronoi.empty()) {
      kernel_.add_vertex_floats("voronoi_area", nv,
                                [&](std::size_t i) { return m.voronoi.vertex_areas[i]; });
      for (int k = 0; k < 3; ++k)
        kernel_.add_vertex_floats(kTangent[k], nv,
                                  [&](std::size_t i) { return m.voronoi.tangents[i][k]; });
      for (int k = 0; k < 3; ++k)
        kernel_.add_face_floats(kCornerArea[k], nf,
                                [&](std::size_t i) { return m.voronoi.corner_areas[i][k]; });
    }
    if (m.normal_change.size() == nv)
      kernel_.add_vertex_floats("normal_change", nv,
                                [&](std::size_t i) { return m.normal_change[i]; });
    if (m.filled.size() == nv)
      kernel_.add_vertex_floats("filled", nv, [&](std::size_t i) { return float(m.filled[i]); });
  }
  bool has_custom() const {
    return !m_.voronoi.empty() || m_.normal_change.size() == m_.n_vertices() ||
           m_.filled.size() == m_.n_vertices();
  }

  OM::Vec3f point(OM::VertexHandle v) const override {
    const auto& p = m_.positions[std::size_t(v.idx())];
    return {p.x(), p.y(), p.z()};
  }
  OM::Vec3d pointd(OM::VertexHandle v) const override { return OM::Vec3d(point(v)); }
  bool is_point_double() const override { return false; }
  OM::Vec3f normal(OM::VertexHandle v) const override {
    const auto& n = m_.normals[std::size_t(v.idx())];
    return {n.x(), n.y(), n.z()};
  }
  OM::Vec3d normald(OM::VertexHandle v) const override { return OM::Vec3d(normal(v)); }
  bool is_normal_double() const override { return false; }
  unsigned int get_vhandles(OM::FaceHandle f, std::vector<OM::VertexHandle>& vh) const override {
    const auto t = m_.topo.face(std::size_t(f.idx()));
    vh.assign(
        {OM::VertexHandle(int(t[0])), OM::VertexHandle(int(t[1])), OM::VertexHandle(int(t[2]))});
    return 3;
  }
  OM::BaseKernel* kernel() override { return &kernel_; }
  size_t n_vertices() const override { return m_.n_vertices(); }
  size_t n_faces() const override { return m_.n_faces(); }
  size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return true; }
  bool has_vertex_normals() const override { return true; }

  // Attributes we do not have.
  OM::Vec3uc color(OM::VertexHandle) const override { return OM::Vec3uc(0); }
  OM::Vec4uc colorA(OM::VertexHandle) const override { return OM::Vec4uc(0); }
  OM::Vec3ui colori(OM::VertexHandle) const override { return OM::Vec3ui(0); }
  OM::Vec4ui colorAi(OM::VertexHandle) const override { return OM::Vec4ui(0); }
  OM::Vec3f colorf(OM::VertexHandle) const override { return OM::Vec3f(0); }
  OM::Vec4f colorAf(OM::VertexHandle) const override { return OM::Vec4f(0); }
  OM::Vec2f texcoord(OM::VertexHandle) const override { return OM::Vec2f(0); }
  OM::Vec2f texcoord(OM::HalfedgeHandle) const override { return OM::Vec2f(0); }
  OM::Attributes::StatusInfo status(OM::VertexHandle) const override {
    return OM::Attributes::StatusInfo();
  }
  OM::HalfedgeHandle getHeh(OM::FaceHandle, OM::VertexHandle) const override {
    return OM::HalfedgeHandle();
  }
  unsigned int get_face_texcoords(std::vector<OM::Vec2f>&) const override { return 0; }
  OM::Vec3f normal(OM::FaceHandle) const override { return OM::Vec3f(0); }
  OM::Vec3d normald(OM::FaceHandle) const override { return OM::Vec3d(0); }
  OM::Vec3uc color(OM::FaceHandle) const override { return OM::Vec3uc(0); }
  OM::Vec4uc colorA(OM::FaceHandle) const override { return OM::Vec4uc(0); }
  OM::Vec3ui colori(OM::FaceHandle) const override { return OM::Vec3ui(0); }
  OM::Vec4ui colorAi(OM::FaceHandle) const override { return OM::Vec4ui(0); }
  OM::Vec3f colorf(OM::FaceHandle) const override { return OM::Vec3f(0); }
  OM::Vec4f colorAf(OM::FaceHandle) const override { return OM::Vec4f(0); }
  OM::Attributes::StatusInfo status(OM::FaceHandle) const override {
    return OM::Attributes::StatusInfo();
  }
  OM::Vec3uc color(OM::EdgeHandle) const override { return OM::Vec3uc(0); }
  OM::Vec4uc colorA(OM::EdgeHandle) const override { return OM::Vec4uc(0); }
  OM::Vec3ui colori(OM::EdgeHandle) const override { return OM::Vec3ui(0); }
  OM::Vec4ui colorAi(OM::EdgeHandle) const override { return OM::Vec4ui(0); }
  OM::Vec3f colorf(OM::EdgeHandle) const override { return OM::Vec3f(0); }
  OM::Vec4f colorAf(OM::EdgeHandle) const override { return OM::Vec4f(0); }
  OM::Attributes::StatusInfo status(OM::EdgeHandle) const override {
    return OM::Attributes::StatusInfo();
  }
  int get_halfedge_id(OM::VertexHandle) override { return -1; }
  int get_halfedge_id(OM::FaceHandle) override { return -1; }
  int get_next_halfedge_id(OM::HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(OM::HalfedgeHandle) override { return -1; }
  int get_face_id(OM::HalfedgeHandle) override { return -1; }
  OM::Attributes::StatusInfo status(OM::HalfedgeHandle) const override {
    return OM::Attributes::StatusInfo();
  }

 private:
  const GridMesh& m_;
  PropertyKernel kernel_;
};

// Receives OpenMesh's PLY reader output into a GridMesh whose topology is known from the
// header comments; faces are checked against that topology instead of being stored.
class GridMeshImporter : public BaseImporter {
 public:
  explicit GridMeshImporter(GridMesh& m) : m_(m), kernel_(m.topo.n_vertices(), m.topo.n_faces()) {
    m_.positions.reserve(m.topo.n_vertices());
    m_.normals.reserve(m.topo.n_vertices());
  }
  std::size_t faces_read = 0;
  std::size_t bad_faces = 0;

  OM::VertexHandle add_vertex(const OM::Vec3f& p) override {
    m_.positions.emplace_back(p[0], p[1], p[2]);
    m_.normals.emplace_back(0.0f, 0.0f, 0.0f);
    return OM::VertexHandle(int(m_.positions.size() - 1));
  }
  OM::VertexHandle add_vertex() override { return add_vertex(OM::Vec3f(0, 0, 0)); }
  void set_point(OM::VertexHandle v, const OM::Vec3f& p) override {
    if (valid(v)) m_.positions[std::size_t(v.idx())] = {p[0], p[1], p[2]};
  }
  void set_normal(OM::VertexHandle v, const OM::Vec3f& n) override {
    if (valid(v)) m_.normals[std::size_t(v.idx())] = {n[0], n[1], n[2]};
  }
  void set_normal(OM::VertexHandle v, const OM::Vec3d& n) override { set_normal(v, OM::Vec3f(n)); }
  OM::FaceHandle add_face(const VHandles& vh) override {
    const std::size_t f = faces_read++;
    bool ok = vh.size() == 3 && f < m_.topo.n_faces();
    if (ok) {
      const auto t = m_.topo.face(f);
      for (int k = 0; k < 3; ++k) ok = ok && vh[std::size_t(k)].idx() == int(t[std::size_t(k)]);
    }
    if (!ok) ++bad_faces;
    return OM::FaceHandle(int(f));
  }
  OM::BaseKernel* kernel() override { return &kernel_; }
  PropertyKernel& properties() { return kernel_; }
  bool is_triangle_mesh() const override { return true; }
  size_t n_vertices() const override { return m_.positions.size(); }
  size_t n_faces() const override { return faces_read; }
  size_t n_edges() const override { return 0; }

  // Data we do not keep.
  OM::HalfedgeHandle add_edge(OM::VertexHandle, OM::VertexHandle) override {
    return OM::HalfedgeHandle();
  }
  OM::FaceHandle add_face(OM::HalfedgeHandle) override { return OM::FaceHandle(); }
  void add_face_texcoords(OM::FaceHandle, OM::VertexHandle,
                          const std::vector<OM::Vec2f>&) override {}
  void add_face_texcoords(OM::FaceHandle, OM::VertexHandle,
                          const std::vector<OM::Vec3f>&) override {}
  void set_face_texindex(OM::FaceHandle, int) override {}
  void set_halfedge(OM::VertexHandle, OM::HalfedgeHandle) override {}
  void set_color(OM::VertexHandle, const OM::Vec3uc&) override {}
  void set_color(OM::VertexHandle, const OM::Vec4uc&) override {}
  void set_color(OM::VertexHandle, const OM::Vec3f&) override {}
  void set_color(OM::VertexHandle, const OM::Vec4f&) override {}
  void set_texcoord(OM::VertexHandle, const OM::Vec2f&) override {}
  void set_status(OM::VertexHandle, const OM::Attributes::StatusInfo&) override {}
  void set_next(OM::HalfedgeHandle, OM::HalfedgeHandle) override {}
  void set_face(OM::HalfedgeHandle, OM::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(OM::HalfedgeHandle, const OM::Vec2f&) override {}
  void set_texcoord(OM::VertexHandle, const OM::Vec3f&) override {}
  void set_texcoord(OM::HalfedgeHandle, const OM::Vec3f&) override {}
  void set_status(OM::HalfedgeHandle, const OM::Attributes::StatusInfo&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec3uc&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec4uc&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec3f&) override {}
  void set_color(OM::EdgeHandle, const OM::Vec4f&) override {}
  void set_status(OM::EdgeHandle, const OM::Attributes::StatusInfo&) override {}
  void set_normal(OM::FaceHandle, const OM::Vec3f&) override {}
  void set_normal(OM::FaceHandle, const OM::Vec3d&) override {}
  void set_color(OM::FaceHandle, const OM::Vec3uc&) override {}
  void set_color(OM::FaceHandle, const OM::Vec4uc&) override {}
  void set_color(OM::FaceHandle, const OM::Vec3f&) override {}
  void set_color(OM::FaceHandle, const OM::Vec4f&) override {}
  void set_status(OM::FaceHandle, const OM::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  bool valid(OM::VertexHandle v) const {
    return v.idx() >= 0 && std::size_t(v.idx()) < m_.positions.size();
  }
  GridMesh& m_;
  PropertyKernel kernel_;
};

// A buffered stream buffer that forwards bytes to `dest`, inserting `text` after the
// `after`-th newline (PLY: after the "ply" and "format" lines of the header OpenMesh
// writes; OBJ: at the start). OpenMesh writes binary PLY one value at a time, so the
// buffer (filled by the inherited xsputn) keeps that to a memcpy per value.
class CommentInjector : public std::streambuf {
 public:
  CommentInjector(std::streambuf* dest, std::string text, int after)
      : dest_(dest), text_(std::move(text)), after_(after), buffer_(std::size_t(1) << 20) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    if (after_ == 0) inject();
  }
  ~CommentInjector() override { flush_buffer(); }

 protected:
  int overflow(int ch) override {
    if (!flush_buffer()) return traits_type::eof();
    if (ch != traits_type::eof()) {
      *pptr() = char(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return flush_buffer() && dest_->pubsync() == 0 ? 0 : -1; }

 private:
  void inject() {
    ok_ = ok_ && dest_->sputn(text_.data(), std::streamsize(text_.size())) ==
                     std::streamsize(text_.size());
    done_ = true;
  }
  bool flush_buffer() {
    const char* p = pbase();
    const char* end = pptr();
    while (!done_ && p < end) {  // still inside the header: look for the insertion point
      const char* nl = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
      const char* upto = nl ? nl + 1 : end;
      ok_ = ok_ && dest_->sputn(p, upto - p) == upto - p;
      p = upto;
      if (nl && ++newlines_ == after_) inject();
    }
    if (p < end) ok_ = ok_ && dest_->sputn(p, end - p) == end - p;
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return ok_;
  }

  std::streambuf* dest_;
  std::string text_;
  int after_;
  std::vector<char> buffer_;
  int newlines_ = 0;
  bool done_ = false;
  bool ok_ = true;
};

// PLY header comments are kept ASCII (some PLY readers reject other bytes): bytes >= 0x80
// and the backslash are written as \xHH and decoded on reading.
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

// The line that carries the mesh's digest (mesh_digest.hpp), its 16 digits last.
constexpr std::string_view kDigestComment = "comment mesh_digest ";

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
  if (f->count != topo.n_faces())
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

}  // namespace

bool is_ply_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  return in && std::string(magic, 3) == "ply" && (magic[3] == '\n' || magic[3] == '\r');
}

namespace {

// Writes `mesh` with an OpenMesh writer into a temp file, `comments` inserted after the
// `after`-th newline, then renames it onto `path`.
// OpenMesh logs to stderr ("[OBJWriter] : write file"); our errors say what went wrong.
void silence_openmesh() {
  static const bool once = [] {
    ::omlog().disable();
    ::omout().disable();
    ::omerr().disable();
    return true;
  }();
  (void)once;
}

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

void write_with(const OM::IO::BaseWriter& writer, OM::IO::Options opt, const GridMesh& mesh,
                const std::string& path, const std::string& comments, int after) {
  if (mesh.positions.size() != mesh.topo.n_vertices() ||
      mesh.normals.size() != mesh.positions.size())
    throw Error("cannot write '" + path + "': positions, normals and grid size disagree");
  check_mesh_georef(mesh, "cannot write '" + path + "'");
  silence_openmesh();
  write_stream_atomic(path, [&](std::ostream& file) {
    CommentInjector injector(file.rdbuf(), comments, after);
    std::ostream stream(&injector);
    GridMeshExporter exporter(mesh);
    if (exporter.has_custom() && dynamic_cast<const OM::IO::_PLYWriter_*>(&writer))
      opt += OM::IO::Options::Custom;
    const bool wrote = writer.write(stream, exporter, opt, 9);
    stream.flush();  // a failed flush of the injector's buffer sets badbit
    if (!wrote || !stream) throw Error("cannot write '" + path + "': write failed (disk full?)");
  });
}

}  // namespace

void write_mesh_ply_openmesh(const GridMesh& mesh, const std::string& path) {
  write_with(OM::IO::PLYWriter(),
             OM::IO::Options::Binary | OM::IO::Options::LSB | OM::IO::Options::VertexNormal, mesh,
             path, header_comments(mesh, mesh_digest(mesh)), 2);
}

namespace {

// The header as OpenMesh writes it: custom properties in the order they were added.
std::string ply_header(const GridMesh& mesh, std::uint64_t digest, bool voronoi, bool change,
                       bool filled) {
  std::string header = "ply\nformat binary_little_endian 1.0\n" + header_comments(mesh, digest);
  header += fmt::format("element vertex {}\n", mesh.topo.n_vertices());
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz"})
    header += fmt::format("property float {}\n", name);
  if (voronoi) {
    header += "property float voronoi_area\n";
    for (const char* name : kTangent) header += fmt::format("property float {}\n", name);
  }
  if (change) header += "property float normal_change\n";
  if (filled) header += "property float filled\n";
  header +=
      fmt::format("element face {}\nproperty list uchar int vertex_indices\n", mesh.n_faces());
  if (voronoi)
    for (const char* name : kCornerArea) header += fmt::format("property float {}\n", name);
  return header + "end_header\n";
}

// A piece of the body: vertex rows r0 .. r1 - 1, or cell rows (two faces each).
struct PlyChunk {
  bool faces;
  std::size_t r0, r1;
};

// Fills `buf` with a chunk's records; returns the byte count. A vertex chunk's positions
// and normals are p[0..] and n[0..] (rows r0 .. r1 - 1), its optional data the mesh's.
std::size_t fill_ply_chunk(const GridMesh& mesh, const PlyChunk& ch, const Eigen::Vector3f* p,
                           const Eigen::Vector3f* n, bool voronoi, bool change, bool filled,
                           char* buf) {
  const std::size_t cols = mesh.topo.cols;
  char* at = buf;
  auto put = [&](const void* q, std::size_t bytes) {
    std::memcpy(at, q, bytes);
    at += bytes;
  };
  if (!ch.faces) {
    const std::size_t first = ch.r0 * cols;
    for (std::size_t i = first; i < ch.r1 * cols; ++i) {
      put(p[i - first].data(), 12);
      put(n[i - first].data(), 12);
      if (voronoi) {
        put(&mesh.voronoi.vertex_areas[i], 4);
        put(mesh.voronoi.tangents[i].data(), 12);
      }
      if (change) put(&mesh.normal_change[i], 4);
      if (filled) {
        const float f = mesh.filled[i];
        put(&f, 4);
      }
    }
    return std::size_t(at - buf);
  }
  for (std::size_t r = ch.r0; r < ch.r1; ++r)
    for (std::size_t c = 0; c + 1 < cols; ++c) {
      const auto nw = std::int32_t(r * cols + c), ne = nw + 1,
                 sw = std::int32_t(nw + std::int32_t(cols)), se = sw + 1;
      const std::size_t f = mesh.topo.face_of_cell(r, c, 0);
      // GridTopology::face's order: (NW, SW, SE), then (NW, SE, NE).
      const std::int32_t tri[2][3] = {{nw, sw, se}, {nw, se, ne}};
      for (int k = 0; k < 2; ++k) {
        const std::uint8_t three = 3;
        put(&three, 1);
        put(tri[k], 12);
        if (voronoi) put(mesh.voronoi.corner_areas[f + std::size_t(k)].data(), 12);
      }
    }
  return std::size_t(at - buf);
}

// Chunks filled at once: one written, two being filled (both cores busy while one writes).
constexpr std::size_t kSlots = 3;

// A vertex chunk's positions and normals: rows(r0, r1, slot, p, n) points p and n at rows
// r0 .. r1 - 1, valid while buffer `slot` (0 .. kSlots - 1) is not filled again.
using VertexRows = std::function<void(std::size_t r0, std::size_t r1, int slot,
                                      const Eigen::Vector3f*& p, const Eigen::Vector3f*& n)>;

// The PLY of `mesh` (its grid, georeference and optional arrays; the positions and normals
// from `rows`), its digest taken as the vertices go out and written into the header last.
void write_ply(const GridMesh& mesh, const VertexRows& rows_of, const std::string& path) {
  static_assert(std::endian::native == std::endian::little,
                "the PLY body is written as the host's floats");
  const std::size_t nv = mesh.topo.n_vertices();
  check_mesh_georef(mesh, "cannot write '" + path + "'");
  const bool voronoi = !mesh.voronoi.empty(), change = mesh.normal_change.size() == nv,
             filled = mesh.filled.size() == nv;
  const std::string header = ply_header(mesh, 0, voronoi, change, filled);
  const std::size_t digest_at = header.find(kDigestComment) + kDigestComment.size();
  // The body in chunks of whole rows (vertex rows, then cell rows of two faces each).
  const std::size_t rows = mesh.topo.rows, cols = mesh.topo.cols;
  const std::size_t vertex_bytes = 24 + (voronoi ? 16 : 0) + (change ? 4 : 0) + (filled ? 4 : 0),
                    face_bytes = 13 + (voronoi ? 12 : 0);
  // 1 MiB: 4 MiB chunks tripled the kernel's time in write(2) on ext4, 256 KiB ones spend
  // it on the helper threads.
  constexpr std::size_t kChunkBytes = std::size_t(1) << 20;
  const std::size_t vrow_bytes = cols * vertex_bytes, frow_bytes = 2 * (cols - 1) * face_bytes;
  const std::size_t vrows =
      std::max<std::size_t>(1, kChunkBytes / std::max<std::size_t>(1, vrow_bytes));
  const std::size_t frows =
      std::max<std::size_t>(1, kChunkBytes / std::max<std::size_t>(1, frow_bytes));
  std::vector<PlyChunk> chunks;
  for (std::size_t r = 0; r < rows; r += vrows)
    chunks.push_back({false, r, std::min(rows, r + vrows)});
  for (std::size_t r = 0; r + 1 < rows; r += frows)
    chunks.push_back({true, r, std::min(rows - 1, r + frows)});
  // What the helper gives back: the chunk's byte count and its vertices for the digest.
  struct Filled {
    std::size_t bytes = 0;
    const Eigen::Vector3f *p = nullptr, *n = nullptr;
  };
  const auto fill = [&](std::size_t i, char* buf) {
    Filled f;
    if (!chunks[i].faces) rows_of(chunks[i].r0, chunks[i].r1, int(i % kSlots), f.p, f.n);
    f.bytes = fill_ply_chunk(mesh, chunks[i], f.p, f.n, voronoi, change, filled, buf);
    return f;
  };
  MeshDigest digest;
  write_stream_atomic(path, [&](std::ostream& out) {
    out.write(header.data(), std::streamsize(header.size()));
    // kSlots buffers: helper threads fill the next ones while this one writes and digests.
    std::vector<char> bufs[kSlots];
    for (auto& b : bufs) b.resize(std::max(vrows * vrow_bytes, frows * frow_bytes));
    std::future<Filled> filling[kSlots];
    const auto launch = [&](std::size_t i) {
      if (i < chunks.size())
        filling[i % kSlots] = std::async(std::launch::async, fill, i, bufs[i % kSlots].data());
    };
    for (std::size_t i = 0; i + 1 < kSlots; ++i) launch(i);
    for (std::size_t i = 0; i < chunks.size() && out; ++i) {
      const Filled now = filling[i % kSlots].get();
      launch(i + kSlots - 1);
      out.write(bufs[i % kSlots].data(), std::streamsize(now.bytes));
      if (!chunks[i].faces) digest.add(now.p, now.n, (chunks[i].r1 - chunks[i].r0) * cols);
    }
    for (auto& f : filling)
      if (f.valid()) f.wait();  // after a failed write: no helper left writing into a buffer
    const std::string text = digest_text(digest.value());
    out.seekp(std::streamoff(digest_at));
    out.write(text.data(), std::streamsize(text.size()));
    out.flush();
    if (!out) throw Error("cannot write '" + path + "': write failed (disk full?)");
  });
}

}  // namespace

void write_mesh_ply(const GridMesh& mesh, const std::string& path) {
  if (mesh.positions.size() != mesh.topo.n_vertices() ||
      mesh.normals.size() != mesh.positions.size())
    throw Error("cannot write '" + path + "': positions, normals and grid size disagree");
  const std::size_t cols = mesh.topo.cols;
  write_ply(
      mesh,
      [&](std::size_t r0, std::size_t, int, const Eigen::Vector3f*& p, const Eigen::Vector3f*& n) {
        p = mesh.positions.data() + r0 * cols;
        n = mesh.normals.data() + r0 * cols;
      },
      path);
}

void write_grid_mesh_ply(const GridMesh& frame, const Grid& grid, NormalWeighting weighting,
                         const std::string& path) {
  if (frame.topo.rows != grid.rows || frame.topo.cols != grid.cols)
    throw Error("cannot write '" + path + "': the mesh's frame and the grid differ");
  // One row source and one pair of arrays per buffer slot.
  const GridMeshRows checked(grid, weighting);
  GridMeshRows sources[kSlots] = {checked, checked, checked};
  std::vector<Eigen::Vector3f> p[kSlots], n[kSlots];
  write_ply(
      frame,
      [&](std::size_t r0, std::size_t r1, int slot, const Eigen::Vector3f*& pp,
          const Eigen::Vector3f*& nn) {
        p[slot].resize((r1 - r0) * grid.cols);
        n[slot].resize(p[slot].size());
        sources[slot].rows(r0, r1, p[slot].data(), n[slot].data());
        pp = p[slot].data();
        nn = n[slot].data();
      },
      path);
}

struct PlyRowWriter::Impl {
  GridMesh header;  // grid, georeference, provenance; no vertices
  std::string path;
  std::ofstream out;
  std::vector<char> buf;
  std::size_t rows = 0;
  MeshDigest digest;
  std::size_t digest_at = 0;  // the header's digest digits, written by finish()
};

PlyRowWriter::PlyRowWriter(const GridMesh& header, const std::string& path)
    : impl_(std::make_unique<Impl>()) {
  static_assert(std::endian::native == std::endian::little,
                "the PLY body is written as the host's floats");
  Impl& m = *impl_;
  m.header.topo = header.topo, m.header.geo = header.geo, m.header.provenance = header.provenance;
  m.header.normal_fit = header.normal_fit;
  m.path = path;
  check_mesh_georef(m.header, "cannot write '" + path + "'");
  m.buf.resize(std::size_t(1) << 20);
  m.out.rdbuf()->pubsetbuf(m.buf.data(), std::streamsize(m.buf.size()));
  m.out.open(path, std::ios::binary | std::ios::trunc);
  const std::string h = ply_header(m.header, 0, false, false, false);
  m.digest_at = h.find(kDigestComment) + kDigestComment.size();
  m.out.write(h.data(), std::streamsize(h.size()));
  if (!m.out) throw Error("cannot write '" + path + "'");
}

PlyRowWriter::~PlyRowWriter() = default;

void PlyRowWriter::add_rows(const Eigen::Vector3f* positions, const Eigen::Vector3f* normals,
                            std::size_t n) {
  Impl& m = *impl_;
  const std::size_t cols = m.header.topo.cols;
  if (m.rows + n > m.header.topo.rows)
    throw Error("cannot write '" + m.path + "': more rows than the grid's");
  std::vector<char> row(24 * cols);
  m.digest.add(positions, normals, n * cols);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < cols; ++c) {
      std::memcpy(&row[24 * c], positions[r * cols + c].data(), 12);
      std::memcpy(&row[24 * c + 12], normals[r * cols + c].data(), 12);
    }
    m.out.write(row.data(), std::streamsize(row.size()));
  }
  m.rows += n;
  if (!m.out) throw Error("cannot write '" + m.path + "': write failed (disk full?)");
}

void PlyRowWriter::finish() {
  Impl& m = *impl_;
  if (m.rows != m.header.topo.rows)
    throw Error(fmt::format("cannot write '{}': {} of the grid's {} rows given", m.path, m.rows,
                            m.header.topo.rows));
  const std::size_t rows = m.header.topo.rows,
                    frows = std::max<std::size_t>(
                        1, (std::size_t(1) << 20) / (26 * m.header.topo.cols));
  std::vector<char> buf(frows * 26 * m.header.topo.cols);
  for (std::size_t r = 0; r + 1 < rows; r += frows) {
    const std::size_t n = fill_ply_chunk(m.header, {true, r, std::min(rows - 1, r + frows)},
                                         nullptr, nullptr, false, false, false, buf.data());
    m.out.write(buf.data(), std::streamsize(n));
  }
  const std::string digest = digest_text(m.digest.value());
  m.out.seekp(std::streamoff(m.digest_at));
  m.out.write(digest.data(), std::streamsize(digest.size()));
  m.out.close();
  if (!m.out) throw Error("cannot write '" + m.path + "': write failed (disk full?)");
}

void write_mesh_obj(const GridMesh& mesh, const std::string& path) {
  // The PLY comment block, as OBJ comments.
  std::istringstream lines(header_comments(mesh, std::nullopt));
  std::string comments, line;
  while (std::getline(lines, line)) comments += "# " + line.substr(8) + "\n";
  write_with(OM::IO::OBJWriter(), OM::IO::Options::VertexNormal, mesh, path, comments, 0);
}

namespace {

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
void check_vertices(const GridMesh& m, const std::string& path, int level = 0,
                    const GridMesh* fine = nullptr) {
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

// The optional data: the Voronoi weights (all seven properties or none), the normal change.
void read_optional(const std::string& path, GridMeshImporter& importer, GridMesh& m) {
  // Optional data: the Voronoi weights come as a set (all seven properties) or not at all.
  auto& k = importer.properties();
  auto& w = m.voronoi;
  w.vertex_areas.resize(m.n_vertices());
  w.tangents.resize(m.n_vertices());
  w.corner_areas.resize(m.n_faces());
  int found =
      k.vertex_floats("voronoi_area", [&](std::size_t i, float v) { w.vertex_areas[i] = v; });
  for (int c = 0; c < 3; ++c) {
    found += k.vertex_floats(kTangent[c], [&](std::size_t i, float v) { w.tangents[i][c] = v; });
    found +=
        k.face_floats(kCornerArea[c], [&](std::size_t i, float v) { w.corner_areas[i][c] = v; });
  }
  if (found != 0 && found != 7)
    throw Error("cannot read '" + path + "': it has only some of the Voronoi weight properties (" +
                std::to_string(found) + " of 7)");
  if (found == 0) w = VoronoiWeights{};
  m.normal_change.resize(m.n_vertices());
  if (!k.vertex_floats("normal_change", [&](std::size_t i, float v) { m.normal_change[i] = v; }))
    m.normal_change = BigVector<float>{};
  m.filled.resize(m.n_vertices());
  if (!k.vertex_floats("filled", [&](std::size_t i, float v) { m.filled[i] = v != 0.0f; }))
    m.filled = BigVector<std::uint8_t>{};
}

}  // namespace

namespace {

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
// faces checked to be the grid's triangulation, as GridMeshImporter checks them. A 10 m
// Logan mesh (715 MB) in about a quarter of OpenMesh's time, which parses every property
// of every record. False, nothing read, for any other layout (OpenMesh reads those).
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

}  // namespace

GridMesh read_mesh_ply(const std::string& path) {
  PlyHeader header;
  std::ifstream in;
  GridMesh m = read_terrain_header(path, header, in);
  if (read_plain_body(in, header, m, path)) {
    check_vertices(m, path);
    return m;
  }
  silence_openmesh();

  GridMeshImporter importer(m);
  OM::IO::Options opt(OM::IO::Options::VertexNormal | OM::IO::Options::Custom);
  if (!OM::IO::PLYReader().read(in, importer, opt))
    throw Error("cannot read '" + path +
                "': OpenMesh's PLY reader failed (corrupt or truncated file)");
  if (!opt.vertex_has_normal()) throw Error("cannot read '" + path + "': it has no vertex normals");
  if (m.positions.size() != m.topo.n_vertices())
    throw Error(fmt::format("cannot read '{}': {} vertices, but its {} x {} grid needs {}", path,
                            m.positions.size(), m.topo.rows, m.topo.cols, m.topo.n_vertices()));
  if (importer.faces_read != m.topo.n_faces() || importer.bad_faces != 0)
    throw faces_error(path, m.topo, importer.faces_read, importer.bad_faces);
  check_vertices(m, path);
  read_optional(path, importer, m);
  return m;
}

std::optional<PyramidMesh> read_mesh_via_pyramid(
    const std::string& ply_path, std::string& why,
    const std::function<PyramidPart(const MeshPyramid&)>& part) {
  namespace fs = std::filesystem;
  why.clear();
  const std::string pyr = pyramid_path_of(ply_path);
  std::error_code ec;
  if (pyr == ply_path || !fs::is_regular_file(pyr, ec) || !is_mesh_pyramid(pyr))
    return std::nullopt;
  PlyHeader header;
  std::ifstream in;
  PyramidMesh out{read_terrain_header(ply_path, header, in), {}, 0};
  in.close();
  GridMesh& m = out.mesh;
  for (const PlyElement& e : header.elements)
    for (const PlyProperty& p : e.properties)
      if (!(e.name == "vertex" && (p.name == "x" || p.name == "y" || p.name == "z" ||
                                   p.name == "nx" || p.name == "ny" || p.name == "nz")) &&
          !(e.name == "face" && p.name == "vertex_indices")) {
        why = "the mesh has data its pyramid does not keep (" + e.name + " property '" + p.name +
              "')";
        return std::nullopt;
      }
  MeshPyramid pyramid(pyr);
  // The pair is one when the pyramid was made from the vertices the PLY holds: both carry
  // the digest of those vertices (dem2mesh writes it into both).
  const std::optional<std::uint64_t> digest = header_digest(header);
  if (!pyramid.digest()) {
    why = fmt::format(
        "'{}' (version {}) does not say which mesh it was made from; dem2mesh --pyramid makes one "
        "that does",
        pyr, pyramid.version());
    return std::nullopt;
  }
  if (!digest || *digest != *pyramid.digest()) {
    why = "'" + pyr +
          "' was made from another mesh than this one (their digests differ; dem2mesh --pyramid "
          "again)";
    return std::nullopt;
  }
  out.digest = *digest;
  const MeshGeoref& g = pyramid.georef();
  auto same = [](double a, double b) {
    return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a));
  };
  if (pyramid.topology().rows != m.topo.rows || pyramid.topology().cols != m.topo.cols ||
      !same(g.origin_x, m.geo.origin_x) || !same(g.origin_y, m.geo.origin_y) ||
      !same(g.origin_z, m.geo.origin_z) || !same(g.dx, m.geo.dx) || !same(g.dy, m.geo.dy) ||
      g.epsg != m.geo.epsg) {
    why = "'" + pyr + "' describes another grid than the mesh's";
    return std::nullopt;
  }
  const PyramidPart want = part ? part(pyramid) : PyramidPart{};
  const int l = std::clamp(want.level, 0, pyramid.level_count() - 1);
  const MeshLevels& all = pyramid.levels();
  const std::size_t B = all.block, rows0 = m.topo.rows - 1, cols0 = m.topo.cols - 1;
  // The window's blocks, and its level-0 cells: whole blocks, so level l's lines (B is a
  // multiple of 2^l; a level too coarse for that reads the whole level).
  const std::size_t br0 = std::min(want.br0, all.block_rows - 1),
                    br1 = std::clamp(want.br1, br0 + 1, all.block_rows);
  const std::size_t bc0 = std::min(want.bc0, all.block_cols - 1),
                    bc1 = std::clamp(want.bc1, bc0 + 1, all.block_cols);
  const bool window = (br0 > 0 || bc0 > 0 || br1 < all.block_rows || bc1 < all.block_cols) &&
                      B % (std::size_t(1) << l) == 0;
  const std::size_t R0 = window ? br0 * B : 0, C0 = window ? bc0 * B : 0;
  const std::size_t R1 = window ? std::min(br1 * B, rows0) : rows0,
                    C1 = window ? std::min(bc1 * B, cols0) : cols0;
  GridMesh fine;  // the grid held at level 0, what its vertices are checked against
  fine.topo = GridTopology{R1 - R0 + 1, C1 - C0 + 1}, fine.geo = m.geo;
  const std::size_t r0 = R0 >> l, c0 = C0 >> l;  // level l's first row and column of the window
  const std::size_t rows = (R1 == rows0 ? pyramid.rows(l) - 1 : R1 >> l) - r0 + 1;
  const std::size_t cols = (C1 == cols0 ? pyramid.cols(l) - 1 : C1 >> l) - c0 + 1;
  // The whole level's spacing: its extent over its cells.
  m.geo.dx *= double(cols0) / double(pyramid.cols(l) - 1);
  m.geo.dy *= double(rows0) / double(pyramid.rows(l) - 1);
  m.topo = GridTopology{rows, cols};
  m.positions.resize(m.topo.n_vertices());
  m.normals.resize(m.topo.n_vertices());
  pyramid.read_window(l, r0, c0, rows, cols, m.positions.data(), m.normals.data());
  out.levels = all;
  out.levels.base = l;
  if (window) {
    // The window's frame: its first vertex at the origin.
    const Eigen::Vector3f shift(float(double(C0) * fine.geo.dx), float(-double(R0) * fine.geo.dy),
                                0.0f);
    MeshLevels::Window w{R0, C0, all.topo, fine.geo, {}, {}};
    for (std::size_t i = 0; i < m.n_vertices(); ++i) m.positions[i] -= shift;
    m.geo.origin_x += double(C0) * fine.geo.dx;
    m.geo.origin_y -= double(R0) * fine.geo.dy;
    fine.geo.origin_x = m.geo.origin_x, fine.geo.origin_y = m.geo.origin_y;
    w.lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
    w.hi = -w.lo;
    for (const MeshLevelBlock& b : all.blocks)
      w.lo = w.lo.cwiseMin(b.lo - shift), w.hi = w.hi.cwiseMax(b.hi - shift);
    out.levels.topo = fine.topo;
    out.levels.block_rows = br1 - br0, out.levels.block_cols = bc1 - bc0;
    out.levels.blocks.clear();
    for (std::size_t br = br0; br < br1; ++br)
      for (std::size_t bc = bc0; bc < bc1; ++bc) {
        MeshLevelBlock b = all.blocks[br * all.block_cols + bc];
        b.r0 -= std::uint32_t(R0), b.c0 -= std::uint32_t(C0);
        b.lo -= shift, b.hi -= shift;
        out.levels.blocks.push_back(std::move(b));
      }
    out.levels.window = w;
  }
  check_vertices(m, pyr, l, &fine);
  return out;
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
