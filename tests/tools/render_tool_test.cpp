// End-to-end: terrain-render frame / batch / path on a real mesh and drainage database,
// bad frame lists, and a machine without a usable OpenGL.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include <gdal_priv.h>
#include <ogrsf_frmts.h>

#include "terrain/dem_io.hpp"
#include "terrain/mesh_io.hpp"
#include "test_support.hpp"
#include "tools/ink.hpp"

namespace {

using terrain::test::data;
using terrain::test::run;
using terrain::test::tool;

std::size_t lines(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n'));
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A 50 m Mount St. Helens mesh and its drainage at 25 m, made once per test.
// The SVG at `svg` rasterized by librsvg on white into `png`.
void rsvg_ink(const std::string& svg, const std::string& png) {
  ASSERT_EQ(run("rsvg-convert -b white " + svg + " -o " + png).exit_code, 0);
}

// A file as GDAL opens it read-only (kind: GDAL_OF_RASTER or GDAL_OF_VECTOR); null if it
// cannot.
std::unique_ptr<GDALDataset> opened(const std::string& path, unsigned kind) {
  terrain::ensure_gdal();
  return std::unique_ptr<GDALDataset>(GDALDataset::Open(path.c_str(), kind | GDAL_OF_READONLY));
}

struct Inputs {
  terrain::test::ScratchDir dir;
  std::string mesh, dv;
  Inputs() : mesh(dir.path("m.ply")), dv(dir.path("m.dv")) {
    const auto a = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                       " --spacing 50 -q");
    EXPECT_EQ(a.exit_code, 0) << a.err;
    const auto b = run(tool("build-drainage") + " " + mesh + " " + dv + " --spacing 25 -q");
    EXPECT_EQ(b.exit_code, 0) << b.err;
  }
};

// terrain-render's top view of the Inputs at 10 m a pixel, 640 x 480, its mask and creases:
// the command up to the output file ("-o " last).
std::string map_frame(const Inputs& in) {
  return tool("terrain-render") + " frame " + in.mesh + " " + in.dv +
         " --view top --map-scale 10 --layers mask,creases --size 640x480 -o ";
}

TEST(TerrainRender, BatchWritesFramesAndTimings) {
  Inputs in;
  const std::string csv = in.dir.path("frames.csv");
  const auto p =
      run(tool("terrain-render") +
          " path --from 561500 5114000 2800 --to 563500 5116000 2700 --frames 3 -o " + csv);
  ASSERT_EQ(p.exit_code, 0) << p.err;
  const std::string out = in.dir.path("frames");
  const auto b = run(tool("terrain-render") + " batch " + in.mesh + " " + in.dv + " " + csv +
                     " -o " + out + " --size 160x120 -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(b.err.empty()) << b.err;
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(std::filesystem::exists(out + "/frame_0000" + std::to_string(i) + ".png")) << i;
  EXPECT_FALSE(std::filesystem::exists(out + "/frame_00003.png"));
  std::ifstream t(out + "/timings.csv");
  std::string header, row;
  std::getline(t, header);
  EXPECT_EQ(header.rfind("frame,TFT_ms,AFT_ms,DM_ms,SIL_ms,LAY_ms,", 0), 0u) << header;
  int rows = 0;
  while (std::getline(t, row)) {
    std::stringstream ss(row);
    std::string cell;
    std::getline(ss, cell, ',');
    EXPECT_EQ(cell, std::to_string(rows));
    for (int k = 0; k < 10; ++k) {  // GPU-timer and wall ms of the five passes
      ASSERT_TRUE(std::getline(ss, cell, ','));
      EXPECT_GT(std::stod(cell), 0.0) << "row " << rows << " column " << k + 1;
    }
    ++rows;
  }
  EXPECT_EQ(rows, 3);
  EXPECT_NE(b.out.find("Table 3"), std::string::npos);
  EXPECT_NE(b.out.find("Table 4"), std::string::npos);

  // --view FRAMES.csv:N draws the batch's frame N, pixel for pixel (the row's camera, light
  // and per-frame options); a row past the last is one line naming the rows there are.
  for (const std::string row : {"0", "2"}) {
    const std::string png = in.dir.path("row" + row + ".png");
    const auto v = run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " + png +
                       " --size 160x120 --view " + csv + ":" + row);
    ASSERT_EQ(v.exit_code, 0) << v.err;
    OIIO::ImageBuf x(png), y(out + "/frame_0000" + row + ".png");
    const auto cmp = OIIO::ImageBufAlgo::compare(x, y, 0.0f, 0.0f);
    EXPECT_EQ(cmp.nfail, 0u) << "row " << row << ": max difference " << cmp.maxerror;
    EXPECT_FALSE(cmp.error) << row;
  }
  const auto past = run(tool("terrain-render") + " frame " + in.mesh + " -o " +
                        in.dir.path("past.png") + " --size 160x120 --view " + csv + ":3");
  EXPECT_EQ(past.exit_code, 1);
  EXPECT_NE(past.err.find("has frames 0 .. 2, not 3"), std::string::npos) << past.err;
  EXPECT_FALSE(std::filesystem::exists(in.dir.path("past.png")));

  // A single frame with the default camera, with and without creases.
  const auto f = run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " +
                     in.dir.path("f.png") + " --size 160x120");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_NE(f.out.find("crease segments drawn: "), std::string::npos) << f.out;
  const auto g = run(tool("terrain-render") + " frame " + in.mesh + " -o " + in.dir.path("g.png") +
                     " --size 160x120 --layers shaded -q");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  EXPECT_TRUE(std::filesystem::exists(in.dir.path("g.png")));
}

// --flow-scale: on the log scale fc = ln a / ln T is at least the linear a / T wherever a
// >= 2 points drain (and T >= 4), so at the same minimum score the default draws at least
// the segments the linear scale draws; an unknown scale is a usage error.
// Surface pixels of a mask-only frame (the mask colour, white).
std::size_t white_pixels(const std::string& png) {
  OIIO::ImageBuf buf(png);
  EXPECT_TRUE(buf.read(0, 0, true, OIIO::TypeDesc::UINT8)) << png;
  std::vector<std::uint8_t> px(std::size_t(buf.spec().width) * std::size_t(buf.spec().height) * 3);
  buf.get_pixels(OIIO::ROI(0, buf.spec().width, 0, buf.spec().height, 0, 1, 0, 3),
                 OIIO::TypeDesc::UINT8, px.data());
  std::size_t n = 0;
  for (std::size_t i = 0; i < px.size(); i += 3)
    n += px[i] == 255 && px[i + 1] == 255 && px[i + 2] == 255;
  return n;
}

// Fine tessellation (1 px per edge, patches at the largest level) covers the same surface as
// the default: llvmpipe dropped whole bands of patches from a draw call tessellating into
// more than 65536 triangles (A3 at 300 dpi showed them at the default 6 px); the surface is
// drawn in calls of 64 patches. Silhouette-free mask frames, so only the outline differs.
TEST(TerrainRender, FineTessellationDrawsEveryPatch) {
  Inputs in;
  std::size_t px[2];
  const char* ppe[2] = {"6", "1"};
  for (int i = 0; i < 2; ++i) {
    const std::string out = in.dir.path(std::string("t") + ppe[i] + ".png");
    const auto r = run(tool("terrain-render") + " frame " + in.mesh + " -o " + out +
                       " --layers mask --view-az 180 "
                       "--pixels-per-edge " +
                       ppe[i] + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    px[i] = white_pixels(out);
  }
  EXPECT_GT(px[0], std::size_t(300000));
  EXPECT_NEAR(double(px[1]) / double(px[0]), 1.0, 0.002) << px[0] << " vs " << px[1];
}

// terrain-inspect info prints the automatic view as terrain-render options: a frame with
// them is the default frame (up to the millimetres the eye is printed to).
TEST(TerrainRender, InfoPrintsTheAutomaticView) {
  Inputs in;
  const auto info = run(tool("terrain-inspect") + " info " + in.mesh);
  ASSERT_EQ(info.exit_code, 0) << info.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(info.out, m, std::regex("automatic_view: ([^\\n]+)"))) << info.out;
  const std::string a = in.dir.path("a.png"), b = in.dir.path("b.png");
  // Without hachures: seeded on a pixel grid, they move with a camera printed to 0.1 m.
  const std::string layers = " --layers mask,creases,silhouettes";
  ASSERT_EQ(run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " + a + " -q " +
                m[1].str() + layers)
                .exit_code,
            0);
  ASSERT_EQ(
      run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " + b + " -q" + layers)
          .exit_code,
      0);
  OIIO::ImageBuf ia(a), ib(b);
  const auto cmp = OIIO::ImageBufAlgo::compare(ia, ib, 0.02f, 0.02f);
  EXPECT_LT(double(cmp.nfail), 0.001 * 1280 * 720) << m[1].str();
}

