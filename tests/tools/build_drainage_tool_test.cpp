// End-to-end: build-drainage and terrain-inspect on .dv files.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gdal_priv.h>

#include "drainage/dv_file.hpp"
#include "drainage/rasters.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

using terrain::test::data;
using terrain::test::file_bytes;
using terrain::test::run;
using terrain::test::tool;

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

TEST(BuildDrainage, MeshPipelineIsDeterministicAcrossThreadCounts) {
  terrain::test::ScratchDir dir;
  const auto m = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + dir.path("m.ply") + " --spacing 50 -q");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const auto a = run(tool("build-drainage") + " " + dir.path("m.ply") + " " + dir.path("a.dv") + " --threads 1 -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  // Same command line as far as the output is concerned: the same file name.
  std::filesystem::rename(dir.path("a.dv"), dir.path("first.dv"));
  const auto b = run(tool("build-drainage") + " " + dir.path("m.ply") + " " + dir.path("a.dv") + " --threads 2 -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_TRUE(file_bytes(dir.path("first.dv")) == file_bytes(dir.path("a.dv"))) << "the .dv differs between 1 and 2 threads";
  EXPECT_NE(a.out.find("points: 131236\n"), std::string::npos) << a.out;  // 301 x 436 samples at 10 m

  const auto i = run(tool("terrain-inspect") + " info " + dir.path("a.dv"));
  ASSERT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("points: 131236\n"), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("source: PN surface of a mesh"), std::string::npos);
  const auto p = run(tool("terrain-inspect") + " preview " + dir.path("a.dv") + " -o " + dir.path("a.png"));
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_TRUE(std::filesystem::exists(dir.path("a.png")));
  const auto g = run(tool("terrain-inspect") + " export " + dir.path("a.dv") + " --to gpkg --min-order 2");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_TRUE(std::filesystem::exists(dir.path("a.gpkg")));
}

// --rasters writes every layer; feeding its d8.tif back through --d8-input reproduces the
// accumulation (the encodings round-trip), in both encodings.
TEST(BuildDrainage, RastersAndD8InputRoundTrip) {
  terrain::test::ScratchDir dir;
  std::filesystem::create_directory(dir.path("r"));
  for (const std::string enc : {"taudem", "esri"}) {
    const auto a = run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + dir.path("a.dv") +
                       " --rasters " + dir.path("r") + " --d8-encoding " + enc + " -q");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    for (const char* f : {"surface", "d8", "accumulation", "normalized_flow", "basin", "class", "order"})
      EXPECT_TRUE(std::filesystem::exists(dir.path(std::string("r/") + f + ".tif"))) << f;
    const auto b = run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " --d8-input " +
                       dir.path("r/d8.tif") + " --d8-encoding " + enc + " " + dir.path("b.dv") + " -q");
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const DrainageDb da = read_dv(dir.path("a.dv")), db = read_dv(dir.path("b.dv"));
    ASSERT_EQ(da.vertices.size(), db.vertices.size());
    for (std::size_t i = 0; i < da.vertices.size(); ++i) {
      ASSERT_EQ(da.vertices[i].accumulated, db.vertices[i].accumulated) << enc << " " << i;
      ASSERT_EQ(da.vertices[i].basin, db.vertices[i].basin);
    }
    const terrain::Grid acc = terrain::read_dem(dir.path("r/accumulation.tif"));
    for (std::size_t i = 0; i < acc.size(); ++i) ASSERT_EQ(double(acc.z[i]), double(da.vertices[i].accumulated));
  }
}

