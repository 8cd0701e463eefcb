// The mesh pyramid (terrain/mesh_pyramid.hpp, docs/formats.md): windows read back equal the
// mesh's own vertices at every level, bit for bit; a window reads only the tiles under it
// (the reader's accounting); the blocks' boxes and errors come back as computed; a
// damaged file is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "terrain/error.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"
#include "test_support.hpp"

namespace {

terrain::GridMesh bumps(std::size_t rows, std::size_t cols) {
  terrain::GridMesh m = terrain::test::function_mesh(rows, cols, 10.0, [](double x, double y) {
    return 0.05 * x + 40 * std::sin(x / 90) * std::cos(y / 70) + 8 * std::sin(x / 23 + y / 31);
  });
  m.geo.origin_x = 500000, m.geo.origin_y = 4100000, m.geo.origin_z = 100;
  m.geo.epsg = 32612;
  m.geo.crs_wkt = "PROJCS[\"test\"]";
  return m;
}

bool same(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return a.x() == b.x() && a.y() == b.y() && a.z() == b.z();
}

}  // namespace

// Every level read whole, and random windows of each, equal the mesh's vertices at that
// level's rows and columns (every 2^l-th and the last), positions and normals exactly; the
// georeference, the blocks' boxes, errors and slopes come back as written.
TEST(MeshPyramid, WindowsEqualTheMeshAtEveryLevel) {
  const terrain::GridMesh m = bumps(150, 131);
  const terrain::MeshLevels levels = terrain::build_mesh_levels(m, 16);
  terrain::test::ScratchDir dir;
  const std::string path = dir.path("m.tpyr");
  const std::uint64_t bytes = terrain::write_mesh_pyramid(m, path, 16);
  EXPECT_EQ(bytes, std::filesystem::file_size(path));
  ASSERT_TRUE(terrain::is_mesh_pyramid(path));
  terrain::MeshPyramid p(path);
  EXPECT_EQ(p.georef().origin_x, m.geo.origin_x);
  EXPECT_EQ(p.georef().origin_z, m.geo.origin_z);
  EXPECT_EQ(p.georef().epsg, 32612);
  EXPECT_EQ(p.georef().crs_wkt, m.geo.crs_wkt);
  EXPECT_EQ(p.topology().rows, 150u);
  EXPECT_EQ(p.topology().cols, 131u);
  EXPECT_EQ(p.level_count(), 5);  // blocks of 16 cells: steps 1 .. 16
  ASSERT_EQ(p.levels().blocks.size(), levels.blocks.size());
  for (std::size_t k = 0; k < levels.blocks.size(); ++k) {
    EXPECT_EQ(p.levels().blocks[k].error, levels.blocks[k].error);
    EXPECT_EQ(p.levels().blocks[k].slope, levels.blocks[k].slope);
    EXPECT_TRUE(same(p.levels().blocks[k].lo, levels.blocks[k].lo) &&
                same(p.levels().blocks[k].hi, levels.blocks[k].hi));
    EXPECT_EQ(p.levels().blocks[k].r0, levels.blocks[k].r0);
    EXPECT_EQ(p.levels().blocks[k].nc, levels.blocks[k].nc);
  }
  std::mt19937 rng(7);
  for (int l = 0; l < p.level_count(); ++l) {
    const std::size_t R = p.rows(l), C = p.cols(l);
    EXPECT_EQ(R, (149 + (1u << l) - 1) / (1u << l) + 1);
    auto check = [&](std::size_t r0, std::size_t c0, std::size_t nr, std::size_t nc) {
      const terrain::MeshWindow w = p.read_window(l, r0, c0, nr, nc);
      std::size_t differ = 0;
      for (std::size_t r = 0; r < nr; ++r)
        for (std::size_t c = 0; c < nc; ++c) {
          const std::size_t v =
              terrain::level_index(r0 + r, 149, l) * 131 + terrain::level_index(c0 + c, 130, l);
          differ += !same(w.positions[r * nc + c], m.positions[v]) ||
                    !same(w.normals[r * nc + c], m.normals[v]);
        }
      EXPECT_EQ(differ, 0u) << "level " << l << " window " << r0 << " " << c0 << " " << nr << " "
                            << nc;
    };
    check(0, 0, R, C);
    for (int k = 0; k < 5; ++k) {
      const std::size_t r0 = rng() % R, c0 = rng() % C;
      check(r0, c0, 1 + rng() % (R - r0), 1 + rng() % (C - c0));
    }
  }
  // The last vertex of every level is the mesh's last.
  const terrain::MeshWindow corner = p.read_window(
      p.level_count() - 1, p.rows(p.level_count() - 1) - 1, p.cols(p.level_count() - 1) - 1, 1, 1);
  EXPECT_TRUE(same(corner.positions[0], m.positions[150 * 131 - 1]));
}

