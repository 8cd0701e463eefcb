// The mesh file: round trip and rejection of bad files.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "terrain/dem_io.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/prepare_grid.hpp"
#include "terrain/voronoi.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

GridMesh msh_mesh() {
  GridRequest req;
  req.spacing = 30.0;
  GridMesh m =
      make_grid_mesh(prepare_grid(read_dem(test::data("msh_2007_utm10n_10m.tif")), req).grid,
                     NormalWeighting::Angle);
  m.provenance = "mesh_io_test: a provenance line";
  return m;
}

TEST(MeshIo, RoundTripIsIdentical) {
  test::ScratchDir dir;
  const GridMesh m = msh_mesh();
  write_mesh_ply(m, dir.path("m.ply"));
  EXPECT_EQ(dir.n_entries(), 1u);  // no temporary left
  EXPECT_TRUE(is_ply_file(dir.path("m.ply")));
  const GridMesh back = read_mesh_ply(dir.path("m.ply"));
  EXPECT_EQ(back.topo.rows, m.topo.rows);
  EXPECT_EQ(back.topo.cols, m.topo.cols);
  EXPECT_EQ(back.positions, m.positions);  // bitwise: binary float32
  EXPECT_EQ(back.normals, m.normals);
  EXPECT_EQ(back.geo.crs_wkt, m.geo.crs_wkt);
  EXPECT_EQ(back.geo.epsg, 26910);
  EXPECT_EQ(back.geo.origin_x, m.geo.origin_x);  // %.17g round-trips doubles exactly
  EXPECT_EQ(back.geo.origin_y, m.geo.origin_y);
  EXPECT_EQ(back.geo.dx, m.geo.dx);
  EXPECT_EQ(back.geo.dy, m.geo.dy);
  EXPECT_EQ(back.provenance, m.provenance);
  // Faces: the reader compares every face with the grid triangulation; the file size
  // pins their count (header + 24 bytes per vertex + 13 per face).
  const auto size = std::filesystem::file_size(dir.path("m.ply"));
  EXPECT_GT(size, 24 * m.n_vertices() + 13 * m.n_faces());
  EXPECT_LT(size, 24 * m.n_vertices() + 13 * m.n_faces() + 8192);
}

