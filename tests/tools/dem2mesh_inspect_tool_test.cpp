// End-to-end: the command-line tools on good and bad input.
#include <fmt/format.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "drainage/dv_file.hpp"
#include "drainage/dv_views.hpp"
#include "renderer/core/options.hpp"
#include "renderer/core/plan_map.hpp"
#include "terrain/dem_io.hpp"
#include "terrain/mesh_io.hpp"
#include "terrain/mesh_pyramid.hpp"
#include "test_support.hpp"
#include "tools/ink.hpp"

namespace terrain {
namespace {

using test::data;
using test::run;
using test::tool;

std::size_t lines(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n'));
}

TEST(Dem2mesh, MeshesMountStHelensAt50m) {
  test::ScratchDir dir;
  const auto r = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " +
                     dir.path("m.ply") + " --spacing 50 --grid-out " + dir.path("g.tif") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");                                                   // -q: nothing on stderr
  EXPECT_NE(r.out.find("vertices: 5368\n"), std::string::npos) << r.out;  // 61 x 88
  EXPECT_NE(r.out.find("(EPSG:26910)"), std::string::npos) << r.out;
  const GridMesh m = read_mesh_ply(dir.path("m.ply"));
  EXPECT_EQ(m.geo.dx, 50.0);
  EXPECT_NE(m.provenance.find("dem2mesh"), std::string::npos);
  EXPECT_NE(m.provenance.find("--spacing 50"), std::string::npos);

  // export --to tif gives back exactly the resampled grid.
  const auto e = run(tool("terrain-inspect") + " export " + dir.path("m.ply") + " --to tif -o " +
                     dir.path("back.tif"));
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const Grid g = read_dem(dir.path("g.tif")), back = read_dem(dir.path("back.tif"));
  EXPECT_EQ(back.z, g.z);
  EXPECT_DOUBLE_EQ(back.geo.x0, g.geo.x0);
  EXPECT_DOUBLE_EQ(back.geo.y0, g.geo.y0);
  EXPECT_EQ(back.geo.epsg, 26910);

  const auto i = run(tool("terrain-inspect") + " info " + dir.path("m.ply"));
  ASSERT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("type: terrain mesh (PLY)"), std::string::npos);
  EXPECT_NE(i.out.find("grid: 61 x 88"), std::string::npos) << i.out;