// The automatic exaggeration (issue 50): a lowland (the Eno crop, about 30 m of relief over
// 2.7 km) gets more than 1, MSH keeps 1; the frame prints it, terrain-inspect info prints
// the same value, and the info's view with that --exaggeration given draws the no-option
// frame; a given value is printed as given.
TEST(TerrainRender, AutomaticExaggerationIsPrintedAndReproduced) {
  Inputs in;
  const std::string eno = in.dir.path("eno.ply");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("eno_nad83_geographic_crop.tif") + " " + eno + " -q")
                .exit_code,
            0);
  for (const std::string& mesh : {eno, in.mesh}) {
    SCOPED_TRACE(mesh);
    const auto info = run(tool("terrain-inspect") + " info " + mesh);
    ASSERT_EQ(info.exit_code, 0) << info.err;
    std::smatch e, v;
    ASSERT_TRUE(std::regex_search(info.out, e, std::regex("automatic_exaggeration: ([0-9.]+)")))
        << info.out;
    ASSERT_TRUE(std::regex_search(info.out, v, std::regex("automatic_view: ([^\n]+)"))) << info.out;
    const double auto_e = std::stod(e[1]);
    if (mesh == eno)
      EXPECT_GE(auto_e, 2.0);
    else
      EXPECT_EQ(auto_e, 1.0);
    // Names of their own for each mesh: OIIO's image cache may hand back the first mesh's
    // pictures for a path written again within the same second (a flaky failure under load).
    const std::string tag = mesh == eno ? "eno" : "msh";
    const std::string a = in.dir.path(tag + "_a.png"), b = in.dir.path(tag + "_b.png");
    // The line layers whose places do not hang on the last digit of the camera (hachures are
    // seeded on a pixel grid: a camera printed to 0.1 m moves some).
    const std::string layers = " --layers mask,creases,silhouettes";
    const auto plain =
        run(tool("terrain-render") + " frame " + mesh + " -o " + a + " --size 320x180" + layers);
    ASSERT_EQ(plain.exit_code, 0) << plain.err;
    EXPECT_NE(plain.out.find("exaggeration: " + e[1].str() + " (automatic)\n"), std::string::npos)
        << plain.out;
    const auto given =
        run(tool("terrain-render") + " frame " + mesh + " -o " + b + " --size 320x180 " +
            v[1].str() + " --exaggeration " + e[1].str() + layers);
    ASSERT_EQ(given.exit_code, 0) << given.err;
    EXPECT_NE(given.out.find("exaggeration: " + e[1].str() + "\n"), std::string::npos) << given.out;
    OIIO::ImageBuf ia(a), ib(b);
    EXPECT_LT(double(OIIO::ImageBufAlgo::compare(ia, ib, 0.02f, 0.02f).nfail), 0.001 * 320 * 180);
  }
}

// An integer DEM (MED_01_01: whole metres, 391-664 m) terraces its gentle slopes into flats,
// and the creases of the default frame ran across them (flat share 0.71). dem2mesh
// interpolates between the terraces' contours (--dequantize auto), and the default valley
// rule (--crease-links valleys) leaves out the D8 tracks down the planes beside the rivers:
// the flat share falls below 0.05 and the valley share rises above 0.8 (issue 38's targets),
// measured by --line-stats at the automatic view.
TEST(TerrainRender, IntegerDemStepsAreSmoothedAwayFromTheCreases) {
  terrain::test::ScratchDir dir;
  double flat[2] = {0, 0}, valley[2] = {0, 0};
  const char* mode[2] = {"auto", "off"};
  auto share = [](const std::string& out, const std::string& key) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(out, m, std::regex("crease " + key + ": ([0-9.]+)"))) << key;
    return m.empty() ? -1.0 : std::stod(m[1]);
  };
  for (int i = 0; i < 2; ++i) {
    const std::string mesh = dir.path(std::string(mode[i]) + ".ply"),
                      dv = dir.path(std::string(mode[i]) + ".dv");
    const auto m = run(tool("dem2mesh") + " " + data("med_01_01_10m.tif") + " " + mesh +
                       " --dequantize " + mode[i] + " -v");
    ASSERT_EQ(m.exit_code, 0) << m.err;
    EXPECT_EQ(m.err.find("integer heights: steps smoothed") != std::string::npos, i == 0) << m.err;
    ASSERT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --breach 10 -q").exit_code, 0);
    const auto r = run(tool("terrain-render") + " frame " + mesh + " " + dv + " -o " +
                       dir.path("f.png") + " --line-stats");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    flat[i] = share(r.out, "flat share"), valley[i] = share(r.out, "valley share");
    if (i == 0) {
      // Every branch (--crease-links all): the tracks down the planes come back, twice the
      // ink (9584 px against 4481), and a lower valley share (0.80).
      const auto k = run(tool("terrain-render") + " frame " + mesh + " " + dv + " -o " +
                         dir.path("k.png") + " --line-stats --crease-links all");
      ASSERT_EQ(k.exit_code, 0) << k.err;
      EXPECT_GT(share(k.out, "length px"), 1.5 * share(r.out, "length px"));
      EXPECT_LT(share(k.out, "valley share"), valley[0] - 0.05);
    }
  }
  // Dequantized: 0.029 and 0.894; as stored: 0.647 and 0.564.
  EXPECT_LT(flat[0], 0.05) << "dequantized";
  EXPECT_GT(valley[0], 0.8) << "dequantized";
  EXPECT_GT(flat[1], 0.5) << "as stored";
  EXPECT_GT(valley[0], valley[1] + 0.2);
}

