// The .dv file: round trip, rejection of damaged files, and its views.
#include <gtest/gtest.h>

#include <filesystem>
#include <cstring>
#include <fstream>
#include <limits>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/pipeline.hpp"
#include "drainage_test_support.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

namespace fs = std::filesystem;

DrainageResult logan_drainage() {
  return compute_drainage(terrain::read_dem(terrain::test::data("logan_utm12n_100m.tif")), {});
}

TEST(DvFile, RoundTrip) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  const DvHeader h = make_dv_header(r.surface, r.net, r.dv_flags, "dv_file_test");
  write_dv(dir.path("a.dv"), h, r.surface, r.dirs, r.net);
  EXPECT_EQ(dir.n_entries(), 1u);
  ASSERT_TRUE(is_dv_file(dir.path("a.dv")));
  const DrainageDb db = read_dv(dir.path("a.dv"));
  EXPECT_EQ(db.header.rows, r.surface.rows);
  EXPECT_EQ(db.header.cols, r.surface.cols);
  EXPECT_EQ(db.header.epsg, 26912);
  EXPECT_EQ(db.header.crs_wkt, r.surface.geo.crs_wkt);
  EXPECT_EQ(db.header.provenance, "dv_file_test");
  EXPECT_EQ(db.header.valid, r.net.points);
  EXPECT_EQ(db.header.basins, r.net.pits.size());
  EXPECT_DOUBLE_EQ(db.header.origin_x, r.surface.geo.x_of_col(0));
  ASSERT_EQ(db.vertices.size(), r.surface.size());
  for (std::size_t i = 0; i < db.vertices.size(); ++i) {
    const DvVertex& v = db.vertices[i];
    ASSERT_EQ(v.accumulated, r.net.accumulated[i]);
    ASSERT_EQ(v.normalized, r.net.normalized[i]);
    ASSERT_EQ(v.basin, r.net.basin[i]);
    ASSERT_EQ(v.downstream, r.net.downstream[i]);
    ASSERT_EQ(v.point_class, r.net.point_class[i]);
    ASSERT_EQ(v.order, r.net.order[i]);
    ASSERT_EQ(v.d8, r.dirs[i]);
    ASSERT_FLOAT_EQ(float(db.header.origin_z) + v.z, r.surface.z[i]);
  }
  ASSERT_EQ(db.branches.size(), r.net.branches.size());
  for (std::size_t b = 0; b < db.branches.size(); ++b) {
    ASSERT_EQ(db.branches[b].first, r.net.branches[b].first);
    ASSERT_EQ(db.branches[b].count, r.net.branches[b].count);
    ASSERT_EQ(db.branches[b].drains_into, r.net.branches[b].drains_into);
    ASSERT_EQ(db.branches[b].order, r.net.branches[b].order);
  }
  EXPECT_TRUE(std::equal(db.branch_vertices.begin(), db.branch_vertices.end(), r.net.branch_vertices.begin()));
  const DvSummary s = summarize(db);
  EXPECT_EQ(s.points, r.net.points);
  EXPECT_EQ(s.pits, r.net.pits.size());
  EXPECT_EQ(s.pits + s.ridges + s.channels + s.junctions, s.points);
}

void expect_error(const std::string& path, const std::string& fragment) {
  try {
    read_dv(path);
    FAIL() << "no error for " << path;
  } catch (const terrain::Error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(DvFile, RejectsDamagedFiles) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  write_dv(dir.path("a.dv"), make_dv_header(r.surface, r.net, r.dv_flags, ""), r.surface, r.dirs, r.net);
  const auto size = fs::file_size(dir.path("a.dv"));
  auto patched = [&](const std::string& name, std::size_t offset, const std::string& bytes) {
    fs::copy_file(dir.path("a.dv"), dir.path(name));
    std::fstream f(dir.path(name), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(offset));
    f.write(bytes.data(), std::streamsize(bytes.size()));
    return dir.path(name);
  };
  expect_error(patched("magic.dv", 0, "NOTADV!!"), "wrong magic");
  expect_error(patched("version.dv", 8, std::string("\x02\x00\x00\x00", 4)), "newer");
  expect_error(patched("flip.dv", size / 2, "\xff\xfe"), "checksum");
  fs::copy_file(dir.path("a.dv"), dir.path("cut.dv"));
  fs::resize_file(dir.path("cut.dv"), size - 100);
  expect_error(dir.path("cut.dv"), "truncated");
  std::ofstream(dir.path("text.dv")) << "hello";
  expect_error(dir.path("text.dv"), "wrong magic");
  expect_error(dir.path("missing.dv"), "no such file");
  std::ofstream(dir.path("empty.dv")).close();
  expect_error(dir.path("empty.dv"), "wrong magic");
}

// Files whose checksum was made to match (as a fuzzer or a hostile file can): every count
// and index is checked, so none reaches a reader out of bounds (each of these overflowed
// a heap buffer in preview or export --to gpkg before).
TEST(DvFile, RejectsBadIndicesBehindAValidChecksum) {
  terrain::test::ScratchDir dir;
  const DrainageResult r = logan_drainage();
  write_dv(dir.path("a.dv"), make_dv_header(r.surface, r.net, r.dv_flags, ""), r.surface, r.dirs, r.net);
  std::ifstream in(dir.path("a.dv"), std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint32_t header_bytes = 0;
  std::memcpy(&header_bytes, good.data() + 12, 4);
  const std::size_t n = r.surface.size(), vertices = header_bytes, branches = vertices + 32 * n;
  const std::size_t branch_vertices = branches + 16 * r.net.branches.size();
  ASSERT_EQ(read_dv(dir.path("a.dv")).vertices.size(), n);
  auto patched = [&](std::size_t offset, auto value) {
    std::string bytes = good;
    std::memcpy(bytes.data() + offset, &value, sizeof value);
    const std::uint32_t crc = dv_checksum(bytes.data(), bytes.size());
    std::memcpy(bytes.data() + 16, &crc, 4);
    std::ofstream(dir.path("bad.dv"), std::ios::binary) << bytes;
    return dir.path("bad.dv");
  };
  expect_error(patched(32, std::uint64_t(1) << 63), "corrupt .dv header (grid");   // cols near 2^63
  expect_error(patched(24, std::uint64_t(0)), "corrupt .dv header (grid");         // rows 0
  expect_error(patched(56, std::uint64_t(n + 1)), "corrupt .dv header");           // basins
  expect_error(patched(vertices + 5 * 32 + 24, std::uint32_t(n)), "downstream index of vertex 5");
  expect_error(patched(vertices + 6 * 32 + 20, std::uint32_t(r.net.pits.size())), "basin of vertex 6");
  expect_error(patched(vertices + 7 * 32 + 28, std::uint8_t(7)), "class of vertex 7");
  expect_error(patched(vertices + 8 * 32 + 30, std::uint8_t(10)), "D8 code of vertex 8");
  expect_error(patched(vertices + 9 * 32 + 8, std::numeric_limits<float>::quiet_NaN()), "of vertex 9");
  expect_error(patched(branches + 3 * 16, std::uint32_t(r.net.points)), "vertex range of branch 3");
  expect_error(patched(branches + 4 * 16 + 4, std::uint32_t(0)), "vertex range of branch 4");
  expect_error(patched(branches + 4 * 16 + 8, std::uint32_t(n)), "outlet of branch 4");
  expect_error(patched(branch_vertices + 4 * 11, std::uint32_t(n)), "branch vertex 11");
  // The untouched file still reads: the patching helper itself is right.
  EXPECT_EQ(read_dv(patched(0, 'T')).vertices.size(), n);
}

}  // namespace
}  // namespace drainage
