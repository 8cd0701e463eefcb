// End-to-end: build-drainage and terrain-inspect on .dv files.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include <fmt/format.h>

#include "drainage/dv_file.hpp"
#include "drainage/gis_layers.hpp"
#include "drainage/rasters.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace drainage {
namespace {

using terrain::test::data;
using terrain::test::file_bytes;
using terrain::test::run;
using terrain::test::tool;

std::size_t lines(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n'));
}

TEST(BuildDrainage, MeshPipelineIsDeterministicAcrossThreadCounts) {
  terrain::test::ScratchDir dir;
  const auto m = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " +
                     dir.path("m.ply") + " --spacing 50 -q");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const auto a = run(tool("build-drainage") + " " + dir.path("m.ply") + " " + dir.path("a.dv") +
                     " --threads 1 -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  // Same command line as far as the output is concerned: the same file name.
  std::filesystem::rename(dir.path("a.dv"), dir.path("first.dv"));
  const auto b = run(tool("build-drainage") + " " + dir.path("m.ply") + " " + dir.path("a.dv") +
                     " --threads 2 -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_TRUE(file_bytes(dir.path("first.dv")) == file_bytes(dir.path("a.dv")))
      << "the .dv differs between 1 and 2 threads";
  EXPECT_NE(a.out.find("points: 131236\n"), std::string::npos)
      << a.out;  // 301 x 436 samples at 10 m

  const auto i = run(tool("terrain-inspect") + " info " + dir.path("a.dv"));
  ASSERT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("points: 131236\n"), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("source: PN surface of a mesh"), std::string::npos);
  const auto p =
      run(tool("terrain-inspect") + " preview " + dir.path("a.dv") + " -o " + dir.path("a.png"));
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_TRUE(std::filesystem::exists(dir.path("a.png")));
  const auto g =
      run(tool("terrain-inspect") + " export " + dir.path("a.dv") + " --to gpkg --min-order 2");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_TRUE(std::filesystem::exists(dir.path("a.gpkg")));
}

// --rasters writes every layer; feeding its d8.tif back through --d8-input reproduces the
// accumulation (the encodings round-trip), in both encodings.
TEST(BuildDrainage, RastersAndD8InputRoundTrip) {
  terrain::test::ScratchDir dir;
  std::filesystem::create_directory(dir.path("r"));
  for (const std::string enc : {"taudem", "esri"}) {
    const auto a =
        run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " +
            dir.path("a.dv") + " --rasters " + dir.path("r") + " --d8-encoding " + enc + " -q");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    for (const char* f :
         {"surface", "d8", "accumulation", "normalized_flow", "basin", "class", "order"})
      EXPECT_TRUE(std::filesystem::exists(dir.path(std::string("r/") + f + ".tif"))) << f;
    const auto b =
        run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " --d8-input " +
            dir.path("r/d8.tif") + " --d8-encoding " + enc + " " + dir.path("b.dv") + " -q");
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const DrainageDb da = read_dv(dir.path("a.dv")), db = read_dv(dir.path("b.dv"));
    ASSERT_EQ(da.vertices.size(), db.vertices.size());
    for (std::size_t i = 0; i < da.vertices.size(); ++i) {
      ASSERT_EQ(da.vertices[i].accumulated, db.vertices[i].accumulated) << enc << " " << i;
      ASSERT_EQ(da.vertices[i].basin, db.vertices[i].basin);
    }
    const terrain::Grid acc = terrain::read_dem(dir.path("r/accumulation.tif"));
    for (std::size_t i = 0; i < acc.size(); ++i)
      ASSERT_EQ(double(acc.z[i]), double(da.vertices[i].accumulated));
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
    ASSERT_TRUE(u.z == v.z && u.accumulated == v.accumulated && u.normalized == v.normalized &&
                u.basin == v.basin && u.downstream == v.downstream &&
                u.point_class == v.point_class && u.order == v.order && u.d8 == v.d8)
        << "vertex " << i;
  }
  ASSERT_EQ(a.branches.size(), b.branches.size());
  for (std::size_t k = 0; k < a.branches.size(); ++k)
    ASSERT_TRUE(a.branches[k].first == b.branches[k].first &&
                a.branches[k].count == b.branches[k].count &&
                a.branches[k].drains_into == b.branches[k].drains_into &&
                a.branches[k].order == b.branches[k].order)
        << "branch " << k;
  EXPECT_TRUE(
      std::equal(a.branch_vertices.begin(), a.branch_vertices.end(), b.branch_vertices.begin()));
}