// Memory bounded by the view: opening reads the header, blocks and index only (a small
// part of the file); a window inside one tile reads that tile and no other, one across a
// tile corner the four tiles there, and the bytes read are exactly those tiles'.
TEST(MeshPyramid, AWindowReadsOnlyTheTilesUnderIt) {
  const terrain::GridMesh m = bumps(257, 257);
  terrain::test::ScratchDir dir;
  const std::string path = dir.path("m.tpyr");
  const std::uint64_t bytes = terrain::write_mesh_pyramid(m, path, 32);
  terrain::MeshPyramid p(path);
  const std::uint64_t opened = p.bytes_read();
  EXPECT_LT(double(opened), 0.05 * double(bytes));
  EXPECT_EQ(p.tiles_read(), 0u);
  p.read_window(0, 40, 70, 10, 20);  // inside tile (1, 2) of level 0 (32 cells a tile)
  EXPECT_EQ(p.tiles_read(), 1u);
  EXPECT_EQ(p.bytes_read(), opened + p.tile_bytes(0, 1, 2));
  p.read_window(0, 60, 60, 10, 10);  // across the corner of tiles (1, 1), (1, 2), (2, 1), (2, 2)
  EXPECT_EQ(p.tiles_read(), 5u);
  EXPECT_EQ(p.bytes_read(), opened + p.tile_bytes(0, 1, 2) + p.tile_bytes(0, 1, 1) +
                                p.tile_bytes(0, 1, 2) + p.tile_bytes(0, 2, 1) +
                                p.tile_bytes(0, 2, 2));
  p.read_window(3, 0, 0, p.rows(3), p.cols(3));  // level 3: 33 x 33 vertices, one tile
  EXPECT_EQ(p.tiles_read(), 6u);
}

