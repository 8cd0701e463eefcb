// The terrain PLY through OpenMesh: its PLY writer (the fast writer's test reference), its
// OBJ writer, and its PLY reader for layouts other than the toolkit's own.
#include <fmt/format.h>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/IO/writer/OBJWriter.hh>
#include <OpenMesh/Core/IO/writer/PLYWriter.hh>
#include <OpenMesh/Core/Mesh/BaseKernel.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cstring>
#include <sstream>
#include <streambuf>

#include "mesh_io_internal.hpp"
#include "terrain/atomic_file.hpp"
#include "terrain/mesh_digest.hpp"
#include "terrain/mesh_io.hpp"

namespace terrain {

using namespace detail;

namespace {

namespace OM = OpenMesh;
using OM::IO::BaseExporter;
using OM::IO::BaseImporter;

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

// Presents a GridMesh to OpenMesh's writers (PLY, OBJ) without building a half-edge mesh.
class GridMeshExporter : public BaseExporter {
 public:
  explicit GridMeshExporter(const GridMesh& m)
      : m_(m), kept_(m.kept_faces()), kernel_(m.n_vertices(), kept_.size()) {
    const std::size_t nv = m.n_vertices(), nf = kept_.size();
    if (!m.voronoi.empty()) {
      kernel_.add_vertex_floats("voronoi_area", nv,
                                [&](std::size_t i) { return m.voronoi.vertex_areas[i]; });
      for (int k = 0; k < 3; ++k)
        kernel_.add_vertex_floats(kTangent[k], nv,
                                  [&](std::size_t i) { return m.voronoi.tangents[i][k]; });
      for (int k = 0; k < 3; ++k)
        kernel_.add_face_floats(kCornerArea[k], nf,
                                [&](std::size_t i) { return m.voronoi.corner_areas[kept_[i]][k]; });
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
    const auto t = m_.topo.face(kept_[std::size_t(f.idx())]);
    vh.assign(
        {OM::VertexHandle(int(t[0])), OM::VertexHandle(int(t[1])), OM::VertexHandle(int(t[2]))});
    return 3;
  }
  OM::BaseKernel* kernel() override { return &kernel_; }
  size_t n_vertices() const override { return m_.n_vertices(); }
  size_t n_faces() const override { return kept_.size(); }  // outside the data: none
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
  std::vector<std::uint32_t> kept_;  // the faces written (GridMesh::kept_faces)
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
  // The faces as read; checked by check_faces once the vertices' sources are known.
  OM::FaceHandle add_face(const VHandles& vh) override {
    const std::size_t f = faces_read++;
    if (vh.size() != 3 || f >= m_.topo.n_faces()) {
      ++bad_faces;
    } else {
      faces.push_back(
          {std::uint32_t(vh[0].idx()), std::uint32_t(vh[1].idx()), std::uint32_t(vh[2].idx())});
    }
    return OM::FaceHandle(int(f));
  }
  std::vector<std::array<std::uint32_t, 3>> faces;
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
  bool bad_source = false;
  if (!k.vertex_floats("filled", [&](std::size_t i, float v) {
        bad_source = bad_source || !(v >= 0.0f && v <= float(kVoidFilled) && v == std::floor(v));
        m.filled[i] = bad_source ? 0 : std::uint8_t(v);
      }))
    m.filled = BigVector<std::uint8_t>{};
  if (bad_source)
    throw Error("cannot read '" + path + "': a vertex's 'filled' is not 0, 1, 2 or 3");
}

}  // namespace

void write_mesh_ply_openmesh(const GridMesh& mesh, const std::string& path) {
  write_with(OM::IO::PLYWriter(),
             OM::IO::Options::Binary | OM::IO::Options::LSB | OM::IO::Options::VertexNormal, mesh,
             path, header_comments(mesh, mesh_digest(mesh)), 2);
}

void write_mesh_obj(const GridMesh& mesh, const std::string& path) {
  // The PLY comment block, as OBJ comments.
  std::istringstream lines(header_comments(mesh, std::nullopt));
  std::string comments, line;
  while (std::getline(lines, line)) comments += "# " + line.substr(8) + "\n";
  write_with(OM::IO::OBJWriter(), OM::IO::Options::VertexNormal, mesh, path, comments, 0);
}

namespace detail {

void read_body_openmesh(std::ifstream& in, GridMesh& m, const std::string& path) {
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
  check_vertices(m, path);
  read_optional(path, importer, m);
  // The faces: the grid's triangulation, less those with a corner outside the data.
  const std::vector<std::uint32_t> kept = m.kept_faces();
  std::size_t bad = importer.bad_faces;
  for (std::size_t j = 0; j < importer.faces.size(); ++j)
    bad += j >= kept.size() || importer.faces[j] != m.topo.face(kept[j]);
  if (importer.faces_read != kept.size() || bad != 0)
    throw faces_error(path, m.topo, importer.faces_read, bad);
  if (!m.voronoi.empty() && kept.size() != m.n_faces()) {  // read in kept-face order
    auto by_face = m.voronoi.corner_areas;
    std::fill(by_face.begin(), by_face.end(), Eigen::Vector3f::Zero());
    for (std::size_t j = 0; j < kept.size(); ++j) by_face[kept[j]] = m.voronoi.corner_areas[j];
    m.voronoi.corner_areas = std::move(by_face);
  }
}

}  // namespace detail

}  // namespace terrain