// Issue 38: channel initiation is an area (--min-area, m^2), not a count of drainage points,
// so the same terrain drained at 10 m and at 5 m draws the same creases. The demo's Mount
// St. Helens mesh, drained at both spacings (--breach 10, as the demo), rendered at the
// automatic view and at the demo's shaded view: at least 90 % of each picture's crease ink
// lies within 2 px of the other's. Counting points instead, as before (100 of them, 0.25 ha
// at 5 m: --min-area 2500 on the 5 m network, and no contributing-width rule) draws hillside
// hollows the 10 m network does not: its ink lies markedly less near the 10 m picture's.
// The page's channel selection (--page-min-area, 2-3 ha at these views) is off here: it
// would raise the points rule's 0.25 ha to the page's area, and this test is about
// --min-area (the page's rule has its own tests, StrokesFollowThePageNotTheMesh*).
TEST(CreaseLines, TenAndFiveMetreNetworksAgree) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"),
                    render = tool("terrain-render") + " frame " + mesh + " ";
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 50 -q")
                .exit_code,
            0);
  for (const char* spacing : {"10", "5"}) {
    const auto b = run(tool("build-drainage") + " " + mesh + " " +
                       dir.path(std::string("d") + spacing + ".dv") + " --spacing " + spacing +
                       " --breach 10 -q");
    ASSERT_EQ(b.exit_code, 0) << b.err;
  }
  for (const std::string view : {"", "--view-az 160 --view-alt 35"}) {
    SCOPED_TRACE(view);
    auto draw = [&](const std::string& dv, const std::string& options) {
      const std::string png = dir.path("x.png");
      const auto r = run(render + dir.path(dv) + " -o " + png +
                         " --layers mask,creases --page-min-area 0 " + view + " " + options);
      EXPECT_EQ(r.exit_code, 0) << r.err;
      return terrain::test::ink_of(png);
    };
    const auto ten = draw("d10.dv", ""), five = draw("d5.dv", "");
    // The rules before: 100 points, no contributing-width rule.
    const auto ten_points = draw("d10.dv", "--min-drainage-width 0"),
               five_points = draw("d5.dv", "--min-area 2500 --min-drainage-width 0");
    ASSERT_GT(terrain::test::count(ten), 5000u);
    const double a = terrain::test::near_share(ten, five, 2),
                 b = terrain::test::near_share(five, ten, 2);
    const double c = terrain::test::near_share(five_points, ten_points, 2);
    std::cout << "10 m ink near 5 m ink " << a << ", 5 m near 10 m " << b << " ("
              << terrain::test::count(ten) << ", " << terrain::test::count(five)
              << " px); 5 m at 100 points near 10 m " << c << " ("
              << terrain::test::count(five_points) << " px)\n";
    EXPECT_GE(a, 0.9);
    EXPECT_GE(b, 0.9);
    EXPECT_LT(c, b - 0.05);  // measured: 0.72 and 0.82, against 0.94 and 0.91
  }
}

// Issue 50: density set by the page. MSH meshed at 50 m and at 25 m, drained alike, drawn
// at one camera (the 50 m mesh's automatic view): the stroke rule is in metres and pixels
// at the page scale and channels are selected by the page, so both draw about as many
// strokes (within 25 %, the issue's target) and as much ink (15 %); the rules as they were
// (4 and 1 mesh spacings, channels from 1 ha) drew markedly more strokes on the finer mesh.
TEST(TerrainRender, StrokesFollowThePageNotTheMesh) {
  terrain::test::ScratchDir dir;
  auto value = [](const std::string& out, const std::string& key) {
    const std::smatch m = [&] {
      std::smatch x;
      std::regex_search(out, x, std::regex(key + ": ([-0-9.]+)"));
      return x;
    }();
    EXPECT_FALSE(m.empty()) << key << " in\n" << out;
    return m.empty() ? -1.0 : std::stod(m[1]);
  };
  for (const char* sp : {"50", "25"}) {
    const std::string m = dir.path(std::string("m") + sp + ".ply"),
                      dv = dir.path(std::string("m") + sp + ".dv");
    ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + m +
                  " --spacing " + sp + " -q")
                  .exit_code,
              0);
    ASSERT_EQ(run(tool("build-drainage") + " " + m + " " + dv + " --spacing 20 -q").exit_code, 0);
  }
  auto frame = [&](const std::string& sp, const std::string& options) {
    const auto r = run(tool("terrain-render") + " frame " + dir.path("m" + sp + ".ply") + " " +
                       dir.path("m" + sp + ".dv") + " -o " + dir.path("f.png") +
                       " --size 640x360 --line-stats " + options);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.out;
  };
  const std::string coarse = frame("50", "");
  std::smatch eye;
  ASSERT_TRUE(std::regex_search(coarse, eye, std::regex("eye: ([-0-9.]+) ([-0-9.]+) ([-0-9.]+)")));
  const std::string camera =
      " --eye " + eye[1].str() + " " + eye[2].str() + " " + eye[3].str() +
      " --view-az 270 --view-alt 50 --light-az 225 --light-alt 45 --exaggeration 1";
  ASSERT_NE(coarse.find("view: az 270 alt 50"), std::string::npos) << coarse;
  ASSERT_NE(coarse.find("light: az 225 alt 45"), std::string::npos) << coarse;
  const std::string old = " --crease-min-stroke-px 0 --crease-bridge-px 0 --page-min-area 0";
  const std::string fine = frame("25", camera),
                    fine_old =
                        frame("25", camera + old + " --crease-min-stroke 100 --crease-bridge 25"),
                    coarse_old =
                        frame("50", camera + old + " --crease-min-stroke 200 --crease-bridge 50");
  const double s0 = value(coarse, "crease strokes"), s1 = value(fine, "crease strokes"),
               s_old = value(fine_old, "crease strokes"),
               s0_old = value(coarse_old, "crease strokes");
  const double i0 = value(coarse, "crease length px"), i1 = value(fine, "crease length px");
  std::cout << "strokes: 50 m " << s0 << ", 25 m " << s1 << " (the old rules: " << s0_old << ", "
            << s_old << "); ink " << i0 << ", " << i1 << " px\n";
  ASSERT_GT(s0, 10.0);
  EXPECT_LE(std::abs(s1 - s0), 0.25 * s0);
  EXPECT_LE(std::abs(i1 - i0), 0.15 * i0);
  EXPECT_GT(s_old - s0_old, 0.4 * s0_old);
}

// The same on an analytic surface (a slope with valleys at four wavelengths, 10 m, no
// CRS), meshed at 40 m and at 20 m: about as many strokes at one camera with the rule in
// metres and page pixels; with it in mesh spacings the finer mesh drew more.
TEST(TerrainRender, StrokesFollowThePageNotTheMeshOnAnAnalyticSurface) {
  terrain::test::ScratchDir dir;
  terrain::Georef geo;
  geo.x0 = 500000, geo.y0 = 5000000, geo.dx = geo.dy = 10;
  terrain::Grid dem(301, 301, geo);
  for (std::size_t r = 0; r < 301; ++r)
    for (std::size_t c = 0; c < 301; ++c) {
      const double x = 10.0 * double(c), y = 10.0 * double(r);
      dem.at(r, c) = float(400 - 0.1 * y + 15 * std::sin(x / 230) + 8 * std::sin((x + y) / 97) +
                           5 * std::sin((x - 2 * y) / 61) + 3 * std::sin((3 * x + y) / 37));
    }
  terrain::write_geotiff(dem, dir.path("dem.tif"));
  auto strokes = [](const std::string& out) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(out, m, std::regex("crease strokes: ([0-9]+)"))) << out;
    return m.empty() ? -1.0 : std::stod(m[1]);
  };
  for (const char* sp : {"40", "20"}) {
    const std::string m = dir.path(std::string("m") + sp + ".ply"),
                      dv = dir.path(std::string("m") + sp + ".dv");
    ASSERT_EQ(
        run(tool("dem2mesh") + " " + dir.path("dem.tif") + " " + m + " --spacing " + sp + " -q")
            .exit_code,
        0);
    ASSERT_EQ(run(tool("build-drainage") + " " + m + " " + dv + " -q").exit_code, 0);
  }
  const std::string camera =
      " --eye 501500 4996000 2500 --view-az 0 --view-alt 40 --light-az 315 --light-alt 45 "
      "--exaggeration 1 --size 640x360 --line-stats -o " +
      dir.path("f.png");
  auto frame = [&](const std::string& sp, const std::string& options) {
    const auto r = run(tool("terrain-render") + " frame " + dir.path("m" + sp + ".ply") + " " +
                       dir.path("m" + sp + ".dv") + camera + options);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return strokes(r.out);
  };
  const double
      coarse = frame("40", ""),
      fine = frame("20", ""),
      fine_old = frame(
          "20",
          " --crease-min-stroke 80 --crease-min-stroke-px 0 --crease-bridge 20 --crease-bridge-px 0"
          " --page-min-area 0"),
      coarse_old = frame("40",
                         " --crease-min-stroke 160 --crease-min-stroke-px 0 --crease-bridge 40 "
                         "--crease-bridge-px 0 --page-min-area 0");
  std::cout << "strokes: 40 m " << coarse << ", 20 m " << fine << "; in mesh spacings "
            << coarse_old << ", " << fine_old << "\n";
  ASSERT_GT(coarse, 10.0);
  EXPECT_LE(std::abs(fine - coarse), 0.25 * coarse);
  EXPECT_GT(fine_old - coarse_old, 0.25 * coarse_old);
}