// Every field of two databases, stored and derived (branches included).
void expect_same_db(const DrainageDb& a, const DrainageDb& b, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  EXPECT_EQ(a.header.valid, b.header.valid);
  EXPECT_EQ(a.header.basins, b.header.basins);
  EXPECT_EQ(a.header.flags, b.header.flags);
  EXPECT_DOUBLE_EQ(a.header.origin_x, b.header.origin_x);
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    const DvVertex &u = a.vertices[i], &v = b.vertices[i];
    ASSERT_TRUE(u.z == v.z && u.accumulated == v.accumulated && u.normalized == v.normalized && u.basin == v.basin &&
                u.downstream == v.downstream && u.point_class == v.point_class && u.order == v.order && u.d8 == v.d8)
        << "vertex " << i;
  }
  ASSERT_EQ(a.branches.size(), b.branches.size());
  for (std::size_t k = 0; k < a.branches.size(); ++k)
    ASSERT_TRUE(a.branches[k].first == b.branches[k].first && a.branches[k].count == b.branches[k].count &&
                a.branches[k].drains_into == b.branches[k].drains_into && a.branches[k].order == b.branches[k].order)
        << "branch " << k;
  EXPECT_TRUE(std::equal(a.branch_vertices.begin(), a.branch_vertices.end(), b.branch_vertices.begin()));
}

