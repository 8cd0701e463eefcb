// The mesh file: round trip and rejection of bad files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "terrain/dem_io.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/prepare_grid.hpp"
#include "test_support.hpp"

namespace terrain {
namespace {

GridMesh msh_mesh() {
  GridRequest req;
  req.spacing = 30.0;
  GridMesh m = make_grid_mesh(prepare_grid(read_dem(test::data("msh_2007_utm10n_10m.tif")), req).grid,
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

TEST(MeshIo, RejectsBadFiles) {
  test::ScratchDir dir;
  const GridMesh m = msh_mesh();
  write_mesh_ply(m, dir.path("m.ply"));
  // Truncated.
  std::filesystem::copy_file(dir.path("m.ply"), dir.path("cut.ply"));
  std::filesystem::resize_file(dir.path("cut.ply"), std::filesystem::file_size(dir.path("m.ply")) / 2);
  EXPECT_THROW(read_mesh_ply(dir.path("cut.ply")), Error);
  // Not a PLY.
  std::ofstream(dir.path("text.ply")) << "hello\n";
  EXPECT_THROW(read_mesh_ply(dir.path("text.ply")), Error);
  // A PLY without our georeferencing.
  std::ofstream(dir.path("plain.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
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

}  // namespace
}  // namespace terrain