// Issue 51: --layers hachures. MSH at its automatic view, 480 x 270: the PNG carries
// hachure ink on the terrain and none on the background; the SVG carries them as their own
// Inkscape layer, one path per hachure, and rasterized (rsvg-convert) its ink lies where
// the PNG's does (>= 90 % within 1 px both ways: one trace drawn twice); the spacing sets
// the ink (the default 3 draws more than 1.5 times --hachure-spacing 6's).
TEST(TerrainRender, HachuresAreALayerOfPngAndSvg) {
  Inputs in;
  const std::string frame = tool("terrain-render") + " frame " + in.mesh + " " + in.dv +
                            " --size 480x270 --layers mask,hachures -q -o ";
  ASSERT_EQ(run(frame + in.dir.path("h.png")).exit_code, 0);
  ASSERT_EQ(run(frame + in.dir.path("h.svg")).exit_code, 0);
  ASSERT_EQ(run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv +
                " --size 480x270 --layers mask -q -o " + in.dir.path("m.png"))
                .exit_code,
            0);
  const auto png = terrain::test::ink_of(in.dir.path("h.png"));
  EXPECT_GT(terrain::test::count(png), 2000u);
  OIIO::ImageBuf mask(in.dir.path("m.png"));  // the terrain: the mask's white
  std::size_t off_terrain = 0;
  for (int y = 0; y < png.h; ++y)
    for (int x = 0; x < png.w; ++x) {
      float px[3];
      mask.getpixel(x, y, px, 3);
      off_terrain +=
          png.on[std::size_t(y * png.w + x)] && px[0] < 0.95f;  // background (0xdd = 0.87)
    }
  EXPECT_LT(off_terrain, 20u);  // a round cap's anti-aliased rim at the terrain's edge at most
  const std::string svg = terrain::test::file_bytes(in.dir.path("h.svg"));
  const auto at = svg.find("inkscape:label=\"hachures\"");
  ASSERT_NE(at, std::string::npos);
  EXPECT_GT(std::count(svg.begin() + long(at), svg.end(), 'M'),
            50);  // paths (each starts with a move)
  ASSERT_EQ(
      run("rsvg-convert -b '#dde4ec' " + in.dir.path("h.svg") + " -o " + in.dir.path("svg.png"))
          .exit_code,
      0);
  const auto drawn = terrain::test::ink_of(in.dir.path("svg.png"));
  EXPECT_GE(terrain::test::near_share(png, drawn, 1), 0.9);
  EXPECT_GE(terrain::test::near_share(drawn, png, 1), 0.9);
  ASSERT_EQ(run(frame + in.dir.path("sparse.png") + " --hachure-spacing 6").exit_code, 0);
  EXPECT_GT(double(terrain::test::count(png)),
            1.5 * double(terrain::test::count(terrain::test::ink_of(in.dir.path("sparse.png")))));
}

// --view top is a map: orthographic, north up, at --map-scale metres a pixel. The terrain's
// pixels (the mask) cover exactly the mesh's extent put through the printed geotransform,
// whatever the heights (a perspective view from above would spread the high ground); GDAL
// reads the same geotransform from the PNG's world file and its CRS from its PAM file
// (NAME.png.aux.xml); the SVG names it and the EPSG
// code; --map-scale without the orthographic view is refused.
TEST(TerrainRender, TopViewIsAMapInMapCoordinates) {
  Inputs in;
  const std::string frame = tool("terrain-render") + " frame " + in.mesh + " " + in.dv +
                            " --view top --map-scale 10 --layers mask --size 640x480 -o ";
  const auto f = run(frame + in.dir.path("t.png"));
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_NE(f.out.find("view: orthographic, az 0 alt 90, 10 m a pixel"), std::string::npos)
      << f.out;
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(f.out, m, std::regex(R"(geotransform: (\S+) (\S+) 0 (\S+) 0 (\S+))")))
      << f.out;
  const double x0 = std::stod(m[1]), sx = std::stod(m[2]), y0 = std::stod(m[3]),
               sy = std::stod(m[4]);
  EXPECT_EQ(sx, 10.0);
  EXPECT_EQ(sy, -10.0);
  {
    const auto ds = opened(in.dir.path("t.png"), GDAL_OF_RASTER);
    ASSERT_TRUE(ds);
    double gt[6];
    ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);  // from t.pgw
    // and its CRS from t.png.aux.xml, the mesh's (NAD83 / UTM zone 10N, EPSG:26910)
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    ASSERT_NE(srs, nullptr);
    EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "26910");
    EXPECT_NEAR(gt[0], x0, 1e-3);
    EXPECT_NEAR(gt[3], y0, 1e-3);
    EXPECT_DOUBLE_EQ(gt[1], 10.0);
    EXPECT_DOUBLE_EQ(gt[5], -10.0);
  }
  const terrain::GridMesh mesh = terrain::read_mesh_ply(in.mesh);
  const double west = mesh.geo.origin_x, north = mesh.geo.origin_y;
  const double east = west + double(mesh.topo.cols - 1) * mesh.geo.dx,
               south = north - double(mesh.topo.rows - 1) * mesh.geo.dy;
  OIIO::ImageBuf img(in.dir.path("t.png"));
  ASSERT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::UINT8));
  const int w = img.spec().width, h = img.spec().height;
  std::vector<std::uint8_t> px(std::size_t(w * h * img.spec().nchannels));
  img.get_pixels(img.roi(), OIIO::TypeDesc::UINT8, px.data());
  const int nc = img.spec().nchannels;
  auto background = [&](int u, int v) {
    for (int c = 0; c < 3; ++c)
      if (px[std::size_t((v * w + u) * nc + c)] != px[std::size_t(c)])
        return false;  // the corner's colour
    return true;
  };
  int u_lo = w, u_hi = -1, v_lo = h, v_hi = -1;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      if (!background(u, v))
        u_lo = std::min(u_lo, u), u_hi = std::max(u_hi, u), v_lo = std::min(v_lo, v),
        v_hi = std::max(v_hi, v);
  EXPECT_NEAR(x0 + u_lo * sx, west, 1.5 * sx);
  EXPECT_NEAR(x0 + (u_hi + 1) * sx, east, 1.5 * sx);
  EXPECT_NEAR(y0 + v_lo * sy, north, 1.5 * sx);
  EXPECT_NEAR(y0 + (v_hi + 1) * sy, south, 1.5 * sx);

  ASSERT_EQ(run(frame + in.dir.path("t.svg")).exit_code, 0);
  const std::string svg = terrain::test::file_bytes(in.dir.path("t.svg"));
  EXPECT_NE(
      svg.find(fmt::format("north up, 10 m a pixel; geotransform {:.3f} 10 0 {:.3f} 0 -10; EPSG:{}",
                           x0, y0, mesh.geo.epsg)),
      std::string::npos);
  const auto bad = run(tool("terrain-render") + " frame " + in.mesh + " --map-scale 10 -o " +
                       in.dir.path("b.png"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--map-scale needs the orthographic view"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(in.dir.path("b.png")));
  // A panned map (--view top with the eye, as terrain-view saves one): centred under the eye,
  // 500 m east of the image's centre above, its geotransform 500 m east; looking elsewhere
  // than straight down, north up, it is not a map.
  const std::string eye =
      fmt::format(" --eye {:.3f} {:.3f} 9000", x0 + 320 * 10 + 500, y0 - 240 * 10);
  const auto panned = run(frame + in.dir.path("p.png") + eye);
  ASSERT_EQ(panned.exit_code, 0) << panned.err;
  EXPECT_NE(panned.out.find(fmt::format("geotransform: {:.3f} 10 0 {:.3f} 0 -10", x0 + 500, y0)),
            std::string::npos)
      << panned.out;
  const auto oblique = run(frame + in.dir.path("o.png") + eye + " --view-alt 60");
  EXPECT_NE(oblique.exit_code, 0);
  EXPECT_NE(oblique.err.find("--map-scale needs the orthographic view"), std::string::npos)
      << oblique.err;
}

// The top view's lines as a GeoPackage (-o map.gpkg): a styled line layer per drawn layer,
// in the mesh's CRS, each crease with the basin share its width was drawn from; the creases'
// vertices drawn at half strength or more, taken back to pixels through the map's
// geotransform, lie on the creases the PNG of the same frame draws (within 1 px).
TEST(TerrainRender, TopViewLinesAsAGeoPackage) {
  Inputs in;
  const std::string frame = map_frame(in);
  ASSERT_EQ(run(frame + in.dir.path("m.png")).exit_code, 0);
  const auto g = run(frame + in.dir.path("m.gpkg"));
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const auto png = opened(in.dir.path("m.png"), GDAL_OF_RASTER);
  const auto gpkg = opened(in.dir.path("m.gpkg"), GDAL_OF_VECTOR);
  ASSERT_TRUE(png && gpkg);
  double gt[6];
  ASSERT_EQ(png->GetGeoTransform(gt), CE_None);
  OGRLayer* creases = gpkg->GetLayerByName("creases");
  ASSERT_NE(creases, nullptr);
  EXPECT_STREQ(creases->GetSpatialRef()->GetAuthorityCode(nullptr), "26910");
  OGRLayer* styles = gpkg->GetLayerByName("layer_styles");
  ASSERT_NE(styles, nullptr);
  styles->SetAttributeFilter("f_table_name = 'creases'");
  EXPECT_EQ(styles->GetFeatureCount(), 1);
  const terrain::test::Ink ink = terrain::test::ink_of(in.dir.path("m.png"));
  std::size_t vertices = 0, on_ink = 0;
  const double mm = 25.4 / 96;  // a pixel at --dpi 96
  for (const auto& f : *creases) {
    // Widths from 1 to 3 px by the square root of the basin share (the line's largest; the
    // width its mean): within the rule's bounds for the share written beside it.
    const double share = f->GetFieldAsDouble("flow_share"), width = f->GetFieldAsDouble("width_mm");
    EXPECT_TRUE(share >= 0 && share <= 1) << share;
    EXPECT_GE(f->GetFieldAsInteger("strahler"), 1);  // on the drawn network (crease_orders)
    EXPECT_GE(width, (1.0 - 0.125) * mm);            // a stroke's width quantised to 1/4 px
    EXPECT_LE(width, (1.0 + 2.0 * std::sqrt(share) + 0.125) * mm) << share;
    // A line drawn faint (a bridged gap at the lower opacity of its two sides, a fade) is
    // below the ink threshold of the PNG: the lines drawn at half strength or more are ink.
    if (f->GetFieldAsDouble("opacity") < 0.5) continue;
    const OGRLineString* line = f->GetGeometryRef()->toLineString();
    for (int k = 0; k < line->getNumPoints(); ++k, ++vertices) {
      const int u = int(std::floor((line->getX(k) - gt[0]) / gt[1])),
                v = int(std::floor((line->getY(k) - gt[3]) / gt[5]));
      bool hit = false;
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du)
          hit = hit || (u + du >= 0 && v + dv >= 0 && u + du < ink.w && v + dv < ink.h &&
                        ink.on[std::size_t((v + dv) * ink.w + u + du)]);
      on_ink += hit;
    }
  }
  EXPECT_GT(vertices, 100u);
  EXPECT_GE(double(on_ink), 0.95 * double(vertices)) << on_ink << " of " << vertices;
  // Not a map: refused, nothing written.
  const auto persp = run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " +
                         in.dir.path("p.gpkg"));
  EXPECT_EQ(persp.exit_code, 1);
  EXPECT_NE(persp.err.find("give --view top"), std::string::npos) << persp.err;
  EXPECT_FALSE(std::filesystem::exists(in.dir.path("p.gpkg")));
}