  for (const std::string& in :
       {dir.path("m.ply"), data("msh_2007_utm10n_10m.tif"), data("sinmap_crop_10m.asc")}) {
    const auto p = run(tool("terrain-inspect") + " preview " + in + " -o " + dir.path("p.png"));
    ASSERT_EQ(p.exit_code, 0) << p.err;
    ensure_gdal();  // GDAL reads PNG: check the size (read_dem refuses pictures as DEMs)
    std::unique_ptr<GDALDataset> png(GDALDataset::Open(dir.path("p.png").c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(png);
    const Grid src = is_ply_file(in) ? mesh_to_grid(read_mesh_ply(in)) : read_dem(in);
    EXPECT_EQ(std::size_t(png->GetRasterXSize()), src.cols);
    EXPECT_EQ(std::size_t(png->GetRasterYSize()), src.rows);
  }
}

// Every bad input: non-zero exit, one line on stderr, no output file.
// --fit-normals on a crop of the crater: the fit is reported on stdout, kept in the mesh
// and shown by terrain-inspect info; the mesh's PN surface is closer to the DEM.
TEST(Dem2mesh, FitNormalsIsReportedAndRecorded) {
  test::ScratchDir dir;
  const auto r =
      run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + dir.path("m.ply") +
          " --spacing 50 --center 562700 5117000 --size 1000 1000 --fit-normals -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("normals: fitted\n"), std::string::npos) << r.out;
  const GridMesh m = read_mesh_ply(dir.path("m.ply"));
  ASSERT_TRUE(m.normal_fit.fitted);
  EXPECT_LT(m.normal_fit.rmse_after, 0.8 * m.normal_fit.rmse_before);
  EXPECT_GT(m.normal_fit.samples, 9000u);
  const auto i = run(tool("terrain-inspect") + " info " + dir.path("m.ply"));
  ASSERT_EQ(i.exit_code, 0) << i.err;
  EXPECT_NE(i.out.find("normals_fitted: yes"), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("fit_rmse_m: "), std::string::npos) << i.out;
}

TEST(Dem2mesh, BadInputFailsCleanly) {
  test::ScratchDir dir;
  std::ofstream(dir.path("garbage.tif")) << "this is not a raster\n";
  Georef geo;
  geo.x0 = 500000;
  geo.y0 = 4000000;
  geo.dx = geo.dy = 10;
  Grid nodata(20, 20, geo, std::numeric_limits<float>::quiet_NaN());
  write_geotiff(nodata, dir.path("nodata.tif"));
  write_geotiff(Grid(1, 1, geo, 100.0f), dir.path("one.tif"));
  const std::string msh = data("msh_2007_utm10n_10m.tif");
  struct Case {
    std::string args;
    std::string message;  // a fragment the error line must contain
    int code;
  };
  const Case cases[] = {
      {dir.path("missing.tif"), "no such file", 1},
      {dir.path("garbage.tif"), "not a raster", 1},
      {dir.path("nodata.tif"), "no valid elevation", 1},
      {msh + " --bbox 0 0 1000 1000", "outside the DEM", 1},
      {dir.path("one.tif"), "at least 2 x 2", 1},
      {msh + " --spacing 0", "--spacing", 2},
      {msh + " --spacing -5", "--spacing", 2},
      {msh + " --max-void -1", "--max-void", 2},
      {msh + " --utm-zone 10", "geographic DEMs only", 1},
      {msh + " --resample nearest", "--resample", 2},
  };
  for (const Case& c : cases) {
    const std::string out = dir.path("out.ply");
    const auto r = run(tool("dem2mesh") + " " + c.args + " " + out + " -q");
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1u) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
  EXPECT_EQ(dir.n_entries(), 3u);  // only the three inputs: no temporary files left
  // An output directory that does not exist fails before any work.
  const auto r = run(tool("dem2mesh") + " " + msh + " " + dir.path("nowhere/out.ply"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

// A crop of a huge raster reads only its window: a VRT that claims 40000 x 40000 samples
// (6.4 GB as float32) around the MSH DEM; an 80 m crop reads a few hundred samples. The
// read shows GDAL-style progress.
TEST(Dem2mesh, CropReadsOnlyItsWindow) {
  test::ScratchDir dir;
  std::ofstream(dir.path("big.vrt"))
      << "<VRTDataset rasterXSize=\"40000\" rasterYSize=\"40000\">\n"
         "  <GeoTransform>561190, 10, 0, 5119500, 0, -10</GeoTransform>\n"
         "  <VRTRasterBand dataType=\"Float32\" band=\"1\"><NoDataValue>-9999</NoDataValue>\n"
         "    <SimpleSource><SourceFilename relativeToVRT=\"0\">"
      << data("msh_2007_utm10n_10m.tif")
      << "</SourceFilename><SourceBand>1</SourceBand>\n"
         "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"303\" ySize=\"442\"/>"
         "<DstRect xOff=\"0\" yOff=\"0\" xSize=\"303\" ySize=\"442\"/></SimpleSource>\n"
         "  </VRTRasterBand>\n</VRTDataset>\n";
  const auto r = run(tool("dem2mesh") + " " + dir.path("big.vrt") + " " + dir.path("crop.ply") +
                     " --center 562500 5117000 --size 80 80 -v");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("read 14 x 14 of 40000 x 40000 samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("read: 0...10...20"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("grid: 8 x 8"), std::string::npos) << r.out;
}

// Points on a lattice (issue 39): four cell centres in five of a 60 x 60 crop of the MSH DEM
// as XYZ text. GDAL's XYZ driver reads it as a grid full of holes: meshed with its holes, with
// a warning that --input points exists; --input points triangulates the points instead.
TEST(Dem2mesh, PointsOnALatticeAreReadAsPointsWhenAsked) {
  terrain::test::ScratchDir dir;
  const std::string xyz = dir.path("grid.xyz"), lattice = dir.path("lattice.xyz");
  ASSERT_EQ(std::system(("gdal_translate -q -of XYZ -srcwin 0 0 60 60 " +
                         data("msh_2007_utm10n_10m.tif") + " " + xyz)
                            .c_str()),
            0);
  ASSERT_EQ(std::system(("awk 'NR % 5 != 0' " + xyz + " > " + lattice).c_str()), 0);  // holes
  const std::string d2m = tool("dem2mesh") + " " + lattice + " " + dir.path("m.ply");
  const auto grid = run(d2m);
  EXPECT_EQ(grid.exit_code, 0) << grid.err;
  EXPECT_NE(grid.err.find("no-data"), std::string::npos) << grid.err;
  EXPECT_NE(grid.err.find("pass --input points"), std::string::npos) << grid.err;
  EXPECT_TRUE(read_mesh_ply(dir.path("m.ply")).has_holes());
  std::filesystem::remove(dir.path("m.ply"));
  const auto crs = run(d2m + " --src-crs EPSG:32610");
  EXPECT_EQ(crs.exit_code, 0) << crs.err;
  EXPECT_NE(crs.err.find("pass --input points"), std::string::npos) << crs.err;
  std::filesystem::remove(dir.path("m.ply"));
  const auto points = run(d2m + " --input points --src-crs EPSG:32610 --spacing 20");
  ASSERT_EQ(points.exit_code, 0) << points.err;
  EXPECT_NE(points.out.find("vertices: "), std::string::npos) << points.out;
  EXPECT_TRUE(std::filesystem::exists(dir.path("m.ply")));
  // --input raster reads it as the grid, as auto does (without the warning: asked for).
  const auto raster = run(d2m + " --input raster");
  EXPECT_EQ(raster.exit_code, 0) << raster.err;
  EXPECT_EQ(raster.err.find("pass --input points"), std::string::npos) << raster.err;
}

// Rasters without a CRS (issue 50): an SRTM-style .asc in degrees with no .prj is refused
// with the fix named (--src-crs), and meshed with it; a metre grid without a CRS (MED)
// meshes as it is. No tool refuses a mesh dem2mesh wrote: each mesh goes through
// build-drainage, terrain-render, terrain-inspect and denoise-normals.
TEST(Dem2mesh, RastersWithoutACrsGiveMeshesEveryToolTakes) {
  terrain::test::ScratchDir dir;
  const std::string asc = dir.path("srtm.asc");
  ASSERT_EQ(std::system(("gdal_translate -q -of AAIGrid " + data("eno_nad83_geographic_crop.tif") +
                         " " + asc)
                            .c_str()),
            0);
  std::filesystem::remove(dir.path("srtm.prj"));
  const auto refused = run(tool("dem2mesh") + " " + asc + " " + dir.path("refused.ply") + " -q");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("--src-crs"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path("refused.ply")));
  const std::vector<std::pair<std::string, std::string>> meshes = {
      {"srtm", asc + " --src-crs EPSG:4269"}, {"med", data("med_01_01_10m.tif") + " --spacing 30"}};
  for (const auto& [name, input] : meshes) {
    SCOPED_TRACE(name);
    const std::string m = dir.path(name + ".ply"), dv = dir.path(name + ".dv");
    const auto made = run(tool("dem2mesh") + " " + input + " " + m + " -q");
    ASSERT_EQ(made.exit_code, 0) << made.err;
    for (const std::string& cmd :
         {tool("build-drainage") + " " + m + " " + dv + " --spacing 30 -q",
          tool("terrain-render") + " frame " + m + " " + dv + " -o " + dir.path(name + ".png") +
              " --size 160x90 -q",
          tool("terrain-inspect") + " info " + m, tool("terrain-inspect") + " info " + dv,
          tool("terrain-inspect") + " preview " + dv + " -o " + dir.path(name + "_dv.png"),
          tool("denoise-normals") + " " + m + " " + dir.path(name + "_denoised.ply") +
              " --iterations 1 -q"}) {
      const auto r = run(cmd);
      EXPECT_EQ(r.exit_code, 0) << cmd << "\n" << r.err;
    }
  }
}

// No-data as a hydrologist's clipped DEM has it (docs/dem2mesh.md, "No-data"): a cone on a
// disc of data (radius 30 samples of 10 m in 80 x 80, no-data around it) and a 2 x 2 void
// on its flank. With no option: the void is filled (its vertices drawn and drained), the
// ring is outside (no face touches it: the faces are those of the data's cells, within
// 3 %); no drainage point outside the disc; the top view draws nothing more than 2 px
// beyond the disc.
TEST(Dem2mesh, NodataIsOutsideTheMesh) {
  terrain::test::ScratchDir dir;
  Georef geo;
  geo.x0 = 500000, geo.y0 = 5000000, geo.dx = geo.dy = 10;
  Grid dem(80, 80, geo);
  const auto radius = [](std::size_t r, std::size_t c) {
    return std::hypot(double(r) - 39.5, double(c) - 39.5);
  };
  std::size_t data_cells = 0;
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c) {
      const bool out = radius(r, c) > 30, vd = r >= 20 && r < 22 && c >= 40 && c < 42;
      dem.at(r, c) =
          out || vd ? std::numeric_limits<float>::quiet_NaN() : float(500 - 8 * radius(r, c));
    }
  for (std::size_t r = 0; r + 1 < 80; ++r)
    for (std::size_t c = 0; c + 1 < 80; ++c)
      data_cells += radius(r, c) <= 30 && radius(r + 1, c) <= 30 && radius(r, c + 1) <= 30 &&
                    radius(r + 1, c + 1) <= 30;
  write_geotiff(dem, dir.path("dem.tif"));
  const std::string m = dir.path("m.ply"), dv = dir.path("m.dv");
  const auto made = run(tool("dem2mesh") + " " + dir.path("dem.tif") + " " + m);
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const GridMesh mesh = read_mesh_ply(m);
  ASSERT_EQ(mesh.filled.size(), mesh.n_vertices());
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c) {
      const bool vd = r >= 20 && r < 22 && c >= 40 && c < 42;
      ASSERT_EQ(mesh.filled[r * 80 + c], radius(r, c) > 30 ? kOutside
                                         : vd              ? kVoidFilled
                                                           : kFromData)
          << r << " " << c;
    }
  const double faces = double(mesh.kept_faces().size());
  const std::string info = run(tool("terrain-inspect") + " info " + m).out;
  EXPECT_NE(info.find(fmt::format("outside_vertices: {}\n",
                                  std::count(mesh.filled.begin(), mesh.filled.end(), kOutside))),
            std::string::npos)
      << info;
  EXPECT_NE(info.find("void_filled_vertices: 4\n"), std::string::npos) << info;
  // The preview leaves the outside clear: grey and alpha, alpha 0 exactly there.
  ASSERT_EQ(
      run(tool("terrain-inspect") + " preview " + m + " -o " + dir.path("p.png") + " -q").exit_code,
      0);
  OIIO::ImageBuf preview(dir.path("p.png"));
  ASSERT_EQ(preview.nchannels(), 2);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      float px[2];
      preview.getpixel(x, y, px, 2);
      ASSERT_EQ(px[1] == 0.0f, mesh.filled[std::size_t(y) * 80 + std::size_t(x)] == kOutside)
          << x << " " << y;
    }
  EXPECT_NEAR(faces / (2.0 * double(data_cells)), 1.0, 0.03) << faces << " " << data_cells;
  EXPECT_NE(made.out.find(fmt::format("faces: {}\n", mesh.kept_faces().size())), std::string::npos)
      << made.out;
  ASSERT_EQ(run(tool("build-drainage") + " " + m + " " + dv + " -q").exit_code, 0);
  const auto links = drainage::drainage_links(drainage::read_dv(dv));
  ASSERT_EQ(links.rows, 80u);
  std::size_t valid_inside = 0;
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c) {
      if (radius(r, c) > 31) {
        ASSERT_FALSE(links.valid[r * 80 + c]) << r << " " << c;
      }
      valid_inside += radius(r, c) < 29 && links.valid[r * 80 + c];
    }
  EXPECT_GT(valid_inside, 2400u);  // the void drains: the disc within 29 samples is 2642
  const auto shot = run(tool("terrain-render") + " frame " + m +
                        " --view top --size 400x400 --layers mask -o " + dir.path("top.png"));
  ASSERT_EQ(shot.exit_code, 0) << shot.err;
  const std::size_t at = shot.out.find(" m a pixel");
  ASSERT_NE(at, std::string::npos) << shot.out;
  const double scale = std::stod(shot.out.substr(shot.out.rfind(' ', at - 1) + 1));
  OIIO::ImageBuf top(dir.path("top.png"));
  double sx = 0, sy = 0, n = 0;
  std::vector<std::pair<int, int>> white;
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x) {
      float px[3];
      top.getpixel(x, y, px, 3);
      if (px[0] > 0.99f && px[1] > 0.99f && px[2] > 0.99f)
        white.push_back({x, y}), sx += x, sy += y, n += 1;
    }
  ASSERT_GT(n, 1000);
  const double reach = 300.0 / scale + 2.0;  // the disc's radius in pixels, and 2
  for (const auto& [x, y] : white)
    ASSERT_LE(std::hypot(x - sx / n, y - sy / n), reach) << x << " " << y;
  // With the silhouettes layer the outline is drawn: ink on most of the disc's rim (the
  // faces' staircase lies up to a cell inside the circle).
  ASSERT_EQ(run(tool("terrain-render") + " frame " + m +
                " --view top --size 400x400 --layers mask,silhouettes -q -o " + dir.path("o.png"))
                .exit_code,
            0);
  const auto ink = terrain::test::ink_of(dir.path("o.png"));
  int rim = 0, inked = 0;
  for (int a = 0; a < 360; ++a) {
    const double t = a * std::numbers::pi / 180, rad = reach - 2.0, cell = 10.0 / scale;
    bool hit = false;
    for (double d = -cell - 2; d <= 2 && !hit; d += 0.5) {
      const int x = int(std::lround(sx / n + (rad + d) * std::cos(t)));
      const int y = int(std::lround(sy / n + (rad + d) * std::sin(t)));
      hit = x >= 0 && y >= 0 && x < 400 && y < 400 && ink.on[std::size_t(y) * 400 + std::size_t(x)];
    }
    ++rim, inked += hit;
  }
  EXPECT_GT(inked, rim * 9 / 10) << inked << " of " << rim;
}

// Issue 50: ground that --fill-nodata invents carries no drainage. A 10 m DEM (a slope with
// a valley, no CRS) with a 20 x 20 hole of no-data: the mesh records the 400 filled
// vertices (PLY property `filled`, kept by denoise-normals, counted by terrain-inspect),
// and build-drainage, sampling at the mesh's own 10 m, gives no-data exactly at the samples
// of the cells those vertices touch (22 x 22), valid ones everywhere else. Before, the
// drainage ran over the fill's folds in straight lines (sinmap's watershed).
TEST(Dem2mesh, FilledSamplesCarryNoDrainage) {
  terrain::test::ScratchDir dir;
  Georef geo;
  geo.x0 = 500000, geo.y0 = 5000000, geo.dx = geo.dy = 10;
  Grid dem(80, 80, geo);
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c) {
      const bool hole = r >= 30 && r < 50 && c >= 30 && c < 50;
      dem.at(r, c) = hole ? std::numeric_limits<float>::quiet_NaN()
                          : float(300 - 0.2 * double(r) + 0.3 * std::abs(double(c) - 40.0));
    }
  write_geotiff(dem, dir.path("dem.tif"));
  const std::string m = dir.path("m.ply"), dv = dir.path("m.dv");
  {  // with no option the hole (400 samples, over --max-void) is outside the mesh
    ASSERT_EQ(run(tool("dem2mesh") + " " + dir.path("dem.tif") + " " + m + " -q").exit_code, 0);
    const GridMesh holed = read_mesh_ply(m);
    ASSERT_EQ(holed.filled.size(), holed.n_vertices());
    EXPECT_EQ(std::count(holed.filled.begin(), holed.filled.end(), kOutside), 400);
  }
  const auto made =
      run(tool("dem2mesh") + " " + dir.path("dem.tif") + " " + m + " --fill-nodata -q");
  ASSERT_EQ(made.exit_code, 0) << made.err;
  const GridMesh mesh = read_mesh_ply(m);
  ASSERT_EQ(mesh.topo.rows, 80u);
  ASSERT_EQ(mesh.filled.size(), mesh.n_vertices());
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c)
      ASSERT_EQ(mesh.filled[r * 80 + c], r >= 30 && r < 50 && c >= 30 && c < 50) << r << " " << c;
  EXPECT_NE(run(tool("terrain-inspect") + " info " + m).out.find("filled_vertices: 400\n"),
            std::string::npos);
  ASSERT_EQ(run(tool("denoise-normals") + " " + m + " " + dir.path("d.ply") + " --iterations 1 -q")
                .exit_code,
            0);
  EXPECT_TRUE(read_mesh_ply(dir.path("d.ply")).filled == mesh.filled);
  ASSERT_EQ(run(tool("build-drainage") + " " + m + " " + dv + " -q").exit_code, 0);
  const auto links = drainage::drainage_links(drainage::read_dv(dv));
  ASSERT_EQ(links.rows, 80u);
  ASSERT_EQ(links.cols, 80u);
  for (std::size_t r = 0; r < 80; ++r)
    for (std::size_t c = 0; c < 80; ++c)
      EXPECT_EQ(bool(links.valid[r * 80 + c]), !(r >= 29 && r <= 50 && c >= 29 && c <= 50))
          << r << " " << c;
  // Nor hachures (issue 51): from straight above, the slopes exaggerated 5 times (steeper
  // than the hachures' 0.05 rad), none inside the hole (its inner part, in the terrain's box
  // on the image), and some around it.
  const std::string frame =
      tool("terrain-render") + " frame " + m + " --view top --size 400x400 --exaggeration 5 -q -o ";
  ASSERT_EQ(run(frame + dir.path("mask.png") + " --layers mask").exit_code, 0);
  ASSERT_EQ(
      run(frame + dir.path("h.png") + " --layers mask,hachures --hachure-spacing 4").exit_code, 0);
  const auto white = terrain::test::ink_of(dir.path("mask.png")),
             ink = terrain::test::ink_of(dir.path("h.png"));
  int x0 = 400, x1 = 0, y0 = 400,
      y1 = 0;  // the terrain's box: the mask's pixels (not background, no ink)
  OIIO::ImageBuf mask(dir.path("mask.png"));
  for (int y = 0; y < 400; ++y)
    for (int x = 0; x < 400; ++x) {
      float px[3];
      mask.getpixel(x, y, px, 3);
      if (px[0] > 0.99f && px[1] > 0.99f && px[2] > 0.99f)
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  ASSERT_GT(x1 - x0, 200);
  ASSERT_EQ(terrain::test::count(white), 0u);
  std::size_t inside = 0, outside = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double fx = double(x - x0) / (x1 - x0), fy = double(y - y0) / (y1 - y0);
      const bool in_hole = fx > 0.42 && fx < 0.57 && fy > 0.42 && fy < 0.57;
      (in_hole ? inside : outside) += ink.on[std::size_t(y) * 400 + std::size_t(x)];
    }
  EXPECT_EQ(inside, 0u);
  EXPECT_GT(outside, 500u);
}

