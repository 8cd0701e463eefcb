// Every input that crashed, hung or exhausted memory in a fuzz harness (scripts/fuzz.sh)
// is kept in tests/fuzz/regressions/<harness>/ and read here by the same reader: each
// must give a terrain::Error (or read), never another exception, a crash or a sanitizer
// report (CI runs this under ASan + UBSan too). The seed corpora must read.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "drainage/rasters.hpp"
#include "mesh_target.hpp"
#include "points_target.hpp"
#include "pyramid_target.hpp"
#include "renderer/core/frames.hpp"
#include "terrain/error.hpp"
#include "terrain/mesh_io.hpp"

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> files(const std::string& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(std::string(TERRAIN_FUZZ_DIR) + "/" + dir))
    out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Runs `read` on every file of regressions/NAME; returns how many read without an Error.
template <class Read>
std::size_t read_all(const std::string& name, Read read) {
  std::size_t ok = 0;
  for (const fs::path& p : files("regressions/" + name)) {
    try {
      read(p.string());
      ++ok;
    } catch (const terrain::Error&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << p << ": not a terrain::Error: " << e.what();
    }
  }
  return ok;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(FuzzRegressions, MeshReader) {
  read_all("ply", [](const std::string& p) { terrain::fuzz::mesh_target(p); });
  for (const fs::path& p : files("corpus/ply"))
    EXPECT_NO_THROW(terrain::fuzz::mesh_target(p.string())) << p;
}

// The crafted pyramids of the probe (regressions/pyramid/README) and what the
// fuzzer found: each refused with a terrain::Error, never a crash or a huge allocation.
TEST(FuzzRegressions, PyramidReader) {
  const fs::path scratch =
      fs::temp_directory_path() / ("fuzz_regression_" + std::to_string(::getpid()) + ".tpyr");
  // The crafted cases (make_pyramid_regressions.py), each with the check that refuses it.
  const std::vector<std::pair<std::string, std::string>> crafted = {
      {"block_levels_max", "corrupt mesh pyramid (a block's levels)"},
      {"levels_max", "corrupt mesh pyramid (its levels)"},
      {"tiny_blocks_big_grid", "truncated mesh pyramid"},
      {"origin_inf", "corrupt mesh pyramid (its georeference)"},
      {"box_zero", "are not in its block's box"},
      {"error_nan", "corrupt mesh pyramid (a block's errors)"},
      {"wkt_huge", "truncated mesh pyramid"},
      {"version_0", "corrupt mesh pyramid (version 0)"},
      {"version_99", "mesh pyramid version 99 is newer than this tool's (4)"},
      {"header_past_end", "truncated mesh pyramid"},
      {"truncated", "truncated mesh pyramid"},
  };
  for (const auto& [name, why] : crafted) {
    const std::string p =
        std::string(TERRAIN_FUZZ_DIR) + "/regressions/pyramid/crafted_" + name + ".tpyr";
    try {
      terrain::fuzz::pyramid_target(slurp(p), scratch.string());
      ADD_FAILURE() << name << ": read";
    } catch (const terrain::Error& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << name << ": " << e.what();
    }
  }
  EXPECT_EQ(read_all("pyramid",
                     [&](const std::string& p) {
                       terrain::fuzz::pyramid_target(slurp(p), scratch.string());
                     }),
            0u);
  for (const fs::path& p : files("corpus/pyramid"))
    EXPECT_NO_THROW(terrain::fuzz::pyramid_target(slurp(p.string()), scratch.string())) << p;
  fs::remove(scratch);
}

TEST(FuzzRegressions, DvReader) {
  // As the harness does: every checksum made to match first, then the reads it makes.
  const fs::path fixed =
      fs::temp_directory_path() / ("fuzz_regression_" + std::to_string(::getpid()) + ".dv");
  read_all("dv", [&](const std::string& p) {
    std::string bytes = slurp(p);
    drainage::dv_fix_checksums(bytes.data(), bytes.size());
    std::ofstream(fixed, std::ios::binary) << bytes;
    const drainage::DrainageDb db = drainage::read_dv(fixed.string());
    (void)drainage::summarize(db);
    (void)drainage::dv_preview(db);
    (void)drainage::read_dv_window(fixed.string(), db.header.rows / 3, db.header.cols / 4, 7, 5);
  });
  fs::remove(fixed);
  for (const fs::path& p : files("corpus/dv"))
    EXPECT_NO_THROW((void)drainage::read_dv(p.string())) << p;
}

TEST(FuzzRegressions, FrameListParser) {
  read_all("frames",
           [](const std::string& p) { (void)renderer::parse_frames_csv(slurp(p), {}, p); });
  for (const fs::path& p : files("corpus/frames"))
    EXPECT_NO_THROW((void)renderer::parse_frames_csv(slurp(p.string()), {}, p.string())) << p;
}

TEST(FuzzRegressions, D8RasterReader) {
  read_all("d8", [](const std::string& p) {
    terrain::Grid g;
    (void)drainage::read_d8_raster(p, drainage::D8Encoding::Taudem, g);
  });
  terrain::Grid g;
  EXPECT_NO_THROW((void)drainage::read_d8_raster(files("corpus/d8")[0].string(),
                                                 drainage::D8Encoding::Taudem, g));
}

TEST(FuzzRegressions, PointReader) {
  const auto run = [](const std::string& p) {
    const std::string bytes = slurp(p);
    terrain::fuzz::points_target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  };
  read_all("points", run);
  for (const fs::path& p : files("corpus/points")) EXPECT_NO_THROW(run(p.string())) << p;
}

}  // namespace