// --tile-size gives the untiled run's database exactly (every field), with tile sizes that
// do and do not divide the grid, filled or not, from a DEM or from D8 codes.
// Issue 49: one summary for tiled and untiled runs (drainage/job.hpp), the same keys in the
// same order; the tiled run's classes counted from its .dv, so every value but the tiles
// and the flats (counted by untiled runs only) equals the untiled run's.
TEST(BuildDrainage, TiledAndUntiledRunsPrintTheSameSummary) {
  terrain::test::ScratchDir dir;
  const std::string bd =
      tool("build-drainage") + " --raster " + data("med_01_01_10m.tif") + " --fill -q ";
  const auto u = run(bd + dir.path("u.dv"));
  const auto t = run(bd + dir.path("t.dv") + " --tile-size 100");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  ASSERT_EQ(t.exit_code, 0) << t.err;
  auto lines = [](const std::string& out) {
    std::vector<std::pair<std::string, std::string>> kv;
    std::istringstream in(out);
    for (std::string l; std::getline(in, l);)
      kv.emplace_back(l.substr(0, l.find(':')), l.substr(l.find(':') + 1));
    return kv;
  };
  const auto a = lines(u.out), b = lines(t.out);
  ASSERT_EQ(a.size(), b.size()) << u.out << "\n" << t.out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].first, b[i].first) << "line " << i;
    if (a[i].first != "output" && a[i].first != "tiles" && a[i].first != "flats") {
      EXPECT_EQ(a[i].second, b[i].second) << a[i].first;
    }
  }
  EXPECT_NE(u.out.find("\npits: "), std::string::npos);
  EXPECT_NE(t.out.find("\ntiles: 35\n"), std::string::npos) << t.out;
}