// dem2mesh --pyramid writes MESH.tpyr beside MESH.ply: terrain-inspect info reads it (the
// levels of 64-cell blocks), and its level 0 read whole is the PLY's vertices, bit for bit.
TEST(Dem2mesh, PyramidBesideTheMesh) {
  test::ScratchDir dir;
  const auto r = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " +
                     dir.path("m.ply") + " --spacing 20 --pyramid");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("pyramid: " + dir.path("m.tpyr")), std::string::npos) << r.out;
  const auto info = run(tool("terrain-inspect") + " info " + dir.path("m.tpyr"));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("type: mesh pyramid"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("levels: 7"), std::string::npos)
      << info.out;  // 64-cell blocks: steps 1 .. 64
  EXPECT_NE(info.out.find("slopes: each block's at each level"), std::string::npos) << info.out;
  const GridMesh m = read_mesh_ply(dir.path("m.ply"));
  MeshPyramid p(dir.path("m.tpyr"));
  ASSERT_EQ(p.rows(0), m.topo.rows);
  ASSERT_EQ(p.cols(0), m.topo.cols);
  EXPECT_EQ(p.georef().epsg, m.geo.epsg);
  EXPECT_EQ(p.georef().origin_x, m.geo.origin_x);
  const MeshWindow w = p.read_window(0, 0, 0, p.rows(0), p.cols(0));
  std::size_t differ = 0;
  for (std::size_t i = 0; i < m.n_vertices(); ++i)
    differ += w.positions[i] != m.positions[i] || w.normals[i] != m.normals[i];
  EXPECT_EQ(differ, 0u);
  // terrain-render reads the mesh from the pyramid beside it, and draws the same frame as
  // from the PLY alone (the PNG's bytes, its description naming the same command).
  const std::string frame = tool("terrain-render") + " frame " + dir.path("m.ply") + " -o " +
                            dir.path("f.png") + " --size 480x270 -v";
  const auto via = run(frame);
  ASSERT_EQ(via.exit_code, 0) << via.err;
  EXPECT_NE(via.err.find("from '" + dir.path("m.tpyr") + "' (its pyramid)"), std::string::npos)
      << via.err;
  const std::string png = test::file_bytes(dir.path("f.png"));
  // Under a memory bound the mesh does not fit (--memory 0.25: 256 KiB; the mesh's 151 x 221
  // vertices take 0.8 MB), terrain-render reads a preview level (level 2, within a quarter
  // of the bound), then the finest level the view draws: a map at 30 m a pixel with a
  // 2-pixel error bound (8 where the level faces the eye: everywhere from straight above)
  // draws no block finer than level 2 (cells of 3.8 px; level 3's 7.5 px exceed the
  // tessellation target, lod_cell_px), so the surface and its
  // silhouettes are the same, pixel for pixel, as from the whole mesh. A 0.25-pixel bound
  // draws level 0 there: level 1 (the finest within the bound) is drawn instead, and says so.
  auto same_pixels = [](const std::string& a, const std::string& b) {
    return run("oiiotool --fail 0 --failpercent 0 --diff " + a + " " + b).exit_code == 0;
  };
  const std::string map = tool("terrain-render") + " frame " + dir.path("m.ply") +
                          " --size 480x270 --view top " +
                          "--map-scale 30 --layers mask,silhouettes -v -o ";
  ASSERT_EQ(run(map + dir.path("whole.png") + " --lod-error 2").exit_code, 0);
  const auto bounded = run(map + dir.path("bounded.png") + " --lod-error 2 --memory 0.25");
  ASSERT_EQ(bounded.exit_code, 0) << bounded.err;
  EXPECT_NE(bounded.err.find("(its pyramid, level 2)"), std::string::npos)
      << bounded.err;  // the preview
  EXPECT_NE(bounded.err.find("mesh read at level 2 of its pyramid after the preview at level 2: "
                             "the view draws level 2"),
            std::string::npos)
      << bounded.err;
  EXPECT_TRUE(same_pixels(dir.path("whole.png"), dir.path("bounded.png")));
  // A batch reads the finest level any of its frames draws: two oblique frames from 9 km up
  // draw the same surface and silhouettes as from the whole mesh (before the coarse patches
  // were found by the mesh's own spacing, not the held level's, 117 pixels of the first
  // frame differed).
  const auto path = run(tool("terrain-render") +
                        " path --from 558000 5110000 9000 --to 562000 5111000 9000 --frames 2 " +
                        "--view-alt 50 -o " + dir.path("p.csv"));
  ASSERT_EQ(path.exit_code, 0) << path.err;
  const std::string batch = tool("terrain-render") + " batch " + dir.path("m.ply") + " " +
                            dir.path("p.csv") +
                            " --size 480x270 --layers mask,silhouettes --lod-error 2 -v -o ";
  ASSERT_EQ(run(batch + dir.path("whole")).exit_code, 0);
  const auto bounded_batch = run(batch + dir.path("bounded") + " --memory 0.25");
  ASSERT_EQ(bounded_batch.exit_code, 0) << bounded_batch.err;
  EXPECT_NE(bounded_batch.err.find(
                "mesh read at level 1 of its pyramid after the preview at level 2: the views draw "
                "level 1"),
            std::string::npos)
      << bounded_batch.err;
  for (const std::string f : {"/frame_00000.png", "/frame_00001.png"})
    EXPECT_TRUE(same_pixels(dir.path("whole") + f, dir.path("bounded") + f)) << f;
  const auto finer = run(map + dir.path("finer.png") + " --memory 0.25");
  ASSERT_EQ(finer.exit_code, 0) << finer.err;
  EXPECT_NE(
      finer.err.find(
          "the view draws level 0 at its finest; level 1 read, the finest within the memory bound"),
      std::string::npos)
      << finer.err;
  // build-drainage too (its mesh read from the pyramid): the same database.
  const std::string drain = tool("build-drainage") + " " + dir.path("m.ply") + " " +
                            dir.path("d.dv") + " --spacing 20 -q";
  ASSERT_EQ(run(drain).exit_code, 0);
  const std::string dv = test::file_bytes(dir.path("d.dv"));
  // A near view under a bound that the mesh exceeds but the blocks in its view fit
  // (--memory 0.75: 768 KiB; the mesh's vertices 801 KB, the 3 x 3 blocks north of the eye
  // and around it, 151 x 193 vertices, 700 KB) reads only those blocks, at level 0, and
  // draws the creases of the whole mesh's network: the frame of the whole mesh, pixel for
  // pixel (creases, hachures, silhouettes; a 20 m lattice moves exactly).
  const std::string near =
      tool("terrain-render") + " frame " + dir.path("m.ply") + " " + dir.path("d.dv") +
      " --eye 562800 5117200 2300 --view-az 0 --view-alt 10 --fov 40 --size 480x270 -v -o ";
  ASSERT_EQ(run(near + dir.path("near_whole.png")).exit_code, 0);
  const auto near_window = run(near + dir.path("near_window.png") + " --memory 0.75");
  ASSERT_EQ(near_window.exit_code, 0) << near_window.err;
  EXPECT_NE(
      near_window.err.find(
          "mesh read at level 0 of its pyramid after the preview at level 2: the view draws "
          "level 0 at its finest; the blocks in view, rows 0 .. 2 and columns 0 .. 2 of 4 x 3, "
          "read: 151 x 193 vertices"),
      std::string::npos)
      << near_window.err;
  EXPECT_GT(test::count(test::ink_of(dir.path("near_whole.png"))), 2000u);
  EXPECT_TRUE(same_pixels(dir.path("near_whole.png"), dir.path("near_window.png")));
  // A pyramid from before version 3 does not say which mesh it was made from: the PLY is
  // read instead, with a warning that names the remedy, and draws the same frame.
  const std::string v3 = test::file_bytes(dir.path("m.tpyr"));
  std::ofstream(dir.path("m.tpyr"), std::ios::binary | std::ios::trunc)
      << test::pyramid_as_version1(v3);
  const auto old = run(frame);
  ASSERT_EQ(old.exit_code, 0) << old.err;
  EXPECT_NE(old.err.find("read whole, not its pyramid"), std::string::npos) << old.err;
  EXPECT_NE(
      old.err.find("(version 1) does not say which mesh it was made from; dem2mesh --pyramid"),
      std::string::npos)
      << old.err;
  EXPECT_TRUE(test::file_bytes(dir.path("f.png")) == png) << "the frames differ";
  std::ofstream(dir.path("m.tpyr"), std::ios::binary | std::ios::trunc) << v3;
  std::filesystem::rename(dir.path("m.tpyr"), dir.path("away.tpyr"));
  // Over the bound without a pyramid: read whole, with a warning that names the remedy.
  const auto no_pyramid = run(map + dir.path("plain.png") + " --lod-error 2 --memory 0.25");
  ASSERT_EQ(no_pyramid.exit_code, 0) << no_pyramid.err;
  EXPECT_NE(
      no_pyramid.err.find(
          "more than the memory bound (0.3 MB), and no current pyramid is beside it (the PLY): "
          "read whole; dem2mesh --pyramid makes one"),
      std::string::npos)
      << no_pyramid.err;
  EXPECT_TRUE(same_pixels(dir.path("whole.png"), dir.path("plain.png")));
  const auto direct = run(frame);
  ASSERT_EQ(direct.exit_code, 0) << direct.err;
  EXPECT_NE(direct.err.find("from the PLY"), std::string::npos) << direct.err;
  EXPECT_TRUE(test::file_bytes(dir.path("f.png")) == png) << "the frames differ";
  ASSERT_EQ(run(drain).exit_code, 0);
  EXPECT_TRUE(test::file_bytes(dir.path("d.dv")) == dv) << "the databases differ";
}