// The top view as a GeoTIFF (-o map.tif; its background none unless given): GDAL reads its CRS and
// geotransform (the PNG's), its 4th band is alpha; the pixels the opaque PNG paints with
// the background are transparent, the terrain's are opaque with the PNG's colours.
TEST(TerrainRender, TopViewGeoTiffIsATransparentMap) {
  Inputs in;
  const std::string frame = map_frame(in);
  ASSERT_EQ(run(frame + in.dir.path("o.png")).exit_code, 0);
  const auto t = run(frame + in.dir.path("t.tif"));  // transparent: a GeoTIFF's default
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_FALSE(std::filesystem::exists(in.dir.path("t.pgw")));  // inside the GeoTIFF
  const auto tif = opened(in.dir.path("t.tif"), GDAL_OF_RASTER);
  const auto png = opened(in.dir.path("o.png"), GDAL_OF_RASTER);
  ASSERT_TRUE(tif && png);
  ASSERT_EQ(tif->GetRasterCount(), 4);
  EXPECT_EQ(tif->GetRasterBand(4)->GetColorInterpretation(), GCI_AlphaBand);
  ASSERT_NE(tif->GetSpatialRef(), nullptr);
  EXPECT_STREQ(tif->GetSpatialRef()->GetAuthorityCode(nullptr), "26910");
  double a[6], b[6];
  ASSERT_EQ(tif->GetGeoTransform(a), CE_None);
  ASSERT_EQ(png->GetGeoTransform(b), CE_None);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(a[k], b[k], 1e-3) << k;  // the .pgw: 10 digits
  const int w = 640, h = 480;
  std::vector<std::uint8_t> tp(std::size_t(w * h * 4)), op(std::size_t(w * h * 4));
  int bands[] = {1, 2, 3, 4};
  ASSERT_EQ(
      tif->RasterIO(GF_Read, 0, 0, w, h, tp.data(), w, h, GDT_Byte, 4, bands, 4, w * 4, 1, nullptr),
      CE_None);
  ASSERT_EQ(
      png->RasterIO(GF_Read, 0, 0, w, h, op.data(), w, h, GDT_Byte, 4, bands, 4, w * 4, 1, nullptr),
      CE_None);
  std::size_t background = 0, opaque = 0, wrong = 0;
  for (std::size_t i = 0; i < std::size_t(w * h); ++i) {
    const bool bg = op[4 * i] == op[0] && op[4 * i + 1] == op[1] && op[4 * i + 2] == op[2];
    const std::uint8_t alpha = tp[4 * i + 3];
    background += bg;
    if (bg) wrong += alpha != 0;
    if (alpha == 255) {
      ++opaque;
      for (int c = 0; c < 3; ++c) wrong += std::abs(tp[4 * i + c] - op[4 * i + c]) > 1;
    }
  }
  EXPECT_GT(background, std::size_t(w * h) / 10);  // the map is smaller than the frame
  EXPECT_GT(opaque, std::size_t(w * h) / 4);
  EXPECT_EQ(wrong, 0u);
  // Without the mask the map is its lines alone: transparent but where a crease covers it.
  ASSERT_EQ(
      run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv +
          " --view top --map-scale 10 --layers creases --size 640x480 -o " + in.dir.path("l.tif"))
          .exit_code,
      0);
  const auto lines = opened(in.dir.path("l.tif"), GDAL_OF_RASTER);
  ASSERT_TRUE(lines);
  std::vector<std::uint8_t> alpha(std::size_t(w * h));
  ASSERT_EQ(
      lines->GetRasterBand(4)->RasterIO(GF_Read, 0, 0, w, h, alpha.data(), w, h, GDT_Byte, 0, 0),
      CE_None);
  const std::size_t inked =
      std::size_t(std::count_if(alpha.begin(), alpha.end(), [](std::uint8_t v) { return v > 0; }));
  EXPECT_GT(inked, 100u);
  EXPECT_LT(inked, opaque / 10);
}

