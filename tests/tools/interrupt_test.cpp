// Runs at once, interrupts and temporary names (issue 41): two tiled runs on one output
// never share a scratch file; SIGINT and SIGTERM at any moment leave the output directory
// as it was (or with the finished output) and nothing else; a killed run's leftovers are
// reported by the next; output names up to the file system's limit work.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <map>
#include <set>
#include <thread>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using terrain::test::Background;
using terrain::test::data;
using terrain::test::file_bytes;
using terrain::test::run;
using terrain::test::tool;

std::set<std::string> entries(const std::string& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
  return out;
}

// Waits (at most `limit_s`) until `dir` holds more than `n` entries; false on time-out.
bool wait_for_entries(const std::string& dir, std::size_t n, double limit_s = 30.0) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  while (entries(dir).size() <= n) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

// Logan's DEM resampled to `m` metres (cubic), made once per resolution for the tests below.
const std::string& logan_at(int m) {
  static terrain::test::ScratchDir dir;
  static std::map<int, std::string> made;
  if (!made.count(m)) {
    const std::string t = dir.path("logan" + std::to_string(m) + ".tif");
    const std::string tr = std::to_string(m) + " " + std::to_string(m);
    EXPECT_EQ(std::system(
                  ("gdalwarp -q -r cubic -tr " + tr + " " + data("logan_utm12n_100m.tif") + " " + t)
                      .c_str()),
              0);
    made[m] = t;
  }
  return made[m];
}
// Logan at 10 m (14.4 M points); at 30 m (1.6 M points: long enough phases to interrupt,
// quick to run).
const std::string& logan10() { return logan_at(10); }
const std::string& logan30() { return logan_at(30); }

// The race: the same tiled command twice on one output, the second started while
// the first is working and interrupted. Before, both used OUT.dv.filled.tmp and
// OUT.dv.d8.tmp (opened with O_TRUNC): the first failed or wrote a wrong database.
TEST(Interrupt, TwoTiledRunsOnOneOutputShareNoScratch) {
  terrain::test::ScratchDir dir;
  const std::string cmd =
      tool("build-drainage") + " --raster " + logan10() + " --fill --tile-size 1000 -q ";
  fs::create_directory(dir.path("d"));
  const std::string d = dir.path("d");
  const auto clean =
      run(cmd + dir.path("d/out.dv"));  // the same command: the same provenance in the header
  ASSERT_EQ(clean.exit_code, 0) << clean.err;
  fs::rename(dir.path("d/out.dv"), dir.path("clean.dv"));
  Background first(cmd + dir.path("d/out.dv"));
  ASSERT_TRUE(wait_for_entries(d, 0)) << "the first run made no scratch";
  const std::size_t before = entries(d).size();
  Background second(cmd + dir.path("d/out.dv"));
  ASSERT_TRUE(wait_for_entries(d, before)) << "the second run made no scratch";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // both work on their scratch
  second.signal(SIGINT);
  EXPECT_EQ(second.wait(), 128 + SIGINT) << second.err();
  ASSERT_EQ(first.wait(), 0) << first.err();
  EXPECT_TRUE(file_bytes(dir.path("d/out.dv")) == file_bytes(dir.path("clean.dv")))
      << "the first run's database differs from a clean run's";
  EXPECT_EQ(entries(d), std::set<std::string>{"out.dv"});
}

// An input named like the old fixed scratch names is read, not truncated.
TEST(Interrupt, AnInputNamedLikeScratchSurvives) {
  terrain::test::ScratchDir dir;
  const std::string in = dir.path("x.dv.d8.tmp");
  fs::copy_file(data("msh_2007_utm10n_10m.tif"), in);
  const std::string bytes = file_bytes(in);
  for (const char* extra : {"", " --fill"}) {
    const auto r = run(tool("build-drainage") + " --raster " + in + " " + dir.path("x.dv") +
                       " --tile-size 16 -q" + extra);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(file_bytes(in) == bytes) << "the input changed";
  }
  EXPECT_EQ(entries(dir.path("")), (std::set<std::string>{"x.dv", "x.dv.d8.tmp"}));
}