// dem2mesh in bands of rows (--tile-size, --memory), for DEMs larger than memory: the same
// PLY (but for its provenance line, which records the command) and the same pyramid, byte
// for byte, as one run: a projected DEM resampled bilinearly in bands of 7 rows (not a
// divisor of the 64-cell tiles), a geographic one reprojected onto UTM with the cubic
// kernel in bands of 5. What needs the whole grid is refused.
TEST(Dem2mesh, BandsEqualOneRun) {
  test::ScratchDir dir;
  auto without_provenance = [](std::string ply) {
    const std::size_t at = ply.find("comment provenance ");
    if (at != std::string::npos) ply.erase(at, ply.find('\n', at) - at + 1);
    return ply;
  };
  const std::pair<std::string, std::string> cases[] = {
      {data("msh_2007_utm10n_10m.tif") + " --spacing 20", "--tile-size 7"},
      {data("eno_nad83_geographic_crop.tif") + " --spacing 10 --resample cubic", "--tile-size 5"},
      {data("msh_2007_utm10n_10m.tif") + " --spacing 20", "--memory 16"}};
  for (const auto& [input, bands] : cases) {
    const auto one = run(tool("dem2mesh") + " " + input + " " + dir.path("one.ply") + " --pyramid");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    const auto banded = run(tool("dem2mesh") + " " + input + " " + dir.path("bands.ply") +
                            " --pyramid " + bands + " -v");
    ASSERT_EQ(banded.exit_code, 0) << banded.err;
    EXPECT_NE(banded.err.find("mesh in bands of"), std::string::npos) << banded.err;
    EXPECT_TRUE(test::file_bytes(dir.path("one.tpyr")) == test::file_bytes(dir.path("bands.tpyr")))
        << bands;
    const std::string a = test::file_bytes(dir.path("one.ply")),
                      b = test::file_bytes(dir.path("bands.ply"));
    EXPECT_NE(b.find(bands), std::string::npos);  // the provenance names the bands
    EXPECT_TRUE(without_provenance(a) == without_provenance(b)) << bands;
  }
  for (const std::string& whole : {std::string("--fill-nodata"), std::string("--fit-normals"),
                                   std::string("--grid-out g.tif")}) {
    const auto r = run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " +
                       dir.path("x.ply") + " --spacing 50 --tile-size 8 " + whole);
    EXPECT_NE(r.exit_code, 0) << whole;
    EXPECT_NE(r.err.find("make the mesh in bands, but"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.ply")));
  }
}

TEST(Dem2mesh, HelpShowsAnExample) {
  const auto r = run(tool("dem2mesh") + " --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Examples:"), std::string::npos);
  EXPECT_NE(r.out.find("--spacing"), std::string::npos);
}