// A mesh's plan-view hachure map (terrain-inspect export --layers hachures): the GeoPackage
// holds one line feature a hachure, in the mesh's CRS and extent, with slope and tone; its
// vertices, put through the printed geotransform, lie on the SVG's ink (two paths: OGR's
// coordinates and cairo's drawing); rows carry their form line.
TEST(TerrainInspect, HachureMapsInMapCoordinates) {
  Inputs in;
  const std::string ex = tool("terrain-inspect") + " export " + in.mesh + " --scale 10 ";
  const auto g = run(ex + "--to gpkg -o " + in.dir.path("h.gpkg"));
  ASSERT_EQ(g.exit_code, 0) << g.err;
  ASSERT_EQ(run(ex + "--to svg -o " + in.dir.path("h.svg")).exit_code, 0);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(g.out, m, std::regex(R"(hachures: (\d+))"))) << g.out;
  const long n = std::stol(m[1]);
  ASSERT_TRUE(
      std::regex_search(g.out, m, std::regex(R"(geotransform: (\S+) (\S+) 0 (\S+) 0 (\S+))")))
      << g.out;
  const double x0 = std::stod(m[1]), sx = std::stod(m[2]), y0 = std::stod(m[3]),
               sy = std::stod(m[4]);
  EXPECT_EQ(sx, 10.0);
  EXPECT_EQ(sy, -10.0);
  EXPECT_GT(n, 100);

  const terrain::GridMesh mesh = terrain::read_mesh_ply(in.mesh);
  const double west = mesh.geo.origin_x, north = mesh.geo.origin_y;
  const double east = west + double(mesh.topo.cols - 1) * mesh.geo.dx,
               south = north - double(mesh.topo.rows - 1) * mesh.geo.dy;
  const auto ds = opened(in.dir.path("h.gpkg"), GDAL_OF_VECTOR);
  ASSERT_TRUE(ds);
  OGRLayer* layer = ds->GetLayerByName("hachures");
  ASSERT_TRUE(layer);
  EXPECT_EQ(layer->GetFeatureCount(), n);
  ASSERT_TRUE(layer->GetSpatialRef());
  EXPECT_EQ(std::string(layer->GetSpatialRef()->GetAuthorityCode(nullptr)),
            std::to_string(mesh.geo.epsg));
  rsvg_ink(in.dir.path("h.svg"), in.dir.path("svg.png"));
  const auto ink = terrain::test::ink_of(in.dir.path("svg.png"));
  std::size_t vertices = 0, on_ink = 0;
  for (auto& f : *layer) {
    const double slope = f->GetFieldAsDouble("slope_deg"), tone = f->GetFieldAsDouble("tone");
    EXPECT_TRUE(slope >= 2.8 && slope < 90)
        << slope;  // hachures end where the slope falls under 0.05 rad
    EXPECT_TRUE(tone >= 0 && tone <= 1) << tone;
    EXPECT_GT(f->GetFieldAsDouble("length_m"), 0);
    const OGRLineString* line = f->GetGeometryRef()->toLineString();
    for (int k = 0; k < line->getNumPoints(); ++k) {
      const double x = line->getX(k), y = line->getY(k);
      EXPECT_TRUE(x >= west && x <= east && y >= south && y <= north) << x << " " << y;
      const int u = int((x - x0) / sx), v = int((y - y0) / sy);
      ++vertices;
      bool hit = false;
      for (int dv = -1; dv <= 1; ++dv)
        for (int du = -1; du <= 1; ++du) {
          const int uu = u + du, vv = v + dv;
          hit |= uu >= 0 && vv >= 0 && uu < ink.w && vv < ink.h &&
                 ink.on[std::size_t(vv * ink.w + uu)];
        }
      on_ink += hit;
    }
  }
  EXPECT_GE(double(on_ink), 0.97 * double(vertices));

  const auto r = run(ex + "--to gpkg --hachure-style rows -o " + in.dir.path("r.gpkg"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(form lines: every (\S+) m)"))) << r.out;
  const double interval = std::stod(m[1]);
  const auto rows = opened(in.dir.path("r.gpkg"), GDAL_OF_VECTOR);
  ASSERT_TRUE(rows);
  for (auto& f : *rows->GetLayerByName("hachures")) {
    const double row = f->GetFieldAsDouble("row_m");
    EXPECT_NEAR(row / interval, std::round(row / interval), 1e-9);
    EXPECT_GT(row, 0);
  }
}

// A plan map with its .dv draws the ridge lines (issue 64): on a tent 10 km long whose
// flanks fall 30 % from its crest to valleys 2.5 km away on both sides, the map's ridges layer
// (GeoPackage, SVG) lies along the crest over most of its length, and the hachures stop at it:
// every hachure lies on one side of the crest and keeps off the ridge line's ink (2.2 px wide at 25
// m a pixel: 27.5 m from its centre, less the half pixel the lines are simplified within), and both
// sides have hachures. Without --dv the map is as before (no ridges layer). The tent's mesh
// (dir/tent.ply, 100 m cells) and its drainage at 50 m (dir/tent.dv); returns the crest's easting.
double make_tent(const terrain::test::ScratchDir& dir) {
  terrain::Georef geo = terrain::read_dem_info(data("logan_utm12n_100m.tif")).geo;
  terrain::Grid g(100, 60, geo);  // 100 m cells
  for (std::size_t r = 0; r < g.rows; ++r)
    for (std::size_t c = 0; c < g.cols; ++c)
      g.at(r, c) =
          float(900 - 0.3 * (2500 - std::abs(2500 - std::abs(double(c) * 100 + 50 - 3000))) -
                0.02 * double(r) * 100);
  terrain::write_geotiff(g, dir.path("tent.tif"));
  EXPECT_EQ(run(tool("dem2mesh") + " " + dir.path("tent.tif") + " " + dir.path("tent.ply") + " -q")
                .exit_code,
            0);
  EXPECT_EQ(run(tool("build-drainage") + " " + dir.path("tent.ply") + " " + dir.path("tent.dv") +
                " --spacing 50 -q")
                .exit_code,
            0);
  return geo.x0 + 3000;
}

TEST(TerrainInspect, PlanMapsDrawTheRidgeLinesAndTheHachuresStopAtThem) {
  terrain::test::ScratchDir dir;
  const double crest = make_tent(dir);
  const std::string mesh = dir.path("tent.ply"), dv = dir.path("tent.dv");
  const std::string ex = tool("terrain-inspect") + " export " + mesh + " --scale 25 ";
  const auto e = run(ex + "--dv " + dv + " --to gpkg -o " + dir.path("t.gpkg"));
  ASSERT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.out.find("ridges: "), std::string::npos) << e.out;
  const auto ds = opened(dir.path("t.gpkg"), GDAL_OF_VECTOR);
  ASSERT_TRUE(ds);
  OGRLayer* ridges = ds->GetLayerByName("ridges");
  ASSERT_TRUE(ridges);
  double along = 0;
  OGRMultiLineString crests;
  for (auto& f : *ridges) {
    crests.addGeometry(f->GetGeometryRef());
    const OGRLineString* line = f->GetGeometryRef()->toLineString();
    for (int k = 0; k < line->getNumPoints(); ++k) EXPECT_NEAR(line->getX(k), crest, 60.0);
    along += line->get_Length();
    EXPECT_GT(f->GetFieldAsDouble("basin_m2"), 1e7);
  }
  EXPECT_GT(along, 7000.0) << "the crest is 10 km long";
  std::size_t west = 0, east = 0;
  for (auto& f : *ds->GetLayerByName("hachures")) {
    const OGRLineString* line = f->GetGeometryRef()->toLineString();
    bool w = false, eo = false;
    for (int k = 0; k < line->getNumPoints(); ++k) (line->getX(k) < crest ? w : eo) = true;
    EXPECT_FALSE(w && eo) << "a hachure crosses the ridge line";
    EXPECT_GT(line->Distance(&crests), 15.0) << "a hachure on the ridge line's ink";
    west += w, east += eo;
  }
  EXPECT_GT(west, 20u);
  EXPECT_GT(east, 20u);
  ASSERT_EQ(run(ex + "--dv " + dv + " --to svg -o " + dir.path("t.svg")).exit_code, 0);
  std::ifstream svg(dir.path("t.svg"));
  const std::string text((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("inkscape:label=\"ridges\""), std::string::npos);
  ASSERT_EQ(run(ex + "--to gpkg -o " + dir.path("plain.gpkg")).exit_code, 0);
  const auto plain = opened(dir.path("plain.gpkg"), GDAL_OF_VECTOR);
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->GetLayerByName("ridges"), nullptr);
  const auto bad = run(ex + "--dv " + mesh + " --to gpkg -o " + dir.path("bad.gpkg"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("is not a drainage database"), std::string::npos) << bad.err;
}

// The default picture's layers in its vector files (issue 64): the tent seen across its crest
// with its .dv, as SVG and PDF: the SVG's layers in drawing order (hachures, creases,
// silhouettes, ridges on top), the ridge line drawn, the skyline's silhouette heavier than
// the composite's band (the depth it hides: the sky), and the PDF the same picture as the SVG
// (>= 90 % of either's ink within 1 px of the other's).
TEST(TerrainRender, TheDefaultPicturesLayersInSvgAndPdf) {
  terrain::test::ScratchDir dir;
  make_tent(dir);
  const std::string frame = tool("terrain-render") + " frame " + dir.path("tent.ply") + " " +
                            dir.path("tent.dv") +
                            " --size 480x270 --view-az 90 --view-alt 10 -q -o ";
  ASSERT_EQ(run(frame + dir.path("t.svg")).exit_code, 0);
  ASSERT_EQ(run(frame + dir.path("t.pdf")).exit_code, 0);
  const std::string svg = terrain::test::file_bytes(dir.path("t.svg"));
  std::vector<std::size_t> at;
  for (const char* layer : {"hachures", "creases", "silhouettes", "ridges"}) {
    at.push_back(svg.find(std::string("inkscape:label=\"") + layer + "\""));
    ASSERT_NE(at.back(), std::string::npos) << layer;
  }
  EXPECT_TRUE(std::is_sorted(at.begin(), at.end()));
  EXPECT_NE(svg.find("<path", at[3]), std::string::npos) << "no ridge line";
  double widest = 0;
  const std::string sil = svg.substr(at[2], at[3] - at[2]);
  const std::regex width(R"(stroke-width[=:]"?([0-9.]+))");
  for (std::sregex_iterator it(sil.begin(), sil.end(), width), end; it != end; ++it)
    widest = std::max(widest, std::stod((*it)[1]));
  EXPECT_GT(widest, 1.8 + 1.0) << "the skyline is drawn no heavier than the band";
  ASSERT_EQ(
      run("rsvg-convert -b white " + dir.path("t.svg") + " -o " + dir.path("svg.png")).exit_code,
      0);
  ASSERT_EQ(
      run("pdftoppm -png -r 96 -singlefile " + dir.path("t.pdf") + " " + dir.path("pdf")).exit_code,
      0);
  const auto a = terrain::test::ink_of(dir.path("svg.png")),
             b = terrain::test::ink_of(dir.path("pdf.png"));
  EXPECT_GT(terrain::test::count(a), 1000u);
  EXPECT_GE(terrain::test::near_share(a, b, 1), 0.9);
  EXPECT_GE(terrain::test::near_share(b, a, 1), 0.9);
}

TEST(TerrainRender, FlowScale) {
  Inputs in;
  const std::string frame = tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " +
                            in.dir.path("f.png") + " --size 160x120 --min-score 0.25";
  auto drawn = [](const std::string& out) {
    const auto at = out.find("crease segments drawn: ");
    EXPECT_NE(at, std::string::npos) << out;
    return at == std::string::npos ? -1.0 : std::stod(out.substr(at + 23));
  };
  const auto log = run(frame), linear = run(frame + " --flow-scale linear");
  ASSERT_EQ(log.exit_code, 0) << log.err;
  ASSERT_EQ(linear.exit_code, 0) << linear.err;
  EXPECT_GT(drawn(log.out), drawn(linear.out));
  EXPECT_GT(drawn(linear.out), 0.0);
  const auto bad = run(frame + " --flow-scale cubic");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--flow-scale: 'cubic' is not one of log,linear"), std::string::npos)
      << bad.err;
}

// --line-stats: every key with a value in range, no more strokes than segments the DM pass
// drew; the seed rules draw more of their length near the boundary; no more silhouette
// pieces or pixels than without the piece rule;
// batch writes line_stats.csv (a row per frame) and the flicker; no .dv is a usage error.
TEST(TerrainRender, LineStats) {
  Inputs in;
  auto value = [](const std::string& out, const std::string& key) {
    const auto at = out.find(key + ": ");
    EXPECT_NE(at, std::string::npos) << key << " in\n" << out;
    return at == std::string::npos ? -1.0 : std::stod(out.substr(at + key.size() + 2));
  };
  const std::string frame = tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " +
                            in.dir.path("f.png") + " --size 320x240 --line-stats";
  const auto ours = run(frame), seed = run(frame + " --seed-rules");
  ASSERT_EQ(ours.exit_code, 0) << ours.err;
  ASSERT_EQ(seed.exit_code, 0) << seed.err;
  for (const auto* r : {&ours, &seed}) {
    EXPECT_GT(value(r->out, "crease length px"), 0.0);
    for (const char* share : {"crease boundary share", "crease flat share", "crease valley share",
                              "crease connected share"}) {
      EXPECT_GE(value(r->out, share), 0.0);
      EXPECT_LE(value(r->out, share), 1.0);
    }
    EXPECT_GE(value(r->out, "crease strokes"), 1.0);
    EXPECT_LE(value(r->out, "crease strokes"),
              value(r->out, "crease segments drawn"));  // a stroke has a segment
    // Each stroke weighs its mean opacity, in (0, 1].
    EXPECT_GT(value(r->out, "crease strokes, opacity-weighted"), 0.0);
    EXPECT_LE(value(r->out, "crease strokes, opacity-weighted"),
              value(r->out, "crease strokes") + 0.05);
    EXPECT_GE(value(r->out, "crease mean stroke px, opacity-weighted"),
              value(r->out, "crease mean stroke px") - 0.1);
  }
  EXPECT_GT(value(seed.out, "crease boundary share"), value(ours.out, "crease boundary share"));
  // Silhouettes: the piece rule only removes or fades pieces; each piece drawn is at least
  // three quarters of the minimum (8 % of the 240 rows), and the mean weighs each piece by its
  // opacity (at least the plain mean).
  const auto every = run(frame + " --silhouette-min-length 0");
  ASSERT_EQ(every.exit_code, 0) << every.err;
  EXPECT_GE(value(ours.out, "silhouette pieces"), 1.0);
  EXPECT_GE(value(ours.out, "silhouette mean piece px"),
            value(ours.out, "silhouette px") / value(ours.out, "silhouette pieces") - 0.1);
  EXPECT_GE(value(ours.out, "silhouette mean piece px"), 0.75 * 0.08 * 240 - 0.1);
  EXPECT_LE(value(ours.out, "silhouette pieces"), value(every.out, "silhouette pieces"));
  EXPECT_LE(value(ours.out, "silhouette px"), value(every.out, "silhouette px"));

  const std::string csv = in.dir.path("frames.csv"), out = in.dir.path("frames");
  ASSERT_EQ(run(tool("terrain-render") +
                " path --from 561500 5114000 2800 --to 563500 5116000 2700 --frames 3 -o " + csv)
                .exit_code,
            0);
  const auto b = run(tool("terrain-render") + " batch " + in.mesh + " " + in.dv + " " + csv +
                     " -o " + out + " --size 160x120 -q --line-stats");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  std::ifstream t(out + "/line_stats.csv");
  std::stringstream all;
  all << t.rdbuf();
  EXPECT_EQ(lines(all.str()), 4u) << all.str();
  EXPECT_EQ(all.str().rfind(
                "frame,length_px,boundary_share,flat_share,valley_share,strokes,mean_stroke_px,"
                "silhouette_px,silhouette_pieces,weighted_strokes,weighted_mean_stroke_px,"
                "connected_share,hachures,"
                "hachure_length_px,hachure_along_share,hachure_spacing_share\n",
                0),
            0u);
  const double f = value(b.out, "crease flicker");
  EXPECT_GE(f, 0.0);
  EXPECT_LE(f, 1.0);

  const auto bad = run(tool("terrain-render") + " frame " + in.mesh + " -o " +
                       in.dir.path("g.png") + " --line-stats");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--line-stats"), std::string::npos) << bad.err;
}

// A .dv made from another mesh (here: a crop of it) renders, with one warning naming both
// extents; -q silences it.
TEST(TerrainRender, DrainageOfAnotherMeshIsAWarning) {
  Inputs in;
  const std::string crop = in.dir.path("crop.ply"), crop_dv = in.dir.path("crop.dv");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + crop +
                " --spacing 50 --center 562500 5117000 --size 1000 1000 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("build-drainage") + " " + crop + " " + crop_dv + " --spacing 25 -q").exit_code,
            0);
  const std::string frame = tool("terrain-render") + " frame " + in.mesh + " " + crop_dv + " -o " +
                            in.dir.path("f.png") + " --size 64x48";
  const auto r = run(frame);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("it was not made from this mesh"), std::string::npos) << r.err;
  EXPECT_EQ(run(frame + " -q").err, "");
  const auto same = run(tool("terrain-render") + " frame " + in.mesh + " " + in.dv + " -o " +
                        in.dir.path("g.png") + " --size 64x48");
  EXPECT_EQ(same.exit_code, 0);
  EXPECT_EQ(same.err.find("not made from this mesh"), std::string::npos) << same.err;
}