// Not a pyramid, a truncated one, a damaged tile: one clear error each.
TEST(MeshPyramid, DamagedFilesAreRefused) {
  const terrain::GridMesh m = bumps(70, 70);
  terrain::test::ScratchDir dir;
  const std::string path = dir.path("m.tpyr");
  const std::uint64_t bytes = terrain::write_mesh_pyramid(m, path, 16);
  const std::string good = terrain::test::file_bytes(path);
  auto write = [&](const std::string& name, const std::string& s) {
    std::ofstream(dir.path(name), std::ios::binary) << s;
    return dir.path(name);
  };
  EXPECT_FALSE(
      terrain::is_mesh_pyramid(write("ply.tpyr", "ply\nformat binary_little_endian 1.0\n")));
  EXPECT_THROW(terrain::MeshPyramid(dir.path("ply.tpyr")), terrain::Error);
  const std::string cut = write("cut.tpyr", good.substr(0, std::size_t(bytes / 2)));
  try {
    terrain::MeshPyramid p(cut);
    FAIL() << "a truncated pyramid opened";
  } catch (const terrain::Error& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  std::string flipped = good;
  const std::size_t first_tile =
      std::size_t(terrain::MeshPyramid(path).bytes_read());  // level 0's first tile starts here
  flipped[first_tile + 10] = char(flipped[first_tile + 10] ^ 0x5a);
  terrain::MeshPyramid p(write("flip.tpyr", flipped));
  try {
    p.read_window(0, 0, 0, p.rows(0), p.cols(0));
    FAIL() << "a damaged tile was read";
  } catch (const terrain::Error& e) {
    EXPECT_NE(std::string(e.what()).find("is corrupt"), std::string::npos) << e.what();
  }
  EXPECT_THROW(p.read_window(0, 0, 0, p.rows(0) + 1, 1), terrain::Error);
  // Every header byte is under its CRC (version 3): a block's box, an error, the digest, a
  // tile's offset in the index, each changed by one bit, is refused at opening.
  const std::size_t header = first_tile;
  for (const std::size_t at :
       {std::size_t(40), std::size_t(100), header / 2, header - 20, header - 5}) {
    std::string bad = good;
    bad[at] = char(bad[at] ^ 0x01);
    try {
      terrain::MeshPyramid q(write("header.tpyr", bad));
      ADD_FAILURE() << "a header with byte " << at << " changed opened";
    } catch (const terrain::Error& e) {
      EXPECT_NE(std::string(e.what()).find("corrupt mesh pyramid (its header's checksum)"),
                std::string::npos)
          << at << ": " << e.what();
    }
  }
}

// A pyramid of version 1 (before the blocks' slopes) still reads: the same grid, blocks,
// errors and tiles, its slopes not known (empty: the renderer then holds every level to
// the strict bound). Made from a version-2 file (pyramid_as_version1).
TEST(MeshPyramid, AVersionOnePyramidReadsWithoutSlopes) {
  const terrain::GridMesh m = bumps(70, 70);
  terrain::test::ScratchDir dir;
  const std::string path = dir.path("m.tpyr");
  terrain::write_mesh_pyramid(m, path, 16);
  terrain::MeshPyramid p2(path);
  const std::string v1 = terrain::test::pyramid_as_version1(terrain::test::file_bytes(path));
  std::ofstream(dir.path("v1.tpyr"), std::ios::binary) << v1;
  terrain::MeshPyramid p1(dir.path("v1.tpyr"));
  ASSERT_EQ(p1.levels().blocks.size(), p2.levels().blocks.size());
  for (std::size_t k = 0; k < p1.levels().blocks.size(); ++k) {
    EXPECT_EQ(p1.levels().blocks[k].error, p2.levels().blocks[k].error);
    EXPECT_TRUE(p1.levels().blocks[k].slope.empty());
    EXPECT_FALSE(p2.levels().blocks[k].slope.empty());
  }
  for (int l = 0; l < p2.level_count(); ++l) {
    const terrain::MeshWindow a = p1.read_window(l, 0, 0, p1.rows(l), p1.cols(l));
    const terrain::MeshWindow b = p2.read_window(l, 0, 0, p2.rows(l), p2.cols(l));
    EXPECT_EQ(a.positions, b.positions) << l;
    EXPECT_EQ(a.normals, b.normals) << l;
  }
}

// A renderer reads the mesh from its pyramid (read_mesh_via_pyramid): the same mesh as the
// PLY, bit for bit, with the same levels as computed from it; and not when the pyramid is
// older than the PLY, describes another grid, or the PLY holds data the pyramid lacks.
TEST(MeshPyramid, TheMeshReadFromItsPyramidIsThePly) {
  terrain::GridMesh m = bumps(150, 131);
  m.provenance = "test provenance";
  m.geo.crs_wkt.clear();  // a PLY's CRS must parse; the EPSG code is enough here

  terrain::test::ScratchDir dir;
  const std::string ply = dir.path("m.ply"), pyr = dir.path("m.tpyr");
  std::string why;
  terrain::write_mesh_ply(m, ply);
  EXPECT_FALSE(terrain::read_mesh_via_pyramid(ply, why));
  EXPECT_EQ(why, "");  // no pyramid: nothing to say
  const terrain::MeshLevels levels = terrain::build_mesh_levels(m);
  terrain::write_mesh_pyramid(m, pyr);
  const std::optional<terrain::PyramidMesh> got = terrain::read_mesh_via_pyramid(ply, why);
  ASSERT_TRUE(got) << why;
  const terrain::GridMesh from_ply = terrain::read_mesh_ply(ply);
  ASSERT_EQ(got->mesh.n_vertices(), from_ply.n_vertices());
  std::size_t differ = 0;
  for (std::size_t v = 0; v < from_ply.n_vertices(); ++v)
    differ += !same(got->mesh.positions[v], from_ply.positions[v]) ||
              !same(got->mesh.normals[v], from_ply.normals[v]);
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(got->mesh.provenance, from_ply.provenance);
  EXPECT_EQ(got->mesh.geo.origin_y, from_ply.geo.origin_y);
  EXPECT_EQ(got->mesh.geo.crs_wkt, from_ply.geo.crs_wkt);
  ASSERT_EQ(got->levels.blocks.size(), levels.blocks.size());
  for (std::size_t k = 0; k < levels.blocks.size(); ++k)
    EXPECT_EQ(got->levels.blocks[k].error, levels.blocks[k].error);

  // The pair is tied by content, not by time: a PLY touched after its pyramid (or copied
  // with cp -p, tar, rsync -t) still reads its pyramid.
  const auto later = std::filesystem::last_write_time(pyr) + std::chrono::seconds(2);
  std::filesystem::last_write_time(ply, later);
  EXPECT_TRUE(terrain::read_mesh_via_pyramid(ply, why)) << why;
  // The PLY rewritten with other heights on the same grid, its old pyramid left beside it
  // with the same time (a stale pair the old rule took): refused, and the PLY read.
  terrain::GridMesh other = m;
  other.positions[4321].z() += 0.5f;
  terrain::write_mesh_ply(other, ply);
  std::filesystem::last_write_time(pyr, std::filesystem::last_write_time(ply));
  EXPECT_FALSE(terrain::read_mesh_via_pyramid(ply, why));
  EXPECT_NE(why.find("made from another mesh"), std::string::npos) << why;
  std::string source, warning;
  const terrain::GridMesh read = terrain::read_terrain_mesh(ply, &source, nullptr, &warning);
  EXPECT_EQ(read.positions[4321].z(), other.positions[4321].z());
  EXPECT_NE(warning.find("read whole, not its pyramid"), std::string::npos) << warning;
  // Another DEM's pyramid beside it, newer: refused.
  terrain::write_mesh_pyramid(bumps(150, 130), pyr);
  std::filesystem::last_write_time(pyr, later + std::chrono::seconds(2));
  EXPECT_FALSE(terrain::read_mesh_via_pyramid(ply, why));
  EXPECT_NE(why.find("made from another mesh"), std::string::npos) << why;
  // The vertices' sources (dem2mesh's 'filled': no-data outside the mesh, invented, a void
  // filled) come back from the pyramid (version 4), at every level the vertices' own; a
  // pyramid without them (as before version 4) is refused for a mesh that has them.
  m.filled.assign(m.n_vertices(), terrain::kFromData);
  for (std::size_t r = 0; r < m.topo.rows; ++r)
    for (std::size_t c = 0; c < m.topo.cols; ++c)
      if (std::hypot(double(r) - 75, double(c) - 65) > 60)
        m.filled[r * m.topo.cols + c] = terrain::kOutside;
  m.filled[75 * m.topo.cols + 65] = terrain::kVoidFilled;
  m.filled[70 * m.topo.cols + 60] = terrain::kInvented;
  terrain::write_mesh_ply(m, ply);
  terrain::write_mesh_pyramid(m, pyr);
  for (int l : {0, 1, 3}) {
    const auto holed = terrain::read_mesh_via_pyramid(
        ply, why, [&](const terrain::MeshPyramid&) { return terrain::PyramidPart(l); });
    ASSERT_TRUE(holed) << why;
    const terrain::GridMesh& h = holed->mesh;
    ASSERT_EQ(h.filled.size(), h.n_vertices());
    std::size_t wrong = 0;
    for (std::size_t r = 0; r < h.topo.rows; ++r)
      for (std::size_t c = 0; c < h.topo.cols; ++c)
        wrong += h.filled[r * h.topo.cols + c] !=
                 m.filled[terrain::level_index(r, m.topo.rows - 1, l) * m.topo.cols +
                          terrain::level_index(c, m.topo.cols - 1, l)];
    EXPECT_EQ(wrong, 0u) << "level " << l;
    EXPECT_TRUE(h.has_holes());
  }
  const auto holed = terrain::read_mesh_via_pyramid(ply, why);
  EXPECT_EQ(holed->mesh.kept_faces(), terrain::read_mesh_ply(ply).kept_faces());
  // Blocks with an outside vertex are drawn at level 0, as build_mesh_levels says.
  const terrain::MeshLevels holed_levels = terrain::build_mesh_levels(m);
  for (std::size_t k = 0; k < holed_levels.blocks.size(); ++k)
    EXPECT_EQ(holed->levels.blocks[k].error, holed_levels.blocks[k].error);
  EXPECT_EQ(holed_levels.blocks[0].error.back(), terrain::kHoleError);
  terrain::GridMesh without = m;
  without.filled.clear();
  terrain::write_mesh_pyramid(without, pyr);
  EXPECT_FALSE(terrain::read_mesh_via_pyramid(ply, why));
  EXPECT_NE(why.find("'filled'"), std::string::npos) << why;
}

// A window of the mesh's blocks read through read_mesh_via_pyramid (PyramidPart: what a
// frame of a near view reads, hold_views) is that part of the level, a grid mesh of its
// own: at level 0 and level 2, in the middle and at the far corner (the partial blocks,
// whose last row and column level 2 keeps closer), its vertices are the whole level's
// there moved by the window's corner (exactly: a 10 m lattice), its origin the corner's,
// its spacing the whole level's; its blocks are the window's, moved the same; the whole
// mesh's box comes with it. (It is read by MeshPyramid::read_window, whose accounting
// AWindowReadsOnlyTheTilesUnderIt checks.)
TEST(MeshPyramid, AWindowOfBlocksIsThatPartOfTheLevel) {
  terrain::GridMesh m = bumps(300, 271);  // 299 x 270 cells: 5 x 5 blocks of 64, the last partial
  m.geo.crs_wkt.clear();
  terrain::test::ScratchDir dir;
  const std::string ply = dir.path("m.ply");
  terrain::write_mesh_ply(m, ply);
  terrain::write_mesh_pyramid(m, dir.path("m.tpyr"));
  struct Case {
    int level;
    std::size_t br0, bc0, br1, bc1;
  };
  for (const Case c :
       {Case{0, 1, 2, 3, 4}, Case{2, 1, 2, 3, 4}, Case{2, 3, 3, 9, 9}, Case{0, 4, 1, 5, 5}}) {
    SCOPED_TRACE(::testing::Message()
                 << "level " << c.level << ", blocks " << c.br0 << ", " << c.bc0);
    std::string why;
    const auto whole = terrain::read_mesh_via_pyramid(
        ply, why, [&](const terrain::MeshPyramid&) { return c.level; });
    const auto part = terrain::read_mesh_via_pyramid(ply, why, [&](const terrain::MeshPyramid&) {
      return terrain::PyramidPart{c.level, c.br0, c.bc0, c.br1, c.bc1};
    });
    ASSERT_TRUE(whole && part) << why;
    ASSERT_FALSE(whole->levels.window);
    ASSERT_TRUE(part->levels.window);
    const auto& w = *part->levels.window;
    const std::size_t br1 = std::min<std::size_t>(c.br1, 5), bc1 = std::min<std::size_t>(c.bc1, 5);
    EXPECT_EQ(w.r0, 64 * c.br0);
    EXPECT_EQ(w.c0, 64 * c.bc0);
    EXPECT_EQ(part->levels.topo.rows, std::min<std::size_t>(64 * br1, 299) - w.r0 + 1);
    EXPECT_EQ(part->levels.topo.cols, std::min<std::size_t>(64 * bc1, 270) - w.c0 + 1);
    EXPECT_EQ(w.whole.rows, 300u);
    EXPECT_EQ(w.geo.origin_x, m.geo.origin_x);
    EXPECT_EQ(part->levels.base, c.level);
    EXPECT_EQ(part->mesh.geo.dx, whole->mesh.geo.dx);
    EXPECT_EQ(part->mesh.geo.origin_x, m.geo.origin_x + 10.0 * double(w.c0));
    EXPECT_EQ(part->mesh.geo.origin_y, m.geo.origin_y - 10.0 * double(w.r0));
    // Level l's rows and columns of the window.
    const std::size_t r0 = w.r0 >> c.level, c0 = w.c0 >> c.level;
    ASSERT_EQ(part->mesh.topo.rows, terrain::level_count(part->levels.topo.rows - 1, c.level));
    ASSERT_EQ(part->mesh.topo.cols, terrain::level_count(part->levels.topo.cols - 1, c.level));
    ASSERT_LE(r0 + part->mesh.topo.rows, whole->mesh.topo.rows);
    const Eigen::Vector3f shift(float(10.0 * double(w.c0)), -float(10.0 * double(w.r0)), 0);
    std::size_t differ = 0;
    for (std::size_t r = 0; r < part->mesh.topo.rows; ++r)
      for (std::size_t col = 0; col < part->mesh.topo.cols; ++col) {
        const std::size_t i = r * part->mesh.topo.cols + col,
                          j = (r0 + r) * whole->mesh.topo.cols + c0 + col;
        differ += !same(part->mesh.positions[i] + shift, whole->mesh.positions[j]) ||
                  !same(part->mesh.normals[i], whole->mesh.normals[j]);
      }
    EXPECT_EQ(differ, 0u);
    // Its blocks, moved; the whole box.
    ASSERT_EQ(part->levels.block_rows, br1 - c.br0);
    ASSERT_EQ(part->levels.block_cols, bc1 - c.bc0);
    for (std::size_t br = 0; br < part->levels.block_rows; ++br)
      for (std::size_t bc = 0; bc < part->levels.block_cols; ++bc) {
        const auto& a = part->levels.blocks[br * part->levels.block_cols + bc];
        const auto& b = whole->levels.blocks[(c.br0 + br) * 5 + c.bc0 + bc];
        EXPECT_EQ(a.r0 + w.r0, b.r0);
        EXPECT_EQ(a.c0 + w.c0, b.c0);
        EXPECT_TRUE(same(a.lo + shift, b.lo) && same(a.hi + shift, b.hi));
        EXPECT_EQ(a.error, b.error);
      }
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = -lo;
    for (const auto& b : whole->levels.blocks) lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi);
    EXPECT_TRUE(same(w.lo + shift, lo) && same(w.hi + shift, hi));
  }
}