TEST(TerrainInspect, DemInfo) {
  const auto r = run(tool("terrain-inspect") + " info " + data("logan_utm12n_100m.tif"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("grid: 289 x 498"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("crs: NAD83 / UTM zone 12N (EPSG:26912)"), std::string::npos) << r.out;
  const auto bad = run(tool("terrain-inspect") + " info /nonexistent.tif");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(lines(bad.err), 1u);
}

// A plan map's hachure options are the frame's rows of the option table: each refuses what
// terrain-render refuses (past its range, outside its choices) and takes its bounds, with
// the map's own defaults in --help.
TEST(TerrainInspect, MapHachureOptionsAreTheOptionTables) {
  const std::string help = run(tool("terrain-inspect") + " export --help").out;
  const renderer::PlanHachureOptions map;
  const std::pair<const char*, std::string> defaults[] = {
      {"hachure-spacing", fmt::format("={:g}", map.spacing)},
      {"hachure-width", fmt::format("={:g}", map.width)},
      {"hachure-tone", map.light_tone ? "=light" : "=slope"},
      {"hachure-min-slope", fmt::format("={:g}", 100 * map.min_slope_share)},
      {"hachure-style", map.rows ? "=rows" : "=lines"}};
  for (const auto& [name, shown] : defaults) {
    const renderer::OptionSpec& spec = *renderer::find_option(name);
    const bool choice = spec.type == renderer::OptionType::Enum;
    const std::string bad = choice ? "bogus" : fmt::format("{:g}", spec.max * 2 + 1);
    const std::string good = choice ? spec.choices.back() : fmt::format("{:g}", spec.max);
    const std::string opt = std::string(" --") + name + " ";
    EXPECT_EQ(run(tool("terrain-render") + " frame m.ply -o x.png" + opt + bad).exit_code, 2)
        << name;
    EXPECT_EQ(
        run(tool("terrain-inspect") + " export m.ply --to svg -o x.svg" + opt + bad).exit_code, 2)
        << name;
    // The bound itself parses: the run goes on to the missing mesh (exit 1, not 2).
    EXPECT_EQ(run(tool("terrain-inspect") + " export missing.ply --to svg -o x.svg" + opt + good)
                  .exit_code,
              1)
        << name;
    const std::size_t at = help.find(std::string("--") + name + " ");
    ASSERT_NE(at, std::string::npos) << name;
    EXPECT_NE(help.substr(at, help.find('\n', at) - at).find(shown), std::string::npos)
        << name << ": " << help.substr(at, 80);
  }
}

}  // namespace
}  // namespace terrain