// A .dv sampled from another surface of the same extent (the terrain meshed at 50 m,
// drawn on it meshed at 30 m) renders, with one warning: its points lie off this mesh's PN
// surface, so its creases do not follow this surface's valleys.
TEST(TerrainRender, DrainageOfAnotherSurfaceIsAWarning) {
  Inputs in;
  const std::string m30 = in.dir.path("m30.ply");
  ASSERT_EQ(
      run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + m30 + " --spacing 30 -q")
          .exit_code,
      0);
  const auto r = run(tool("terrain-render") + " frame " + m30 + " " + in.dv + " -o " +
                     in.dir.path("f.png") + " --size 64x48");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("off this mesh's PN surface"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sampled from another surface"), std::string::npos) << r.err;
}

TEST(TerrainRender, BadFrameListsNameTheLine) {
  Inputs in;
  const std::string csv = in.dir.path("bad.csv"), out = in.dir.path("frames");
  write(csv, "view_az,view_alt\n10,20\n30\n");
  auto r = run(tool("terrain-render") + " batch " + in.mesh + " " + in.dv + " " + csv + " -o " +
               out + " --size 64x64");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("bad.csv:3: expected 2 fields, found 1"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out + "/frame_00000.png"));

  write(csv, "view_az,zoom\n10,2\n");
  r = run(tool("terrain-render") + " batch " + in.mesh + " " + csv + " -o " + out +
          " --size 64x64");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(lines(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("bad.csv:1: unknown column 'zoom'"), std::string::npos) << r.err;
}