// --tile-size gives the untiled run's database exactly (every field), with tile sizes that
// do and do not divide the grid, filled or not, from a DEM or from D8 codes.
TEST(BuildDrainage, TiledRunsEqualTheUntiledRun) {
  terrain::test::ScratchDir dir;
  const std::string bd = tool("build-drainage") + " ";
  // MSH and MED (projected), the Eno crop (geographic: per-row metric cells in every window).
  for (const char* name : {"msh_2007_utm10n_10m.tif", "med_01_01_10m.tif", "eno_nad83_geographic_crop.tif"}) {
    for (const std::string opts : {"", " --fill", " --keep-flats", " --keep-flats --fill"}) {
      const auto u = run(bd + "--raster " + data(name) + " " + dir.path("u.dv") + opts + " -q");
      ASSERT_EQ(u.exit_code, 0) << u.err;
      const DrainageDb whole = read_dv(dir.path("u.dv"));
      for (const int side : {100, 128, 457}) {
        const auto t = run(bd + "--raster " + data(name) + " " + dir.path("t.dv") + opts + " --tile-size " +
                           std::to_string(side) + " -q");
        ASSERT_EQ(t.exit_code, 0) << t.err;
        expect_same_db(whole, read_dv(dir.path("t.dv")), std::string(name) + opts + " tiles " + std::to_string(side));
        EXPECT_EQ(read_dv_header(dir.path("t.dv")).block_rows, std::uint32_t(side));
      }
    }
  }
  // From D8 codes: the d8.tif of an untiled run, accumulated in tiles.
  std::filesystem::create_directory(dir.path("r"));
  const auto a = run(bd + "--raster " + data("logan_utm12n_100m.tif") + " " + dir.path("a.dv") + " --rasters " +
                     dir.path("r") + " -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run(bd + "--d8-input " + dir.path("r/d8.tif") + " " + dir.path("b.dv") + " -q");
  const auto c = run(bd + "--d8-input " + dir.path("r/d8.tif") + " " + dir.path("c.dv") + " --tile-size 77 -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  ASSERT_EQ(c.exit_code, 0) << c.err;
  expect_same_db(read_dv(dir.path("b.dv")), read_dv(dir.path("c.dv")), "d8 input");
  // Not in mesh mode; nothing left behind (temporary rasters included).
  const auto f = run(bd + data("logan_utm12n_100m.tif") + " " + dir.path("f.dv") + " --tile-size 100 -q");
  EXPECT_EQ(f.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.path("f.dv")));
  for (const auto& e : std::filesystem::directory_iterator(dir.path("")))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

// Logan at 10 m (gdalwarp -r cubic of the bundled 100 m DEM; 2890 x 4980 = 14.4 M points),
// filled: Cache Valley's filled floor is one flat across many tiles. Tiles of 1000 (do not
// divide the grid) and 1245 (divide its rows) give the untiled database in every field.
TEST(BuildDrainage, TiledLogan10mEqualsTheUntiledRun) {
  terrain::test::ScratchDir dir;
  const std::string tif = dir.path("logan10.tif");
  ASSERT_EQ(std::system(("gdalwarp -q -r cubic -tr 10 10 " + data("logan_utm12n_100m.tif") + " " + tif).c_str()), 0);
  const std::string bd = tool("build-drainage") + " --raster " + tif + " --fill ";
  const auto u = run(bd + dir.path("u.dv") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  const DrainageDb whole = read_dv(dir.path("u.dv"));
  for (const int side : {1000, 1245}) {
    const auto t = run(bd + dir.path("t.dv") + " --tile-size " + std::to_string(side) + " -q");
    ASSERT_EQ(t.exit_code, 0) << t.err;
    expect_same_db(whole, read_dv(dir.path("t.dv")), "logan 10 m, tiles " + std::to_string(side));
  }
}

// A plane sloping west (1 m per column, 10 m samples) with a terrace (a flat that drains
// over its west edge) and a square depression (flat once filled), each across the corner of
// four 16 x 16 tiles, the depression with its outlet three tiles away.
terrain::Grid terrace_and_depression() {
  terrain::Georef geo = terrain::read_dem_info(data("logan_utm12n_100m.tif")).geo;
  geo.dx = geo.dy = 10.0;
  terrain::Grid g(80, 80, geo);
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c) {
      float z = 10.0f + float(c);
      if (r >= 8 && r < 24 && c >= 9 && c < 24) z = 19.0f;     // terrace over tiles (0,0) (0,1) (1,0) (1,1)
      if (r >= 40 && r < 56 && c >= 56 && c < 72) z = 20.0f;   // depression over tiles (2,3) (2,4) (3,3) (3,4)
      g.at(r, c) = z;
    }
  return g;
}

// The flat and the depression across four tiles: tiled runs (tiles of 16 and 13) equal
// the untiled run in every field, filled or not.
TEST(BuildDrainage, TiledFlatAndDepressionAcrossFourTiles) {
  terrain::test::ScratchDir dir;
  terrain::write_geotiff(terrace_and_depression(), dir.path("t.tif"));
  const std::string bd = tool("build-drainage") + " --raster " + dir.path("t.tif") + " ";
  for (const std::string opts : {"", " --fill"}) {
    const auto u = run(bd + dir.path("u.dv") + opts + " -q");
    ASSERT_EQ(u.exit_code, 0) << u.err;
    const DrainageDb whole = read_dv(dir.path("u.dv"));
    // The terrace's 15 x 16 cells are one flat that drains west: no pit on it.
    for (std::size_t r = 8; r < 24; ++r)
      for (std::size_t c = 9; c < 24; ++c) ASSERT_NE(whole.vertices[r * 80 + c].downstream, kNone) << r << " " << c;
    // Filled, the depression drains too: every basin is one whose pit is on the west edge.
    if (!opts.empty()) {
      for (const DvVertex& v : whole.vertices) {
        if (v.downstream == kNone) {
          ASSERT_LT(v.x, whole.vertices[1].x);
        }
      }
    }
    for (const int side : {16, 13}) {
      const auto t = run(bd + dir.path("t.dv") + opts + " --tile-size " + std::to_string(side) + " -q");
      ASSERT_EQ(t.exit_code, 0) << t.err;
      expect_same_db(whole, read_dv(dir.path("t.dv")), "terrace" + opts + " tiles " + std::to_string(side));
    }
  }
}

// Band 1 of a GeoTIFF as doubles (exact for every type written here), with its geotransform
// and no-data value.
struct Band {
  std::vector<double> v;
  std::array<double, 6> gt{};
  double nodata = 0;
};
Band band_of(const std::string& path) {
  terrain::ensure_gdal();
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  EXPECT_TRUE(ds) << path;
  Band b;
  if (!ds) return b;
  const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
  b.v.resize(std::size_t(w) * std::size_t(h));
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w, h, b.v.data(), w, h, GDT_Float64, 0, 0), CE_None);
  ds->GetGeoTransform(b.gt.data());
  b.nodata = ds->GetRasterBand(1)->GetNoDataValue();
  return b;
}