// SIGINT and SIGTERM at several moments of each tool's long work: what remains is the old
// output (or the new one, when the run finished first) and nothing else.
TEST(Interrupt, SignalsLeaveNothingBehind) {
  const std::string msh = data("msh_2007_utm10n_10m.tif");
  struct Case {
    std::string what, command, output,
        second = {};  // second: another output written with the first
  };
  terrain::test::ScratchDir mesh_dir;
  ASSERT_EQ(
      run(tool("dem2mesh") + " " + logan10() + " " + mesh_dir.path("l.ply") + " --spacing 20 -q")
          .exit_code,
      0);
  const std::vector<Case> cases = {
      {"dem2mesh",
       tool("dem2mesh") + " " + logan10() + " OUT --spacing 20 --grid-out OUTDIR/g.tif -q", "o.ply",
       "g.tif"},
      {"build-drainage --raster", tool("build-drainage") + " --raster " + logan10() + " OUT -q",
       "o.dv"},
      {"build-drainage tiled",
       tool("build-drainage") + " --raster " + logan10() + " OUT --tile-size 700 --fill -q",
       "o.dv"},
      {"build-drainage mesh", tool("build-drainage") + " " + mesh_dir.path("l.ply") + " OUT -q",
       "o.dv"},
#ifdef TERRAIN_MPIEXEC
      // mpirun sends the ranks SIGTERM, then SIGKILL after odls_base_sigkill_timeout (1 s);
      // 3 s here, so that a rank that a loaded machine schedules late still cleans up.
      {"build-drainage 2 ranks",
       "OMPI_MCA_odls_base_sigkill_timeout=3 " + terrain::test::mpirun(2) + tool("build-drainage") +
           " --raster " + logan10() + " OUT --tile-size 700 --fill -q",
       "o.dv"},
#endif
  };
  int runs = 0;
  for (const Case& c : cases)
    for (const int sig : {SIGINT, SIGTERM})
      for (const int delay_ms : {50, 1200}) {  // while reading and set up, and deep in the work
        terrain::test::ScratchDir dir;
        const std::string out = dir.path(c.output);
        std::ofstream(out) << "old output\n";
        std::string cmd = c.command;
        cmd.replace(cmd.find("OUT"), 3, out);
        if (const auto at = cmd.find("OUTDIR/"); at != std::string::npos)
          cmd.replace(at, 7, dir.path(""));
        Background b(cmd);
        std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
        b.signal(sig);
        const int code = b.wait();
        const std::string what =
            c.what + ", signal " + std::to_string(sig) + " at " + std::to_string(delay_ms) + " ms";
        ++runs;
        // The output is the old one, or the new one complete (the run finished its renames
        // before the signal came: terrain-inspect reads it), and nothing else is left.
        const bool replaced = file_bytes(out) != "old output\n";
        if (replaced) {
          EXPECT_EQ(run(tool("terrain-inspect") + " info " + out).exit_code, 0) << what;
        }
        EXPECT_TRUE(code == 0 || code == 128 + sig ||
                    (c.what.find("ranks") != std::string::npos && code != 0))
            << what << ": exit " << code << "\n"
            << b.err();
        if (code == 0) {
          EXPECT_TRUE(replaced) << what;
        }
        std::set<std::string> expected{c.output};
        if (!c.second.empty() && replaced)
          expected.insert(c.second);  // the outputs land together or not at all
        // mpirun's ranks end (and clean up) after it: up to 10 s for the folder to settle.
        for (int k = 0; k < 200 && entries(dir.path("")) != expected; ++k)
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        EXPECT_EQ(entries(dir.path("")), expected) << what << ": exit " << code;
      }
  EXPECT_GT(runs, 0);
}