TEST(TerrainRender, BadInputGivesOneLine) {
  Inputs in;
  for (const std::string& args :
       {std::string("frame ") + in.dir.path("missing.ply") + " -o " + in.dir.path("x.png"),
        std::string("frame ") + in.mesh + " " + in.mesh + " -o " +
            in.dir.path("x.png"),  // not a .dv
        std::string("frame ") + in.mesh + " -o " + in.dir.path("x.png") +
            " --layers shaded,contours",
        std::string("frame ") + in.mesh + " -o " + in.dir.path("x.png") + " --size 10x10000000"}) {
    const auto r = run(tool("terrain-render") + " " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(lines(r.err), 1u) << args << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(in.dir.path("x.png"))) << args;
  }
}

// No EGL vendor (glvnd finds no driver) and a driver with OpenGL 3.3 only (Mesa softpipe):
// one clear error line and exit code 1, no crash and no output.
TEST(TerrainRender, NoUsableOpenGlIsAClearError) {
  Inputs in;
  for (const std::string env :
       {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/vendor.json", "GALLIUM_DRIVER=softpipe"}) {
    const auto r = run("env " + env + " " + tool("terrain-render") + " frame " + in.mesh + " -o " +
                       in.dir.path("x.png") + " --size 64x64");
    EXPECT_EQ(r.exit_code, 1) << env << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1u) << env << "\n" << r.err;
    EXPECT_NE(r.err.find("no usable OpenGL 4.3"), std::string::npos) << env << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(in.dir.path("x.png")));
  }
}

}  // namespace

namespace {

// denoise-normals adds the Voronoi weights (and, denoising, the normal change) that
// terrain-inspect reports and the PEL layer needs; without them --layers pels is an error.
TEST(TerrainRender, DenoisedMeshRendersPels) {
  Inputs in;
  const std::string dn = in.dir.path("dn.ply"), w = in.dir.path("w.ply");
  const auto d = run(tool("denoise-normals") + " " + in.mesh + " " + dn + " --iterations 5 -q");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_NE(d.out.find("normal_change_mean_deg: "), std::string::npos) << d.out;
  const auto info = run(tool("terrain-inspect") + " info " + dn);
  EXPECT_NE(info.out.find("voronoi_weights: yes"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("denoised: yes"), std::string::npos) << info.out;
  const auto z = run(tool("denoise-normals") + " " + in.mesh + " " + w + " --iterations 0 -q");
  ASSERT_EQ(z.exit_code, 0) << z.err;
  EXPECT_NE(z.out.find("normal_change_max_deg: 0.0000"), std::string::npos) << z.out;
  const auto pv = run(tool("terrain-inspect") + " preview " + dn +
                      " --colour-by normal-change -o " + in.dir.path("nc.png"));
  EXPECT_EQ(pv.exit_code, 0) << pv.err;
  const auto pw = run(tool("terrain-inspect") + " preview " + in.mesh + " --colour-by voronoi -o " +
                      in.dir.path("v.png"));
  EXPECT_EQ(pw.exit_code, 1);  // the plain mesh has no weights
  EXPECT_EQ(lines(pw.err), 1u) << pw.err;

  const auto f =
      run(tool("terrain-render") + " frame " + dn + " " + in.dv + " -o " + in.dir.path("p.png") +
          " --size 160x120 --layers mask,pels,creases,silhouettes");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_NE(f.out.find("pel segments drawn: "), std::string::npos) << f.out;
  EXPECT_EQ(f.out.find("pel segments drawn: 0\n"), std::string::npos) << f.out;
  const auto bad = run(tool("terrain-render") + " frame " + in.mesh + " -o " +
                       in.dir.path("q.png") + " --size 160x120 --layers mask,pels");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(lines(bad.err), 1u) << bad.err;
  EXPECT_NE(bad.err.find("Voronoi weights"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(in.dir.path("q.png")));
}

}  // namespace