// Every layer of directory `a` equals `b`'s: values, geotransform (to 1e-9 of a cell) and
// no-data value.
void expect_same_rasters(const std::string& a, const std::string& b, const std::string& what) {
  for (const char* name : kDrainageRasterNames) {
    SCOPED_TRACE(what + ": " + name);
    const Band x = band_of(a + "/" + name), y = band_of(b + "/" + name);
    ASSERT_EQ(x.v.size(), y.v.size());
    EXPECT_GT(x.v.size(), 0u);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < x.v.size(); ++i) differ += x.v[i] != y.v[i];
    EXPECT_EQ(differ, 0u);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(x.gt[std::size_t(k)], y.gt[std::size_t(k)], 1e-9 * std::abs(x.gt[1])) << k;
    EXPECT_EQ(x.nodata, y.nodata);
  }
}

// Issue 39: every layer out of any .dv and out of tiled runs. terrain-inspect export X.dv --to
// tif writes, window by window, the layers --rasters writes for the run that made X (the
// Logan DEM, filled: 498 rows, so two windows of 256; .dv versions 2 and 1); a tiled run's
// --rasters (tiles of 100 and of 77) are the untiled run's; and a tiled run from TauDEM's
// D8 directions of Logan 30 m writes the accumulation TauDEM's aread8 computed, on each of
// its 1,587,804 cells.
TEST(BuildDrainage, EveryLayerOutOfAnyDvAndOfTiledRuns) {
  terrain::test::ScratchDir dir;
  for (const char* d : {"u", "t100", "t77", "x2", "x1", "taudem"}) std::filesystem::create_directory(dir.path(d));
  const std::string bd = tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " --fill ";
  const auto u = run(bd + dir.path("u.dv") + " --rasters " + dir.path("u") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  const auto v1 = run(bd + dir.path("v1.dv") + " --dv-version 1 -q");
  ASSERT_EQ(v1.exit_code, 0) << v1.err;
  for (const std::string side : {"100", "77"}) {
    const auto t = run(bd + dir.path("t.dv") + " --tile-size " + side + " --rasters " + dir.path("t" + side) + " -q");
    ASSERT_EQ(t.exit_code, 0) << t.err;
    expect_same_rasters(dir.path("u"), dir.path("t" + side), "tiles of " + side);
  }
  for (const std::string version : {"2", "1"}) {
    const std::string dv = dir.path(version == "2" ? "u.dv" : "v1.dv"), out = dir.path("x" + version);
    const auto e = run(tool("terrain-inspect") + " export " + dv + " --to tif -o " + out);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    EXPECT_NE(e.out.find("points: 143922"), std::string::npos) << e.out;
    expect_same_rasters(dir.path("u"), out, "export of version " + version);
  }
  // A file where the directory should be: one line, nothing written.
  std::ofstream(dir.path("file")) << "x";
  const auto bad = run(tool("terrain-inspect") + " export " + dir.path("u.dv") + " --to tif -o " + dir.path("file"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("is not a directory"), std::string::npos) << bad.err;

  const auto a = run(tool("build-drainage") + " --d8-input " + data("logan_30m_taudem_d8dir.tif") + " " +
                     dir.path("a.dv") + " --tile-size 300 --rasters " + dir.path("taudem") + " -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const Band acc = band_of(dir.path("taudem/accumulation.tif")),
             ref = band_of(data("logan_30m_taudem_aread8.tif"));
  ASSERT_EQ(acc.v.size(), ref.v.size());
  std::size_t compared = 0, equal = 0;
  for (std::size_t i = 0; i < ref.v.size(); ++i) {
    if (ref.v[i] == ref.nodata || std::isnan(ref.v[i])) continue;
    ++compared;
    equal += acc.v[i] == ref.v[i];
  }
  EXPECT_EQ(compared, 1587804u);
  EXPECT_EQ(equal, compared);
}

#ifdef TERRAIN_MPIEXEC
using terrain::test::mpirun;

// Skips the test where this machine cannot start 3 ranks at all (a launcher problem, not ours).
#define SKIP_WITHOUT_MPI_LAUNCH()                                                         \
  do {                                                                                    \
    const auto probe = run(mpirun(3) + "true");                                          \
    if (probe.exit_code != 0) GTEST_SKIP() << "mpirun cannot start 3 ranks here: " << probe.err; \
  } while (0)

// The tiled run on 1 and 3 MPI ranks equals the untiled run in every field, and the
// single-process tiled run byte for byte (the same command line, so the same header):
// MSH, MED, the geographic Eno crop, the terrace and depression across four tiles, tiles
// that do and do not divide the grid, filled or not, and from D8 codes.
TEST(BuildDrainage, MpiRanksEqualTheSingleProcessRun) {
  SKIP_WITHOUT_MPI_LAUNCH();
  terrain::test::ScratchDir dir;
  terrain::write_geotiff(terrace_and_depression(), dir.path("terrace.tif"));
  const std::string bd = tool("build-drainage") + " ";
  auto check = [&](const std::string& input, const std::string& opts, int side) {
    SCOPED_TRACE(input + opts + " tiles " + std::to_string(side));
    const auto u = run(bd + input + " " + dir.path("u.dv") + opts + " -q");
    ASSERT_EQ(u.exit_code, 0) << u.err;
    const std::string tiled = input + " " + dir.path("t.dv") + opts + " --tile-size " + std::to_string(side) + " -q";
    const auto s = run(bd + tiled);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const std::string single = file_bytes(dir.path("t.dv"));
    for (const int ranks : {1, 3}) {
      std::filesystem::remove(dir.path("t.dv"));
      const auto m = run(mpirun(ranks) + bd + tiled);
      ASSERT_EQ(m.exit_code, 0) << m.err;
      EXPECT_EQ(m.out, s.out) << ranks << " ranks";
      expect_same_db(read_dv(dir.path("u.dv")), read_dv(dir.path("t.dv")), std::to_string(ranks) + " ranks");
      EXPECT_TRUE(file_bytes(dir.path("t.dv")) == single) << ranks << " ranks: not the single-process file";
    }
  };
  for (const char* name : {"msh_2007_utm10n_10m.tif", "med_01_01_10m.tif", "eno_nad83_geographic_crop.tif"})
    for (const std::string opts : {"", " --fill"})
      for (const int side : {64, 100}) check("--raster " + data(name), opts, side);
  check("--raster " + dir.path("terrace.tif"), " --fill", 16);
  check("--raster " + dir.path("terrace.tif"), "", 13);
  // From D8 codes.
  std::filesystem::create_directory(dir.path("r"));
  const auto a = run(bd + "--raster " + data("logan_utm12n_100m.tif") + " " + dir.path("a.dv") + " --rasters " +
                     dir.path("r") + " -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  check("--d8-input " + dir.path("r/d8.tif"), "", 77);
  // Nothing left behind: no scratch array, no rank's block file.
  for (const auto& e : std::filesystem::directory_iterator(dir.path("")))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  // Mesh mode does not run on several ranks: a clear error, every rank ended.
  const auto mesh = run(mpirun(3) + bd + data("logan_utm12n_100m.tif") + " " + dir.path("f.dv") + " -q");
  EXPECT_NE(mesh.exit_code, 0);
  EXPECT_NE(mesh.err.find("mesh mode runs on one process"), std::string::npos) << mesh.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("f.dv")));
}

// Logan at 10 m on 3 ranks (tiles of 1000, which do not divide 2890 x 4980), filled.
TEST(BuildDrainage, MpiLogan10mEqualsTheUntiledRun) {
  SKIP_WITHOUT_MPI_LAUNCH();
  terrain::test::ScratchDir dir;
  const std::string tif = dir.path("logan10.tif");
  ASSERT_EQ(std::system(("gdalwarp -q -r cubic -tr 10 10 " + data("logan_utm12n_100m.tif") + " " + tif).c_str()), 0);
  const std::string args = "--raster " + tif + " --fill ";
  const auto u = run(tool("build-drainage") + " " + args + dir.path("u.dv") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  const auto m = run(mpirun(3) + tool("build-drainage") + " " + args + dir.path("t.dv") + " --tile-size 1000 -q");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  expect_same_db(read_dv(dir.path("u.dv")), read_dv(dir.path("t.dv")), "logan 10 m, 3 ranks");
}
#endif

// --breach: the counts on stdout, the flag in the file (terrain-inspect info), and the
// surface written with --rasters is the breached one (its elevations are the .dv's).
TEST(BuildDrainage, BreachIsReportedAndRecorded) {
  terrain::test::ScratchDir dir;
  const std::string dem = data("logan_utm12n_100m.tif");
  const auto r = run(tool("build-drainage") + " --raster " + dem + " " + dir.path("b.dv") + " --breach 5 -q --rasters " +
                     dir.path(""));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("carved: "), std::string::npos) << r.out;
  const auto info = run(tool("terrain-inspect") + " info " + dir.path("b.dv"));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("breached: yes"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("filled: no"), std::string::npos) << info.out;
  const terrain::Grid original = terrain::read_dem(dem), surface = terrain::read_dem(dir.path("surface.tif"));
  std::size_t lowered = 0;
  for (std::size_t i = 0; i < original.size(); ++i)
    if (original.valid(i)) lowered += surface.z[i] < original.z[i];
  EXPECT_NE(r.out.find("carved: " + std::to_string(lowered) + " "), std::string::npos) << r.out;
  EXPECT_GT(lowered, 0u);
}

TEST(BuildDrainage, BadInputFailsCleanly) {
  terrain::test::ScratchDir dir;
  // A D8 raster with an invalid TauDEM code (9), and a truncated .dv.
  terrain::Grid bad = terrain::read_dem(data("logan_utm12n_100m.tif"));
  std::fill(bad.z.begin(), bad.z.end(), 1.0f);
  bad.at(10, 10) = 9.0f;
  terrain::write_geotiff(bad, dir.path("bad_d8.tif"));
  bad.at(10, 10) = 1.0f;
  terrain::write_geotiff(bad, dir.path("good_d8.tif"));
  const auto ok = run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + dir.path("ok.dv") + " -q");
  ASSERT_EQ(ok.exit_code, 0);
  std::filesystem::resize_file(dir.path("ok.dv"), std::filesystem::file_size(dir.path("ok.dv")) - 1);
  const std::size_t entries = dir.n_entries();
  struct Case {
    std::string command, message;
    int code;
  };
  const std::string out = dir.path("out.dv");
  const Case cases[] = {
      {tool("build-drainage") + " " + data("logan_utm12n_100m.tif") + " " + out, "not a PLY file", 1},
      {tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " --d8-input " + dir.path("bad_d8.tif") +
           " " + out,
       "row 10, column 10: D8 code 9 is not a valid TauDEM code", 1},
      {tool("build-drainage") + " --raster " + data("msh_2007_utm10n_10m.tif") + " --d8-input " + dir.path("good_d8.tif") +
           " " + out,
       "mismatched grids", 1},
      {tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + out + " --spacing 5",
       "--spacing applies to mesh mode only", 1},
      {tool("build-drainage") + " --raster " + data("missing.tif") + " " + out, "no such file", 1},
      {tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + out + " --spacing 0", "--spacing", 2},
      {tool("terrain-inspect") + " info " + dir.path("ok.dv"), "truncated", 1},
  };
  for (const Case& c : cases) {
    const auto r = run(c.command + " -q");
    EXPECT_EQ(r.exit_code, c.code) << c.command << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1u) << c.command << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.command << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.command;
  }
  EXPECT_EQ(dir.n_entries(), entries);  // nothing left behind
}

}  // namespace
}  // namespace drainage