// Issue 48: a tiled run with --rasters interrupted in its raster phase had already replaced
// the .dv while the folder still held the previous run's rasters. Now the .dv is staged
// and lands with them: interrupted there, every output is the old one.
TEST(Interrupt, TiledRunReplacesItsDvAndRastersTogether) {
  terrain::test::ScratchDir dir;
  const std::string out = dir.path("o.dv"), rasters = dir.path("r");
  fs::create_directories(rasters);
  const std::string cmd = tool("build-drainage") + " --raster " + logan30() + " " + out +
                          " --tile-size 400 --fill -q --rasters " + rasters;
  for (const int sig : {SIGINT, SIGHUP}) {
    std::ofstream(out) << "old output\n";
    for (const auto& e : fs::directory_iterator(rasters)) fs::remove(e.path());
    for (const char* n : {"surface.tif", "d8.tif", "accumulation.tif"})
      std::ofstream(rasters + "/" + n) << "old raster\n";
    Background b(cmd);
    // The raster phase: a staged raster appears beside the old ones.
    ASSERT_TRUE(wait_for_entries(rasters, 3, 120)) << "no raster was staged";
    b.signal(sig);
    EXPECT_EQ(b.wait(), 128 + sig) << b.err();
    EXPECT_EQ(file_bytes(out), "old output\n")
        << "signal " << sig << ": the .dv was replaced without its rasters";
    EXPECT_EQ(entries(rasters),
              (std::set<std::string>{"accumulation.tif", "d8.tif", "surface.tif"}))
        << sig;
    EXPECT_EQ(file_bytes(rasters + "/d8.tif"), "old raster\n") << sig;
    EXPECT_EQ(entries(dir.path("")), (std::set<std::string>{"o.dv", "r"})) << sig;
  }
  const auto r = run(cmd);  // uninterrupted: all of them new
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(run(tool("terrain-inspect") + " info " + out).exit_code, 0);
  EXPECT_NE(file_bytes(rasters + "/d8.tif"), "old raster\n");
}

// Issue 48: SIGINT, SIGTERM or SIGHUP while a GeoPackage is written (terrain-inspect export
// --to gpkg, build-drainage --outlets) left SQLite's '-journal' file beside the output.
TEST(Interrupt, GeoPackageWritersLeaveNoJournal) {
  terrain::test::ScratchDir src;
  const std::string dv = src.path("l.dv");  // Logan at 100 m: its GeoPackage takes about a second
  ASSERT_EQ(run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + dv +
                " --fill -q")
                .exit_code,
            0);
  std::ofstream(src.path("outlet.csv")) << "x,y\n447000,4637000\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"export --to gpkg",
       tool("terrain-inspect") + " export " + dv + " --to gpkg -o OUTDIR/e.gpkg -q"},
      {"--outlets", tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") +
                        " OUTDIR/w.dv --fill --outlets " + src.path("outlet.csv") + " -q"},
  };
  for (const auto& [what, command] : cases)
    for (const int sig : {SIGINT, SIGTERM, SIGHUP})
      for (const int delay_ms : {0, 30}) {
        terrain::test::ScratchDir dir;
        std::string cmd = command;
        cmd.replace(cmd.find("OUTDIR/"), 7, dir.path(""));
        Background b(cmd);
        // Until SQLite's journal (or the temporary GeoPackage) exists, then the signal.
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        bool writing = false;
        while (!writing && std::chrono::steady_clock::now() < until) {
          for (const std::string& n : entries(dir.path("")))
            writing = writing || n.find(".gpkg") != std::string::npos;
          if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        ASSERT_TRUE(writing) << what << ": no GeoPackage was written";
        std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
        b.signal(sig);
        const int code = b.wait();
        const std::string label =
            what + ", signal " + std::to_string(sig) + " after " + std::to_string(delay_ms) + " ms";
        EXPECT_TRUE(code == 0 || code == 128 + sig) << label << ": exit " << code << "\n"
                                                    << b.err();
        for (const std::string& n : entries(dir.path("")))
          EXPECT_NE(n[0], '.') << label << ": left " << n;
      }
}

