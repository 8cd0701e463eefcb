// End-to-end: every output of every tool under a file-size limit (ulimit -f 8 in sh: 4 KiB, so
// the stderr line fits and no output does). Each run must exit 1 with one line on stderr
// naming the output, and leave nothing in the output directory: no truncated file, no
// temporary file, and none of the other outputs of the same run. Device targets
// (/dev/null, /dev/full) are refused.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.hpp"

namespace {

using terrain::test::data;
using terrain::test::run;
using terrain::test::tool;

std::size_t lines(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n'));
}

// Inputs made once for all cases: a 50 m MSH mesh, its drainage, its denoised copy and a
// 3-frame list.
class FailedWrite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    in_ = new terrain::test::ScratchDir;
    const std::string mesh = in_->path("m.ply");
    const auto a = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                       " --spacing 50 -q");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const auto b =
        run(tool("build-drainage") + " " + mesh + " " + in_->path("m.dv") + " --spacing 25 -q");
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const auto c =
        run(tool("denoise-normals") + " " + mesh + " " + in_->path("d.ply") + " --iterations 0 -q");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    const auto d = run(tool("terrain-render") +
                       " path --from 561500 5114000 2800 --to 563500 5116000 2700 "
                       "--frames 3 -o " +
                       in_->path("f.csv"));
    ASSERT_EQ(d.exit_code, 0) << d.err;
  }
  static void TearDownTestSuite() { delete in_; }
  static std::string input(const std::string& name) { return in_->path(name); }

  // Runs `args` (OUT stands for the output directory) under ulimit -f 8.
  void expect_clean_failure(const std::string& args) {
    terrain::test::ScratchDir out;
    std::string cmd = args;
    for (std::size_t at; (at = cmd.find("OUT/")) != std::string::npos;)
      cmd.replace(at, 4, out.path(""));
    const auto r = run("ulimit -f 8; exec " + cmd);  // 4 KiB: libomp needs 1 KiB in /dev/shm
    EXPECT_EQ(r.exit_code, 1) << cmd << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1u) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("cannot write '" + out.path("")), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos)
        << "the message names a temporary file: " << r.err;
    std::string left;
    for (const auto& e : std::filesystem::directory_iterator(out.path("")))
      left += e.path().filename().string() + " ";
    EXPECT_EQ(left, "") << cmd;
  }

  static terrain::test::ScratchDir* in_;
};
terrain::test::ScratchDir* FailedWrite::in_ = nullptr;

TEST_F(FailedWrite, Dem2mesh) {
  const std::string dem = data("msh_2007_utm10n_10m.tif");
  expect_clean_failure(tool("dem2mesh") + " " + dem + " OUT/m.ply --spacing 50 -q");
  expect_clean_failure(tool("dem2mesh") + " " + dem +
                       " OUT/m.ply --spacing 50 --grid-out OUT/g.tif -q");
}

TEST_F(FailedWrite, BuildDrainage) {
  expect_clean_failure(tool("build-drainage") + " " + input("m.ply") + " OUT/m.dv --spacing 25 -q");
  expect_clean_failure(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") +
                       " OUT/l.dv --rasters OUT/ --surface OUT/s.tif -q");
}

TEST_F(FailedWrite, DenoiseNormals) {
  expect_clean_failure(tool("denoise-normals") + " " + input("m.ply") + " OUT/d.ply -q");
}

TEST_F(FailedWrite, TerrainInspect) {
  const std::string ti = tool("terrain-inspect");
  expect_clean_failure(ti + " preview " + data("msh_2007_utm10n_10m.tif") + " -o OUT/p.png");
  expect_clean_failure(ti + " preview " + input("m.ply") + " -o OUT/p.png");
  expect_clean_failure(ti + " preview " + input("m.dv") + " -o OUT/p.png");
  expect_clean_failure(ti + " export " + input("m.ply") + " --to obj -o OUT/m.obj");
  expect_clean_failure(ti + " export " + input("m.ply") + " --to tif -o OUT/m.tif");
  expect_clean_failure(ti + " export " + input("m.dv") + " --to gpkg -o OUT/m.gpkg");
}

TEST_F(FailedWrite, TerrainRender) {
  const std::string tr = tool("terrain-render");
  expect_clean_failure(tr + " path --from 0 0 100 --to 1000 1000 100 --frames 200 -o OUT/p.csv");
  expect_clean_failure(tr + " frame " + input("m.ply") + " " + input("m.dv") +
                       " -o OUT/f.png --size 320x240 --layers shaded,creases -q");
  expect_clean_failure(tr + " batch " + input("m.ply") + " " + input("m.dv") + " " +
                       input("f.csv") + " -o OUT/ --size 320x240 --layers shaded,creases -q");
}

// A device given as the output is refused before any work, and the device stays.
TEST(OutputPaths, DevicesAreRefused) {
  for (const std::string dev : {"/dev/null", "/dev/full"}) {
    const auto r = run(tool("terrain-render") +
                       " path --from 0 0 100 --to 1000 1000 100 --frames 5 -o " + dev);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    EXPECT_TRUE(std::filesystem::is_character_file(dev));
  }
}

}  // namespace