// The block writer (issue 40) writes the bytes OpenMesh's PLY writer wrote: a plain mesh, a
// denoised one (Voronoi weights, tangents, corner areas, normal changes), a fitted one, one
// with non-ASCII text in its header, two larger than a block, and one with filled vertices
// (dem2mesh --fill-nodata), which reads back.
TEST(MeshIo, BlockWriterWritesOpenMeshsBytes) {
  test::ScratchDir dir;
  GridMesh plain = msh_mesh();
  GridMesh denoised = plain;
  denoised.voronoi = voronoi_weights(denoised);
  denoised.normal_change.resize(denoised.n_vertices());
  for (std::size_t i = 0; i < denoised.n_vertices(); ++i)
    denoised.normal_change[i] = float(i % 97) * 0.01f;
  GridMesh only_change = plain;
  only_change.normal_change = denoised.normal_change;
  GridMesh fitted = plain;
  fitted.normal_fit = {true, 1.25, 3.5, 0.827, 2.25, 14300000};
  fitted.provenance = "caf\xc3\xa9 \\ line";
  // Several of the writer's chunks (1 MiB of whole rows: 139 vertex rows or 129 cell rows
  // of 313 columns, 83 and 67 with the Voronoi weights), the last ones part-filled.
  GridMesh large = test::function_mesh(
      400, 313, 10.0, [](double x, double y) { return std::sin(x / 300) * y / 50; });
  GridMesh large_denoised = large;
  large_denoised.voronoi = voronoi_weights(large_denoised);
  GridMesh filled = denoised;
  filled.filled.assign(filled.n_vertices(), 0);
  for (std::size_t i = 0; i < filled.n_vertices(); i += 7) filled.filled[i] = 1;
  // With holes (docs/dem2mesh.md, "No-data"): a disc of data, every source of vertex; the
  // faces with an outside corner are left out, with their corner areas.
  GridMesh holed = denoised;
  holed.filled.assign(holed.n_vertices(), kFromData);
  const double rc = 0.5 * double(holed.topo.rows - 1), cc = 0.5 * double(holed.topo.cols - 1);
  for (std::size_t r = 0; r < holed.topo.rows; ++r)
    for (std::size_t c = 0; c < holed.topo.cols; ++c)
      if (std::hypot(double(r) - rc, double(c) - cc) > 0.4 * double(holed.topo.rows))
        holed.filled[r * holed.topo.cols + c] = std::uint8_t(kOutside);
      else if ((r + c) % 11 == 0)
        holed.filled[r * holed.topo.cols + c] = std::uint8_t((r + c) % 2 ? kInvented : kVoidFilled);
  ASSERT_TRUE(holed.has_holes());
  int k = 0;
  for (const GridMesh* m :
       {&plain, &denoised, &only_change, &fitted, &large, &large_denoised, &filled, &holed}) {
    const std::string n =
        std::to_string(k) + ".ply";  // appended: `"a" + std::string` trips GCC 12's -Wrestrict
    std::string a = "a", b = "b";
    a = dir.path(a += n), b = dir.path(b += n);
    write_mesh_ply(*m, a);
    write_mesh_ply_openmesh(*m, b);
    const std::string fa = test::file_bytes(a), fb = test::file_bytes(b);
    EXPECT_GT(fa.size(), 24 * m->n_vertices()) << k;
    EXPECT_TRUE(fa == fb) << "mesh " << k << ": " << fa.size() << " vs " << fb.size() << " bytes";
    const GridMesh back = read_mesh_ply(a);
    EXPECT_TRUE(back.filled == m->filled) << k;
    if (m == &holed) {  // the kept faces' corner areas read back in place, the others 0
      const std::vector<std::uint32_t> kept = m->kept_faces();
      ASSERT_LT(kept.size(), m->n_faces());
      EXPECT_NE(fa.find(fmt::format("element face {}\n", kept.size())), std::string::npos);
      for (std::size_t f = 0; f < m->n_faces(); ++f)
        ASSERT_EQ(back.voronoi.corner_areas[f],
                  m->face_kept(f) ? m->voronoi.corner_areas[f] : Eigen::Vector3f::Zero())
            << f;
    }
    ++k;
  }
}

// dem2mesh's streaming writer: the bytes of the whole mesh's, in one chunk and in several,
// with and without the filled flags, for each normal rule.
TEST(MeshIo, GridWriterWritesTheMeshWritersBytes) {
  test::ScratchDir dir;
  GridRequest req;
  req.spacing = 30.0;
  const Grid msh = prepare_grid(read_dem(test::data("msh_2007_utm10n_10m.tif")), req).grid;
  const Grid large = mesh_to_grid(test::function_mesh(
      400, 313, 10.0, [](double x, double y) { return std::sin(x / 300) * y / 50; }));
  int k = 0;
  for (const Grid* g : {&msh, &large})
    for (NormalWeighting w : {NormalWeighting::Uniform, NormalWeighting::Angle})
      for (bool filled : {false, true}) {
        GridMesh whole = make_grid_mesh(*g, w);
        GridMesh frame = grid_mesh_frame(*g);
        whole.provenance = frame.provenance = "mesh_io_test";
        if (filled) {
          whole.filled.assign(whole.n_vertices(), 0);
          for (std::size_t i = 0; i < whole.filled.size(); i += 5) whole.filled[i] = 1;
          frame.filled.assign(whole.filled.begin(), whole.filled.end());
        }
        const std::string n = std::to_string(k++) + ".ply";
        std::string a = "a", b = "b";
        a = dir.path(a += n), b = dir.path(b += n);
        write_mesh_ply(whole, a);
        write_grid_mesh_ply(frame, *g, w, b);
        EXPECT_TRUE(test::file_bytes(a) == test::file_bytes(b))
            << "grid " << g->cols << " " << to_string(w) << " " << filled;
      }
}