// What a run killed by SIGKILL leaves (its temporary output, its scratch folder) is
// reported by the next run on the same output.
TEST(Interrupt, ALaterRunReportsWhatAKilledRunLeft) {
  terrain::test::ScratchDir dir;
  const std::string out = dir.path("o.dv");
  Background b(tool("build-drainage") + " --raster " + logan10() + " " + out +
               " --tile-size 700 --fill -q");
  ASSERT_TRUE(wait_for_entries(dir.path(""), 0));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  b.signal(SIGKILL);
  EXPECT_EQ(b.wait(), 128 + SIGKILL);
  const std::set<std::string> left = entries(dir.path(""));
  ASSERT_FALSE(left.empty()) << "SIGKILL cannot be caught: its scratch stays";
  const auto r =
      run(tool("build-drainage") + " --raster " + data("msh_2007_utm10n_10m.tif") + " " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string& name : left) {
    EXPECT_NE(r.err.find("stale temporary '" + dir.path(name) + "'"), std::string::npos)
        << name << "\n"
        << r.err;
  }
}

// Output names up to 255 bytes (the file system's limit): the temporary names fit too.
TEST(Interrupt, LongOutputNamesWork) {
  terrain::test::ScratchDir dir;
  const std::string msh = data("msh_2007_utm10n_10m.tif");
  for (const std::size_t length : {238u, 239u, 255u}) {
    const std::string stem(length - 4, 'a');
    const std::string ply = dir.path(stem + ".ply"),
                      dv = dir.path(stem.substr(0, length - 3) + ".dv");
    auto r = run(tool("dem2mesh") + " " + msh + " " + ply + " --spacing 50 --grid-out " +
                 dir.path(stem + ".tif") + " -q");
    EXPECT_EQ(r.exit_code, 0) << length << ": " << r.err;
    r = run(tool("build-drainage") + " --raster " + msh + " " + dv + " --tile-size 64 --fill -q");
    EXPECT_EQ(r.exit_code, 0) << length << ": " << r.err;
    r = run(tool("build-drainage") + " " + ply + " " + dv + " --surface " +
            dir.path(stem + ".tif") + " -q");
    EXPECT_EQ(r.exit_code, 0) << length << ": " << r.err;
    for (const auto& name : entries(dir.path(""))) EXPECT_NE(name[0], '.') << "left: " << name;
    fs::remove_all(dir.path(""));
    fs::create_directories(dir.path(""));
  }
}

// The crash: dem2mesh on scattered points with --fill-nodata died by SIGSEGV in
// about 8 % of runs (an unterminated DATAPOINTER string). 50 runs, each interpolant; the
// sanitizer script runs the same command under Valgrind's memcheck.
TEST(Interrupt, ScatteredPointsWithFillNodataNeverCrash) {
  terrain::test::ScratchDir dir;
  const char* interpolants[] = {"natural", "linear", "natural-c0"};
  std::string first;
  for (int i = 0; i < 50; ++i) {
    const auto r = run("cd " + dir.path("") + " && " + (i % 2 ? "OMP_NUM_THREADS=1 " : "") +
                       tool("dem2mesh") + " " + data("scattered_60_utm10n.xyz") +
                       " o.ply --spacing 5 --src-crs EPSG:32610 --fill-nodata -q " +
                       "--interpolation " + interpolants[i % 3]);
    ASSERT_EQ(r.exit_code, 0) << "run " << i << ": " << r.err;
    if (i == 0) first = file_bytes(dir.path("o.ply"));
    if (i % 6 == 0) {
      EXPECT_TRUE(file_bytes(dir.path("o.ply")) == first) << "run " << i << " differs";
    }
  }
  EXPECT_EQ(entries(dir.path("")), std::set<std::string>{"o.ply"})
      << "GDAL's fill work files left in the working directory";
}

}  // namespace