TEST(BuildDrainage, TiledRunsEqualTheUntiledRun) {
  terrain::test::ScratchDir dir;
  const std::string bd = tool("build-drainage") + " ";
  // MSH and MED (projected), the Eno crop (geographic: per-row metric cells in every window),
  // Mandakini (clipped to its catchment: 45 % no-data, its outline across many tiles).
  for (const char* name : {"msh_2007_utm10n_10m.tif", "med_01_01_10m.tif",
                           "eno_nad83_geographic_crop.tif", "mandakini_srtm90_utm44n.tif"}) {
    for (const std::string opts : {"", " --fill", " --keep-flats", " --keep-flats --fill"}) {
      const auto u = run(bd + "--raster " + data(name) + " " + dir.path("u.dv") + opts + " -q");
      ASSERT_EQ(u.exit_code, 0) << u.err;
      const DrainageDb whole = read_dv(dir.path("u.dv"));
      // Tiles of 128 (dividing the .dv's blocks) and 457 (dividing nothing); 100 (neither
      // either) is the MPI test's and the summary test's.
      for (const int side : {128, 457}) {
        const auto t = run(bd + "--raster " + data(name) + " " + dir.path("t.dv") + opts +
                           " --tile-size " + std::to_string(side) + " -q");
        ASSERT_EQ(t.exit_code, 0) << t.err;
        expect_same_db(whole, read_dv(dir.path("t.dv")),
                       std::string(name) + opts + " tiles " + std::to_string(side));
        EXPECT_EQ(read_dv_header(dir.path("t.dv")).block_rows, std::uint32_t(side));
      }
    }
  }
  // From D8 codes: the d8.tif of an untiled run, accumulated in tiles.
  std::filesystem::create_directory(dir.path("r"));
  const auto a = run(bd + "--raster " + data("logan_utm12n_100m.tif") + " " + dir.path("a.dv") +
                     " --rasters " + dir.path("r") + " -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run(bd + "--d8-input " + dir.path("r/d8.tif") + " " + dir.path("b.dv") + " -q");
  const auto c = run(bd + "--d8-input " + dir.path("r/d8.tif") + " " + dir.path("c.dv") +
                     " --tile-size 77 -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  ASSERT_EQ(c.exit_code, 0) << c.err;
  expect_same_db(read_dv(dir.path("b.dv")), read_dv(dir.path("c.dv")), "d8 input");
  // Not in mesh mode; nothing left behind (temporary rasters included).
  const auto f =
      run(bd + data("logan_utm12n_100m.tif") + " " + dir.path("f.dv") + " --tile-size 100 -q");
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
  ASSERT_EQ(
      std::system(
          ("gdalwarp -q -r cubic -tr 10 10 " + data("logan_utm12n_100m.tif") + " " + tif).c_str()),
      0);
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
      if (r >= 8 && r < 24 && c >= 9 && c < 24)
        z = 19.0f;  // terrace over tiles (0,0) (0,1) (1,0) (1,1)
      if (r >= 40 && r < 56 && c >= 56 && c < 72)
        z = 20.0f;  // depression over tiles (2,3) (2,4) (3,3) (3,4)
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
      for (std::size_t c = 9; c < 24; ++c)
        ASSERT_NE(whole.vertices[r * 80 + c].downstream, kNone) << r << " " << c;
    // Filled, the depression drains too: every basin is one whose pit is on the west edge.
    if (!opts.empty()) {
      for (const DvVertex& v : whole.vertices) {
        if (v.downstream == kNone) {
          ASSERT_LT(v.x, whole.vertices[1].x);
        }
      }
    }
    for (const int side : {16, 13}) {
      const auto t =
          run(bd + dir.path("t.dv") + opts + " --tile-size " + std::to_string(side) + " -q");
      ASSERT_EQ(t.exit_code, 0) << t.err;
      expect_same_db(whole, read_dv(dir.path("t.dv")),
                     "terrace" + opts + " tiles " + std::to_string(side));
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
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  EXPECT_TRUE(ds) << path;
  Band b;
  if (!ds) return b;
  const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
  b.v.resize(std::size_t(w) * std::size_t(h));
  EXPECT_EQ(
      ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w, h, b.v.data(), w, h, GDT_Float64, 0, 0),
      CE_None);
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
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(x.gt[std::size_t(k)], y.gt[std::size_t(k)], 1e-9 * std::abs(x.gt[1])) << k;
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
  for (const char* d : {"u", "t100", "t77", "x2", "x1", "taudem"})
    std::filesystem::create_directory(dir.path(d));
  const std::string bd =
      tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " --fill ";
  const auto u = run(bd + dir.path("u.dv") + " --rasters " + dir.path("u") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  const auto v1 = run(bd + dir.path("v1.dv") + " --dv-version 1 -q");
  ASSERT_EQ(v1.exit_code, 0) << v1.err;
  for (const std::string side : {"100", "77"}) {
    const auto t = run(bd + dir.path("t.dv") + " --tile-size " + side + " --rasters " +
                       dir.path("t" + side) + " -q");
    ASSERT_EQ(t.exit_code, 0) << t.err;
    expect_same_rasters(dir.path("u"), dir.path("t" + side), "tiles of " + side);
  }
  for (const std::string version : {"2", "1"}) {
    const std::string dv = dir.path(version == "2" ? "u.dv" : "v1.dv"),
                      out = dir.path("x" + version);
    const auto e = run(tool("terrain-inspect") + " export " + dv + " --to tif -o " + out);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    EXPECT_NE(e.out.find("points: 143922"), std::string::npos) << e.out;
    expect_same_rasters(dir.path("u"), out, "export of version " + version);
  }
  // A file where the directory should be: one line, nothing written.
  std::ofstream(dir.path("file")) << "x";
  const auto bad = run(tool("terrain-inspect") + " export " + dir.path("u.dv") + " --to tif -o " +
                       dir.path("file"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("is not a directory"), std::string::npos) << bad.err;

  const auto a =
      run(tool("build-drainage") + " --d8-input " + data("logan_30m_taudem_d8dir.tif") + " " +
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

std::unique_ptr<GDALDataset> open_vector(const std::string& path) {
  terrain::ensure_gdal();
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  EXPECT_TRUE(ds) << path;
  return ds;
}

// Basins and divides of the Logan 100 m run as GeoPackage layers, checked against the
// basin raster of the same run: every basin one feature whose area is its cells', holding
// its outlet; the divides along the cell edges between two basins, on both boundaries.
TEST(BuildDrainage, BasinsAndDividesAsGisLayers) {
  terrain::test::ScratchDir dir;
  std::filesystem::create_directory(dir.path("r"));
  const auto b = run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " +
                     dir.path("l.dv") + " --fill --rasters " + dir.path("r") + " -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto e = run(tool("terrain-inspect") + " export " + dir.path("l.dv") + " --to gpkg -q");
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const auto o = run("ogrinfo -so -al " + dir.path("l.gpkg"));  // what QGIS reads, GDAL reads
  ASSERT_EQ(o.exit_code, 0) << o.err;
  for (const char* layer : {"branches", "basins", "divides"})
    EXPECT_NE(o.out.find(std::string("Layer name: ") + layer), std::string::npos) << o.out;

  // The branches: a filter on the Strahler order as QGIS writes it (no quoting: the field is
  // not the SQL keyword `order`), and each branch's max_flow its own, below the junction's
  // it drains into (the line's last vertex, M the normalized flow there).
  {
    auto gpkg = open_vector(dir.path("l.gpkg"));
    ASSERT_TRUE(gpkg);
    OGRLayer* all = gpkg->GetLayerByName("branches");
    ASSERT_NE(all, nullptr);
    ASSERT_EQ(all->SetAttributeFilter("strahler >= 3"), OGRERR_NONE);
    const GIntBig high = all->GetFeatureCount();
    EXPECT_GT(high, 0);
    EXPECT_LT(high, (all->SetAttributeFilter(nullptr), all->GetFeatureCount()));
    const DrainageDb db = read_dv(dir.path("l.dv"));
    std::vector<std::int64_t> own;  // per branch written (a lone pit is none), in order
    std::size_t stubs = 0, below = 0;
    for (const DvBranch& br : db.branches) {
      if (br.count + (br.drains_into != kNone ? 1u : 0u) < 2) continue;
      std::uint32_t m = 0;
      for (std::uint32_t k = 0; k < br.count; ++k)
        m = std::max(m, db.vertices[db.branch_vertices[br.first + k]].accumulated);
      own.push_back(m);
      if (br.order == 1 && br.drains_into != kNone)
        ++stubs, below += m < db.vertices[br.drains_into].accumulated;
    }
    all->ResetReading();
    std::size_t i = 0;
    for (const auto& f : *all) {
      ASSERT_LT(i, own.size());
      ASSERT_EQ(f->GetFieldAsInteger64("max_flow"), own[i++]) << i;
    }
    EXPECT_EQ(i, own.size());
    EXPECT_GT(stubs, 100u);
    EXPECT_EQ(below, stubs);  // the junction's flow is never a stub's own
  }
  const DvHeader h = read_dv_header(dir.path("l.dv"));
  const Band basin = band_of(dir.path("r/basin.tif")), order = band_of(dir.path("r/order.tif"));
  const std::size_t C = h.cols, R = h.rows;
  const double cell = h.dx * h.dy;
  std::map<std::uint32_t, std::uint64_t> cells;
  double edges = 0;  // 4-neighbour pairs of cells in two different basins
  for (std::size_t r = 0; r < R; ++r)
    for (std::size_t c = 0; c < C; ++c) {
      const double u = basin.v[r * C + c];
      if (u == basin.nodata) continue;
      ++cells[std::uint32_t(u)];
      for (const std::size_t j :
           {c + 1 < C ? r * C + c + 1 : SIZE_MAX, r + 1 < R ? (r + 1) * C + c : SIZE_MAX})
        if (j != SIZE_MAX && basin.v[j] != basin.nodata && basin.v[j] != u) ++edges;
    }

  const auto ds = open_vector(dir.path("l.gpkg"));
  ASSERT_TRUE(ds);
  OGRLayer* basins = ds->GetLayerByName("basins");
  ASSERT_TRUE(basins);
  EXPECT_EQ(std::uint64_t(basins->GetFeatureCount()), h.basins);
  double area = 0;
  std::map<std::int64_t, std::unique_ptr<OGRGeometry>> boundary;
  std::map<std::int64_t, int> max_order;
  for (auto& f : *basins) {
    const std::int64_t id = f->GetFieldAsInteger64("id");
    const auto* poly = f->GetGeometryRef()->toMultiPolygon();
    area += poly->get_Area();
    EXPECT_NEAR(poly->get_Area(), double(cells[std::uint32_t(id)]) * cell,
                1e-12 * double(h.valid) * cell)
        << id;
    EXPECT_EQ(std::uint64_t(f->GetFieldAsInteger64("cells")), cells[std::uint32_t(id)]) << id;
    const double x = f->GetFieldAsDouble("outlet_x"), y = f->GetFieldAsDouble("outlet_y");
    OGRPoint outlet(x, y);
    EXPECT_TRUE(poly->Contains(&outlet)) << "basin " << id << " does not hold its outlet";
    const std::size_t oc = std::size_t(std::lround((x - basin.gt[0]) / basin.gt[1] - 0.5)),
                      orow = std::size_t(std::lround((y - basin.gt[3]) / basin.gt[5] - 0.5));
    EXPECT_EQ(basin.v[orow * C + oc], double(id));
    EXPECT_EQ(f->GetFieldAsInteger("max_order"), int(order.v[orow * C + oc]));
    max_order[id] = f->GetFieldAsInteger("max_order");
    boundary[id].reset(poly->Boundary());
  }
  EXPECT_NEAR(area, double(h.valid) * cell, 1e-9 * double(h.valid) * cell)
      << "polygon areas sum to the valid area";

  OGRLayer* divides = ds->GetLayerByName("divides");
  ASSERT_TRUE(divides);
  double length = 0;
  std::size_t checked = 0;
  for (auto& f : *divides) {
    const std::int64_t a = f->GetFieldAsInteger64("basin_a"),
                       bb = f->GetFieldAsInteger64("basin_b");
    const auto* lines = f->GetGeometryRef()->toMultiLineString();
    EXPECT_LT(a, bb);
    EXPECT_NEAR(lines->get_Length(), f->GetFieldAsDouble("length_m"), 1e-6);
    EXPECT_EQ(f->GetFieldAsInteger("max_order"), std::max(max_order[a], max_order[bb]));
    length += lines->get_Length();
    if (checked++ % 8 == 0) {  // GEOS on one in eight: the divide lies on both basins' boundaries
      EXPECT_TRUE(lines->Within(boundary[a].get())) << a << "-" << bb;
      EXPECT_TRUE(lines->Within(boundary[bb].get())) << a << "-" << bb;
    }
  }
  EXPECT_GT(checked, 100u);
  EXPECT_NEAR(length, edges * h.dx, 1e-6 * length)
      << "divides run along every edge between two basins";
}

// Watersheds at outlets on TauDEM's D8 of Logan 30 m: each watershed's cells are TauDEM's
// aread8 at its outlet less the aread8 of the outlets nested in it; the same raster from a
// tiled run; snapping picks the highest aread8 within the distance.
TEST(BuildDrainage, WatershedsAtOutletsAreTauDemsUpstreamAreas) {
  terrain::test::ScratchDir dir;
  const Band d8 = band_of(data("logan_30m_taudem_d8dir.tif")),
             acc = band_of(data("logan_30m_taudem_aread8.tif"));
  const std::size_t C = 985, R = 1660;
  ASSERT_EQ(acc.v.size(), R * C);
  auto valid = [&](std::size_t i) { return acc.v[i] != acc.nodata && !std::isnan(acc.v[i]); };
  auto x_of = [&](std::size_t i) { return acc.gt[0] + (double(i % C) + 0.5) * acc.gt[1]; };
  auto y_of = [&](std::size_t i) { return acc.gt[3] + (double(i / C) + 0.5) * acc.gt[5]; };
  // Outlets: the largest aread8, three interior cells of 300-3000 cells and, 60 steps down
  // TauDEM's D8 from each, a cell they nest in.
  std::vector<std::size_t> outlet;
  outlet.push_back(std::size_t(
      std::max_element(acc.v.begin(), acc.v.end(), [&](double p, double q) { return p < q; }) -
      acc.v.begin()));
  const int dr[9] = {0, 0, -1, -1, -1, 0, 1, 1, 1},
            dc[9] = {0, 1, 1, 0, -1, -1, -1, 0, 1};  // TauDEM 1..8
  for (const std::size_t row : {R / 4, R / 2, 3 * R / 4}) {
    std::size_t i = row * C + C / 3;  // away from the edges, where aread8 is left undefined
    while (i < (row + 1) * C && !(valid(i) && acc.v[i] >= 300 && acc.v[i] <= 3000)) ++i;
    ASSERT_LT(i, (row + 1) * C);
    outlet.push_back(i);
    for (int step = 0; step < 60; ++step) {
      const int code = int(d8.v[i]);
      if (code < 1 || code > 8) break;
      const long r = long(i / C) + dr[code], c = long(i % C) + dc[code];
      if (r < 0 || c < 0 || r >= long(R) || c >= long(C) ||
          !valid(std::size_t(r) * C + std::size_t(c)))
        break;
      i = std::size_t(r) * C + std::size_t(c);
    }
    if (std::find(outlet.begin(), outlet.end(), i) == outlet.end()) outlet.push_back(i);
  }
  {
    std::ofstream csv(dir.path("outlets.csv"));
    csv << "name,x,y\n" << std::setprecision(17);
    for (std::size_t k = 0; k < outlet.size(); ++k)
      csv << "o" << k << "," << x_of(outlet[k]) << "," << y_of(outlet[k]) << "\n";
  }
  const std::string bd =
      tool("build-drainage") + " --d8-input " + data("logan_30m_taudem_d8dir.tif") + " ";
  const auto u = run(bd + dir.path("u.dv") + " --outlets " + dir.path("outlets.csv") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  EXPECT_NE(u.out.find("watersheds: " + dir.path("u_watersheds.gpkg")), std::string::npos) << u.out;
  const Band shed = band_of(dir.path("u_watersheds.tif"));
  std::vector<std::uint64_t> raster_cells(outlet.size());
  for (const double v : shed.v)
    if (v != shed.nodata) ++raster_cells.at(std::size_t(v));

  const auto ds = open_vector(dir.path("u_watersheds.gpkg"));
  ASSERT_TRUE(ds);
  OGRLayer* points = ds->GetLayerByName("outlets");
  ASSERT_TRUE(points);
  ASSERT_EQ(std::size_t(points->GetFeatureCount()), outlet.size());
  std::vector<std::int64_t> downstream(outlet.size());
  std::vector<std::uint64_t> cells(outlet.size());
  for (auto& f : *points) {
    const std::size_t k = std::size_t(f->GetFieldAsInteger64("id"));
    downstream.at(k) = f->IsFieldSetAndNotNull(f->GetFieldIndex("downstream"))
                           ? f->GetFieldAsInteger64("downstream")
                           : -1;
    cells[k] = std::uint64_t(f->GetFieldAsInteger64("cells"));
    EXPECT_EQ(f->GetFieldAsDouble("moved_m"), 0.0) << k;
    EXPECT_EQ(double(f->GetFieldAsInteger64("accumulated")), acc.v[outlet[k]]) << k;
    EXPECT_EQ(cells[k], raster_cells[k]) << k;
  }
  std::size_t nested = 0;
  for (std::size_t k = 0; k < outlet.size(); ++k) {
    double upstream = double(cells[k]);
    for (std::size_t j = 0; j < outlet.size(); ++j)
      if (downstream[j] == std::int64_t(k)) upstream += acc.v[outlet[j]], ++nested;
    EXPECT_EQ(upstream, acc.v[outlet[k]]) << "outlet " << k;
  }
  EXPECT_GE(nested, 3u);
  OGRLayer* polygons = ds->GetLayerByName("watersheds");
  ASSERT_TRUE(polygons);
  for (auto& f : *polygons)
    EXPECT_NEAR(f->GetGeometryRef()->toMultiPolygon()->get_Area(),
                double(cells.at(std::size_t(f->GetFieldAsInteger64("id")))) * 900.0,
                1e-3);  // of 10^5..10^9 m^2

  // Tiled: the same raster.
  const auto t =
      run(bd + dir.path("t.dv") + " --tile-size 300 --outlets " + dir.path("outlets.csv") + " -q");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_TRUE(band_of(dir.path("t_watersheds.tif")).v == shed.v);

  // Snapping: 100 m around a point 40 m off an outlet in the interior (where TauDEM's aread8
  // is defined on every cell within reach).
  const std::size_t near = outlet.back();
  const double px = x_of(near) + 40, py = y_of(near) - 25;
  std::size_t best = SIZE_MAX;
  double best_d = 0;
  for (std::size_t i = 0; i < acc.v.size(); ++i) {
    const double d = std::hypot(x_of(i) - px, y_of(i) - py);
    if (d > 100) continue;
    ASSERT_TRUE(valid(i)) << "aread8 has no value within reach of the snapped point";
    if (best == SIZE_MAX || acc.v[i] > acc.v[best] || (acc.v[i] == acc.v[best] && d < best_d))
      best = i, best_d = d;
  }
  EXPECT_NE(best, near);
  {
    std::ofstream csv(dir.path("one.csv"));
    csv << "x,y\n" << std::setprecision(17) << px << "," << py << "\n";
  }
  const auto s =
      run(bd + dir.path("s.dv") + " --outlets " + dir.path("one.csv") + " --snap-distance 100 -q");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_NE(s.out.find(fmt::format("outlet_0: row {}, column {}, moved {:.2f} m", best / C,
                                   best % C, best_d)),
            std::string::npos)
      << s.out << "expected row " << best / C << ", column " << best % C << ", " << best_d << " m";

  // An outlet off the grid: one line, nothing written (refused before any snapping, issue 48).
  {
    std::ofstream csv(dir.path("off.csv"));
    csv << "x,y\n1000,1000\n";
  }
  const auto off =
      run(bd + dir.path("off.dv") + " --outlets " + dir.path("off.csv") + " --snap-distance 50 -q");
  EXPECT_EQ(off.exit_code, 1);
  EXPECT_NE(off.err.find("lies outside the grid"), std::string::npos) << off.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("off.dv")));
  EXPECT_FALSE(std::filesystem::exists(dir.path("off_watersheds.gpkg")));
}

#ifdef TERRAIN_MPIEXEC
using terrain::test::mpirun;

// Skips the test where this machine cannot start 3 ranks at all (a launcher problem, not ours).
#define SKIP_WITHOUT_MPI_LAUNCH()                                                                \
  do {                                                                                           \
    const auto probe = run(mpirun(3) + "true");                                                  \
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
    const std::string tiled =
        input + " " + dir.path("t.dv") + opts + " --tile-size " + std::to_string(side) + " -q";
    const auto s = run(bd + tiled);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const std::string single = file_bytes(dir.path("t.dv"));
    for (const int ranks : {1, 3}) {
      std::filesystem::remove(dir.path("t.dv"));
      const auto m = run(mpirun(ranks) + bd + tiled);
      ASSERT_EQ(m.exit_code, 0) << m.err;
      EXPECT_EQ(m.out, s.out) << ranks << " ranks";
      expect_same_db(read_dv(dir.path("u.dv")), read_dv(dir.path("t.dv")),
                     std::to_string(ranks) + " ranks");
      EXPECT_TRUE(file_bytes(dir.path("t.dv")) == single)
          << ranks << " ranks: not the single-process file";
    }
  };
  // Each DEM with and without --fill, tiles of 64 and 100 in turn (each side meets each
  // option on some DEM; every pair on every DEM cost 30 s more of mpirun starts).
  int turn = 0;
  for (const char* name :
       {"msh_2007_utm10n_10m.tif", "med_01_01_10m.tif", "eno_nad83_geographic_crop.tif"})
    for (const std::string opts : {"", " --fill"})
      check("--raster " + data(name), opts, turn++ % 3 == 1 ? 100 : 64);
  check("--raster " + dir.path("terrace.tif"), " --fill", 16);
  check("--raster " + dir.path("terrace.tif"), "", 13);
  // From D8 codes.
  std::filesystem::create_directory(dir.path("r"));
  const auto a = run(bd + "--raster " + data("logan_utm12n_100m.tif") + " " + dir.path("a.dv") +
                     " --rasters " + dir.path("r") + " -q");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  check("--d8-input " + dir.path("r/d8.tif"), "", 77);
  // Nothing left behind: no scratch array, no rank's block file.
  for (const auto& e : std::filesystem::directory_iterator(dir.path("")))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  // Mesh mode does not run on several ranks: a clear error, every rank ended.
  const auto mesh =
      run(mpirun(3) + bd + data("logan_utm12n_100m.tif") + " " + dir.path("f.dv") + " -q");
  EXPECT_NE(mesh.exit_code, 0);
  EXPECT_NE(mesh.err.find("mesh mode runs on one process"), std::string::npos) << mesh.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("f.dv")));
}

// Logan at 10 m on 3 ranks (tiles of 1000, which do not divide 2890 x 4980), filled.
TEST(BuildDrainage, MpiLogan10mEqualsTheUntiledRun) {
  SKIP_WITHOUT_MPI_LAUNCH();
  terrain::test::ScratchDir dir;
  const std::string tif = dir.path("logan10.tif");
  ASSERT_EQ(
      std::system(
          ("gdalwarp -q -r cubic -tr 10 10 " + data("logan_utm12n_100m.tif") + " " + tif).c_str()),
      0);
  const std::string args = "--raster " + tif + " --fill ";
  const auto u = run(tool("build-drainage") + " " + args + dir.path("u.dv") + " -q");
  ASSERT_EQ(u.exit_code, 0) << u.err;
  const auto m = run(mpirun(3) + tool("build-drainage") + " " + args + dir.path("t.dv") +
                     " --tile-size 1000 -q");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  expect_same_db(read_dv(dir.path("u.dv")), read_dv(dir.path("t.dv")), "logan 10 m, 3 ranks");
}
#endif

// --breach: the counts on stdout, the flag in the file (terrain-inspect info), and the
// surface written with --rasters is the breached one (its elevations are the .dv's).
TEST(BuildDrainage, BreachIsReportedAndRecorded) {
  terrain::test::ScratchDir dir;
  const std::string dem = data("logan_utm12n_100m.tif");
  const auto r = run(tool("build-drainage") + " --raster " + dem + " " + dir.path("b.dv") +
                     " --breach 5 -q --rasters " + dir.path(""));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("carved: "), std::string::npos) << r.out;
  const auto info = run(tool("terrain-inspect") + " info " + dir.path("b.dv"));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("breached: yes"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("filled: no"), std::string::npos) << info.out;
  const terrain::Grid original = terrain::read_dem(dem),
                      surface = terrain::read_dem(dir.path("surface.tif"));
  std::size_t lowered = 0;
  for (std::size_t i = 0; i < original.size(); ++i)
    if (original.valid(i)) lowered += surface.z[i] < original.z[i];
  EXPECT_NE(r.out.find("carved: " + std::to_string(lowered) + " "), std::string::npos) << r.out;
  EXPECT_GT(lowered, 0u);
}

// Mesh mode conditions by default: its .dv is --breach 10's (every point, every branch),
// recorded as breached; --keep-pits keeps the paper's every-pit-a-basin rule, with more
// basins on a real surface (MSH's crater floor and the pits of its PN surface). Raster
// mode's default stays unconditioned (the TauDEM references test it point by point).
TEST(BuildDrainage, MeshModeBreachesByDefaultAndKeepPitsKeepsThePapersRule) {
  terrain::test::ScratchDir dir;
  const auto m = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " +
                     dir.path("m.ply") + " --spacing 50 -q");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const std::string bd = tool("build-drainage") + " " + dir.path("m.ply") + " ";
  const auto d = run(bd + dir.path("default.dv") + " -q");
  const auto b = run(bd + dir.path("breach.dv") + " --breach 10 -q");
  const auto k = run(bd + dir.path("pits.dv") + " --keep-pits -q");
  for (const auto* r : {&d, &b, &k}) ASSERT_EQ(r->exit_code, 0) << r->err;
  EXPECT_NE(d.out.find("carved: "), std::string::npos) << d.out;
  EXPECT_EQ(k.out.find("carved: "), std::string::npos) << k.out;
  const DrainageDb def = read_dv(dir.path("default.dv")), pits = read_dv(dir.path("pits.dv"));
  expect_same_db(def, read_dv(dir.path("breach.dv")), "default vs --breach 10");
  EXPECT_TRUE(def.header.flags & kDvBreached);
  EXPECT_FALSE(pits.header.flags & (kDvBreached | kDvFilled));
  EXPECT_GT(pits.header.basins, def.header.basins);
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
  const auto ok = run(tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " +
                      dir.path("ok.dv") + " -q");
  ASSERT_EQ(ok.exit_code, 0);
  std::filesystem::resize_file(dir.path("ok.dv"),
                               std::filesystem::file_size(dir.path("ok.dv")) - 1);
  const std::size_t entries = dir.n_entries();
  struct Case {
    std::string command, message;
    int code;
  };
  const std::string out = dir.path("out.dv");
  const Case cases[] = {
      {tool("build-drainage") + " " + data("logan_utm12n_100m.tif") + " " + out, "not a PLY file",
       1},
      {tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " --d8-input " +
           dir.path("bad_d8.tif") + " " + out,
       "row 10, column 10: D8 code 9 is not a valid TauDEM code", 1},
      {tool("build-drainage") + " --raster " + data("msh_2007_utm10n_10m.tif") + " --d8-input " +
           dir.path("good_d8.tif") + " " + out,
       "mismatched grids", 1},
      {tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + out +
           " --spacing 5",
       "--spacing applies to mesh mode only", 1},
      {tool("build-drainage") + " --raster " + data("missing.tif") + " " + out, "no such file", 1},
      {tool("build-drainage") + " --raster " + data("logan_utm12n_100m.tif") + " " + out +
           " --spacing 0",
       "--spacing", 2},
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