TEST(MeshIo, RejectsBadFiles) {
  test::ScratchDir dir;
  const GridMesh m = msh_mesh();
  write_mesh_ply(m, dir.path("m.ply"));
  // Truncated.
  std::filesystem::copy_file(dir.path("m.ply"), dir.path("cut.ply"));
  std::filesystem::resize_file(dir.path("cut.ply"),
                               std::filesystem::file_size(dir.path("m.ply")) / 2);
  EXPECT_THROW(read_mesh_ply(dir.path("cut.ply")), Error);
  // Not a PLY.
  std::ofstream(dir.path("text.ply")) << "hello\n";
  EXPECT_THROW(read_mesh_ply(dir.path("text.ply")), Error);
  // A PLY without our georeferencing.
  std::ofstream(dir.path("plain.ply"))
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\n"
         "property list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  try {
    read_mesh_ply(dir.path("plain.ply"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a terrain mesh"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_mesh_ply(dir.path("missing.ply")), Error);
  // Writing into a missing directory fails before creating anything.
  EXPECT_THROW(write_mesh_ply(m, dir.path("no/such/dir/m.ply")), Error);
}

TEST(MeshIo, ObjExportHasEveryVertexAndFace) {
  test::ScratchDir dir;
  const GridMesh m = msh_mesh();
  write_mesh_obj(m, dir.path("m.obj"));
  std::ifstream in(dir.path("m.obj"));
  std::size_t v = 0, vn = 0, f = 0;
  bool has_origin = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vn ", 0) == 0) ++vn;
    if (line.rfind("f ", 0) == 0) ++f;
    if (line.rfind("# origin ", 0) == 0) has_origin = true;
  }
  EXPECT_EQ(v, m.n_vertices());
  EXPECT_EQ(vn, m.n_vertices());
  EXPECT_EQ(f, m.n_faces());
  EXPECT_TRUE(has_origin);
}

// The file's bytes split at the end of the header: header lines and the body.
struct PlyParts {
  std::vector<std::string> header;  // lines without their newline, up to end_header
  std::string body;
};

PlyParts split_ply(const std::string& path) {
  const std::string bytes = test::file_bytes(path);
  const std::size_t end = bytes.find("end_header\n") + 11;
  PlyParts p;
  std::istringstream lines(bytes.substr(0, end));
  for (std::string line; std::getline(lines, line);) p.header.push_back(line);
  p.body = bytes.substr(end);
  return p;
}

void write_ply(const PlyParts& p, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  for (const auto& line : p.header) out << line << "\n";
  out << p.body;
}

// The read error's message for `parts`, or "" when it reads.
std::string read_error(const PlyParts& parts, const test::ScratchDir& dir) {
  write_ply(parts, dir.path("bad.ply"));
  try {
    read_mesh_ply(dir.path("bad.ply"));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Every face is checked against the grid triangulation, by both readers: the plain layout's
// block reader (read_plain_body) and OpenMesh's (a mesh with optional data, here a
// normal-change property): one vertex index changed, or a face of four, is refused with
// the count of faces that differ; the vertex block reads back bit for bit.
TEST(MeshIo, BothReadersCheckEveryFace) {
  test::ScratchDir dir;
  GridMesh plain = msh_mesh();
  GridMesh changed = plain;
  changed.normal_change.assign(changed.n_vertices(), 0.5f);
  for (const GridMesh* m : {&plain, &changed}) {
    write_mesh_ply(*m, dir.path("m.ply"));
    const GridMesh back = read_mesh_ply(dir.path("m.ply"));
    EXPECT_EQ(back.positions, m->positions);
    EXPECT_EQ(back.normals, m->normals);
    const std::size_t record = 24 + (m->normal_change.empty() ? 0 : 4);
    PlyParts parts = split_ply(dir.path("m.ply"));
    const std::size_t faces = m->n_vertices() * record;
    PlyParts index = parts, count = parts;
    index.body[faces + 5 * 13 + 1 + 4] ^= 1;  // face 5's second vertex index
    count.body[faces + 7 * 13] = 4;           // face 7 has four corners
    const std::string e = read_error(index, dir);
    EXPECT_NE(e.find("faces are not the"), std::string::npos) << e;
    EXPECT_NE(read_error(count, dir), "");
    if (m == &plain) {
      EXPECT_NE(e.find("1 differ"), std::string::npos) << e;
    }
  }
}

// Damaged headers found by probing and fuzzing the reader (each crashed, hung or
// exhausted memory inside OpenMesh's PLY parser before the header was validated).
TEST(MeshIo, DamagedHeadersAreOneClearError) {
  test::ScratchDir dir;
  write_mesh_ply(msh_mesh(), dir.path("m.ply"));
  const PlyParts good = split_ply(dir.path("m.ply"));
  ASSERT_EQ(read_error(good, dir), "");
  auto edit = [&](const std::string& line, const std::vector<std::string>& replacement) {
    PlyParts p = good;
    auto it = std::find_if(p.header.begin(), p.header.end(),
                           [&](const std::string& l) { return l.rfind(line, 0) == 0; });
    EXPECT_NE(it, p.header.end()) << line;
    it = p.header.erase(it);
    p.header.insert(it, replacement.begin(), replacement.end());
    return p;
  };
  const std::string face_line = [&] {
    for (const auto& l : good.header)
      if (l.rfind("element face", 0) == 0) return l;
    return std::string();
  }();
  const std::vector<std::pair<PlyParts, std::string>> cases = {
      {edit("element vertex", {}), "property before any element"},
      {edit("element vertex", {"element vertex @36"}),
       "element 'vertex' has no valid count ('@36')"},
      {edit("element vertex", {"element vertex"}), "expected 'element NAME COUNT'"},
      {edit("element vertex", {"element vertex 1099511627776"}),
       "element 'vertex' has no valid count"},
      {edit("element vertex", {"element vertex 1099511627"}), "1099511627 vertices, but its"},
      {edit("element face", {face_line, face_line}), "element 'face' appears twice"},
      {edit("element face", {"element edge 0", face_line}), "unexpected PLY element 'edge'"},
      {edit("format", {"format ascii 1.0"}), "in ascii format"},
      {edit("format", {"format binary_little_endian 2.0"}), "unknown format"},
      {edit("property float nz", {}), "the vertices have no property 'nz'"},
      {edit("property float nz", {"property double nz"}), "vertex property 'nz' is not a float"},
      {edit("property float nz", {"property float nz", "property float nz"}), "appears twice"},
      {edit("property float nz", {"property flaot nz"}), "unknown property type 'flaot'"},
      {edit("property list", {"property list uchar float vertex_indices"}), "vertex_indices"},
      {edit("end_header", {"end_heder"}), "unknown keyword 'end_heder'"},
      {edit("comment grid", {"comment grid 18446744073709551615 2 30 30"}), "invalid grid"},
      {edit("comment grid", {"comment grid 4294967296 4294967296 30 30"}), "invalid grid"},
      {edit("comment origin", {"comment origin nan 0 0"}), "invalid 'origin' comment"},
  };
  for (const auto& [parts, expected] : cases)
    EXPECT_NE(read_error(parts, dir).find(expected), std::string::npos)
        << "expected '" << expected << "', got '" << read_error(parts, dir) << "'";

  PlyParts trailing = good;
  trailing.body += "xx";
  EXPECT_NE(read_error(trailing, dir).find("2 unexpected bytes after the faces"),
            std::string::npos);
  PlyParts cut = good;
  cut.body.resize(cut.body.size() - 1);
  EXPECT_NE(read_error(cut, dir).find("truncated"), std::string::npos);
  // A NaN coordinate (vertex 7's z) in an otherwise valid file.
  PlyParts nan = good;
  const float q = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.body.data() + 7 * 24 + 8, &q, 4);
  EXPECT_NE(read_error(nan, dir).find("vertex 7 (row 0, column 7) is not a finite number"),
            std::string::npos)
      << read_error(nan, dir);
}

// Non-ASCII text (the degree signs in EPSG's WKT usage areas, a provenance path) is
// escaped in the header, which stays 7-bit ASCII, and comes back unchanged.
TEST(MeshIo, HeaderIsAsciiAndNonAsciiTextRoundTrips) {
  test::ScratchDir dir;
  GridMesh m = msh_mesh();
  m.provenance = "dem2mesh /data/H\xC3\xB6he/dem.tif \\ 126\xC2\xB0W";
  ASSERT_NE(m.geo.crs_wkt.find("\xC2\xB0"), std::string::npos);  // the WKT has degree signs
  write_mesh_ply(m, dir.path("m.ply"));
  for (const std::string& line : split_ply(dir.path("m.ply")).header)
    for (const char c : line) EXPECT_LT(static_cast<unsigned char>(c), 0x80u) << line;
  const GridMesh back = read_mesh_ply(dir.path("m.ply"));
  EXPECT_EQ(back.provenance, m.provenance);
  EXPECT_EQ(back.geo.crs_wkt, m.geo.crs_wkt);
}

}  // namespace
}  // namespace terrain
