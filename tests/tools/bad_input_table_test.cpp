// One table of bad (and odd) inputs across every tool: each row is a command, the exit
// code it must give and a substring of its one stderr line. Inputs are made by the test
// (GDAL's API and gdal_translate/gdalbuildvrt). Every failing row must print exactly one
// line, leave nothing in the output directory, and end within 60 s (run under
// `timeout -s KILL 60`: a hang is exit 137). Rows that must work (formats nobody tuned
// for, a 2 x 2 grid, a DEM across a UTM zone boundary) expect 0.
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "drainage/dv_file.hpp"
#include "terrain/dem_io.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using terrain::test::data;
using terrain::test::run;
using terrain::test::tool;

struct Row {
  std::string command;  // IN/ = the inputs' directory, OUT/ = an empty output directory
  int exit_code;
  std::string message;  // substring of stderr (failures) or stdout (successes)
};

std::ostream& operator<<(std::ostream& os, const Row& r) { return os << r.command; }

// A row's name is its program and its index ("dem2mesh_12"): tests/CMakeLists.txt runs each
// program's rows as one ctest entry by this name.
std::string row_name(const ::testing::TestParamInfo<Row>& info) {
  const std::string& cmd = info.param.command;
  std::string program = cmd.substr(0, cmd.find(' '));
  program = program.substr(program.rfind('/') + 1);
  for (char& ch : program)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return program + "_" + std::to_string(info.index);
}

const char* kUtm10 = "EPSG:26910";

// A Float32 GeoTIFF of rows x cols `values` with geotransform `gt`, CRS `srs` (none if
// empty) and no-data `nodata` (none if NaN is not asked for).
void make_tif(const std::string& path, int rows, int cols, const std::vector<float>& values,
              const std::array<double, 6>& gt, const std::string& srs,
              std::optional<double> nodata = {}) {
  terrain::ensure_gdal();
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
  std::unique_ptr<GDALDataset> ds(drv->Create(path.c_str(), cols, rows, 1, GDT_Float32, nullptr));
  ASSERT_TRUE(ds);
  double g[6] = {gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]};
  ds->SetGeoTransform(g);
  if (!srs.empty()) {
    OGRSpatialReference s;
    s.SetFromUserInput(srs.c_str());
    ds->SetSpatialRef(&s);
  }
  if (nodata) ds->GetRasterBand(1)->SetNoDataValue(*nodata);
  ASSERT_EQ(
      ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, cols, rows, const_cast<float*>(values.data()),
                                     cols, rows, GDT_Float32, 0, 0),
      CE_None);
}

// A tilted plane of rows x cols samples, 10 m apart, in UTM 10N.
std::vector<float> plane(int rows, int cols) {
  std::vector<float> v(std::size_t(rows) * std::size_t(cols));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      v[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = float(100 + 2 * r + c);
  return v;
}

class BadInput : public ::testing::TestWithParam<Row> {
 protected:
  // ctest runs every row in its own process: the inputs are made once per build of the
  // tools (the directory's name holds the newest modification time of the binaries) in
  // the build tree, in a scratch directory renamed into place, so parallel rows never see
  // half-made inputs.
  static void SetUpTestSuite() {
    fs::file_time_type newest = fs::file_time_type::min();
    for (const char* t : {"dem2mesh", "build-drainage", "terrain-inspect", "terrain_tests"})
      newest = std::max(newest, fs::last_write_time(tool(t)));
    const fs::path dir = fs::path(TERRAIN_BIN_DIR).parent_path() / "test-fixtures" /
                         ("bad-input-" + std::to_string(newest.time_since_epoch().count()));
    in_ = dir.string() + "/";
    if (fs::exists(dir)) return;
    fs::create_directories(dir.parent_path());
    const fs::path scratch = dir.string() + ".tmp" + std::to_string(::getpid());
    fs::create_directories(scratch);
    if (!make_inputs(scratch.string() + "/", in_)) {
      fs::remove_all(scratch);
      return;  // the rows fail on the missing inputs, after the setup's own failure
    }
    std::error_code ec;
    fs::rename(scratch, dir, ec);  // fails when another row made them first: use those
    if (ec) fs::remove_all(scratch);
  }

  // Returns false when a command that makes an input failed. `final` is where `into` will
  // be renamed: the paths written inside replay files.
  static bool make_inputs(const std::string& into, const std::string& final) {
    bool ok = true;
    auto in = [&](const std::string& n) { return into + n; };
    const std::string msh = data("msh_2007_utm10n_10m.tif"),
                      eno = data("eno_nad83_geographic_crop.tif");
    const std::array<double, 6> gt = {500000, 10, 0, 4000000, 0, -10};
    std::ofstream(in("empty.tif")).close();
    fs::create_directories(in("a_directory"));
    {  // the first 3000 bytes of a GeoTIFF
      std::ifstream src(msh, std::ios::binary);
      std::string head(3000, '\0');
      src.read(head.data(), 3000);
      std::ofstream(in("truncated.tif"), std::ios::binary) << head;
    }
    make_tif(in("all_nodata.tif"), 20, 20, std::vector<float>(400, -9999.0f), gt, kUtm10, -9999.0);
    std::vector<float> v = plane(20, 20);
    v[5] = std::numeric_limits<float>::infinity();
    make_tif(in("inf_cell.tif"), 20, 20, v, gt, kUtm10);
    make_tif(in("one_by_one.tif"), 1, 1, {100.0f}, gt, kUtm10);
    make_tif(in("two_by_two.tif"), 2, 2, plane(2, 2), gt, kUtm10);
    make_tif(in("one_by_n.tif"), 1, 50, plane(1, 50), gt, kUtm10);
    make_tif(in("rotated.tif"), 20, 20, plane(20, 20), {500000, 10, 2, 4000000, 2, -10}, kUtm10);
    make_tif(in("no_crs.tif"), 20, 20, plane(20, 20), gt, "");
    make_tif(in("plane.tif"), 20, 20, plane(20, 20), gt, kUtm10);
    std::ofstream(in("huge.vrt"))
        << "<VRTDataset rasterXSize=\"1000000\" rasterYSize=\"1000000\">"
           "<GeoTransform>500000, 10, 0, 4000000, 0, -10</GeoTransform>"
           "<VRTRasterBand dataType=\"Float32\" band=\"1\"/></VRTDataset>\n";
    auto sh = [&ok](const std::string& cmd) {
      const auto r = run(cmd);
      EXPECT_EQ(r.exit_code, 0) << cmd << "\n" << r.err;
      ok = ok && r.exit_code == 0;
    };
    // Geographic DEMs across the UTM 17/18 boundary (78 W), in the south, at 85 N.
    sh("gdal_translate -q -a_ullr -78.01 36.01 -77.99 35.99 " + eno + " " + in("cross_zone.tif"));
    sh("gdal_translate -q -a_ullr -78.01 -36.01 -77.99 -35.99 " + eno + " " + in("south.tif"));
    sh("gdal_translate -q -a_ullr -78.01 85.01 -77.99 84.99 " + eno + " " + in("lat85.tif"));
    // Formats nobody tuned for.
    sh("gdal_translate -q -of ENVI " + msh + " " + in("m.envi"));
    sh("gdal_translate -q -of HFA " + msh + " " + in("m.img"));
    sh("gdal_translate -q -of netCDF " + msh + " " + in("m.nc"));
    sh("gdal_translate -q -of XYZ " + msh + " " + in("m.xyz"));
    sh("gdal_translate -q -of AAIGrid " + msh + " " + in("m.asc"));
    sh("gdal_translate -q -of DTED -outsize 121 121 -a_ullr -78 37 -77 36 " + eno + " " +
       in("m.dt0") + " 2>/dev/null");
    sh("gdal_translate -q -srcwin 0 0 150 442 " + msh + " " + in("west.tif"));
    sh("gdal_translate -q -srcwin 150 0 153 442 " + msh + " " + in("east.tif"));
    sh("gdalbuildvrt -q " + in("mosaic.vrt") + " " + in("west.tif") + " " + in("east.tif"));
    // Meshes, drainage and frame lists, good and damaged.
    sh(tool("dem2mesh") + " " + msh + " " + in("m.ply") + " --spacing 50 -q");
    sh(tool("build-drainage") + " " + in("m.ply") + " " + in("m.dv") + " --spacing 25 -q");
    sh(tool("terrain-inspect") + " preview " + in("m.ply") + " -o " + in("image.png"));
    fs::copy_file(in("image.png"), in("png_renamed.tif"));
    fs::copy_file(in("m.ply"), in("truncated.ply"));
    fs::resize_file(in("truncated.ply"), fs::file_size(in("m.ply")) - 100);
    std::ofstream(in("ascii.ply"))
        << "ply\nformat ascii 1.0\ncomment terrain-mesh 1\ncomment grid 2 2 10 10\n"
           "comment origin 0 0 0\nelement vertex 4\nproperty float x\nproperty float y\n"
           "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
           "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0 0 0 1\n10 0 0 0 0 1\n0 -10 0 0 0 1\n10 -10 0 0 0 1\n3 0 2 3\n3 0 3 1\n";
    {  // the mesh with an extra element another tool might add
      std::string bytes = terrain::test::file_bytes(in("m.ply"));
      bytes.replace(bytes.find("end_header\n"), 11,
                    "element material 0\nproperty uchar red\nend_header\n");
      std::ofstream(in("extra_element.ply"), std::ios::binary) << bytes;
      bytes = std::string("ply\nformat binary_little_endian 1.0\nelement vertex\nend_header\n");
      std::ofstream(in("wrong_header.ply"), std::ios::binary) << bytes;
    }
    std::ofstream(in("zero.dv")).close();
    {
      fs::copy_file(in("m.dv"), in("flipped.dv"));
      std::fstream f(in("flipped.dv"), std::ios::in | std::ios::out | std::ios::binary);
      f.seekp(std::streamoff(fs::file_size(in("m.dv")) / 2));
      f.put('\x5a');
    }
    std::ofstream(in("nan.csv")) << "easting,northing,elevation\n562000,5117000,nan\n";
    std::ofstream(in("inf.csv")) << "view_az,view_alt\n200,inf\n";
    std::ofstream(in("inside.csv")) << "easting,northing,elevation\n562500,5117000,1000\n";
    std::ofstream(in("pts_two.xyz")) << "0 0 1\n10 5 2\n";
    std::ofstream(in("pts_case.csv"))
        << "X,x,y,z\n1,0,0,1\n17,100,0,2\n3.3,0,100,3\n40,70,80,4\n";  // not a grid
    std::ofstream(in("pts_line.xyz")) << "0 0 1\n10 10 2\n20 20 3\n30 30 4\n";
    std::ofstream(in("pts_nan.xyz")) << "0 0 1\nx y z\n";
    std::ofstream(in("pts_nan2.xyz")) << "0 0 1\n10 0 nan\n0 10 3\n";
    std::ofstream(in("pts.xyz"))
        << "0 0 1\n100 0 2\n0 100 3\n70 80 4\n";  // irregular: not an XYZ raster
    // Issue 41: hostile metadata, malformed numbers, outputs placed on inputs.
    std::ofstream(in("big.vrt"))
        << "<VRTDataset rasterXSize=\"40000\" rasterYSize=\"40000\">"
           "<SRS>EPSG:26910</SRS><GeoTransform>500000, 10, 0, 4000000, 0, -10</GeoTransform>"
           "<VRTRasterBand dataType=\"Float32\" band=\"1\"/></VRTDataset>\n";
    sh("gdal_translate -q -a_ullr 500000 4000000 500000 3999800 " + in("plane.tif") + " " +
       in("zero_width.tif") + " 2>/dev/null");
    sh("gdal_translate -q -a_ullr -200 95 -199 94 " + eno + " " + in("lat95.tif"));
    {  // the mesh (50 m) with a grid or origin comment that disagrees with its vertices
      const std::string bytes = terrain::test::file_bytes(in("m.ply"));
      const std::size_t at = bytes.find("comment grid "), end = bytes.find('\n', at);
      std::istringstream grid(bytes.substr(at + 13, end - at - 13));
      std::string rows, cols;
      grid >> rows >> cols;
      for (const std::string dx : {"100", "1e300", "5e-324"}) {
        std::string b = bytes;
        b.replace(at, end - at, "comment grid " + rows + " " + cols + " " + dx + " 50");
        std::ofstream(in("dx" + dx + ".ply"), std::ios::binary) << b;
      }
      std::string b = bytes;
      const std::size_t o = b.find("comment origin "), oe = b.find('\n', o);
      b.replace(o, oe - o, "comment origin 1e300 5117000 0");
      std::ofstream(in("origin1e300.ply"), std::ios::binary) << b;
    }
    {  // a version 2 .dv whose header says 127 valid points, every checksum made to match
      std::string bytes = terrain::test::file_bytes(in("m.dv"));
      const std::uint64_t wrong = 127;
      std::memcpy(bytes.data() + 40, &wrong, 8);
      drainage::dv_fix_checksums(bytes.data(), bytes.size());
      std::ofstream(in("valid127.dv"), std::ios::binary) << bytes;
    }
    std::ofstream(in("comma.xyz"))
        << "562270.00 5117000 1915.5\n562280.00 5117010 1916.5\n562290 5117000 1917\n"
           "562270.00 1,5 1915.545\n";
    std::ofstream(in("four.xyz"))
        << "562270 5117000 1915.5 7\n562280 5117010 1916.5 7\n562290 5117000 1917 7\n";
    for (const std::string x : {"nan", "abc", ""})
      std::ofstream(in("x_" + (x.empty() ? std::string("empty") : x) + ".csv"))
          << "x,y,z\n562270,5117000,1915\n562280,5117010,1916\n"
          << x << ",5117000,1917\n562290,5117020,1917\n";
    for (const auto& [column, value] :
         std::vector<std::pair<std::string, std::string>>{{"view_alt", "1000"},
                                                          {"light_alt", "-500"},
                                                          {"min_score", "5"},
                                                          {"sw", "-5"},
                                                          {"falloff", "-7"},
                                                          {"pel_threshold", "-3"},
                                                          {"fov", "179.99"}})
      std::ofstream(in("range_" + column + ".csv"))
          << "view_az," << column << "\n200," << value << "\n";
    std::ofstream(in("line_stats.csv"))
        << "view_az,view_alt\n200,30\n";  // a frames CSV named like batch's output
    fs::create_directories(in("meshdir"));
    fs::copy_file(in("m.ply"),
                  in("meshdir/frame_00000.png"));  // a mesh named like batch's first frame
    // Issue 63: a mesh and a .dv named like a map's world file; a file named like a
    // GeoPackage that is not one; a pyramid with a damaged tile and one of version 0.
    fs::copy_file(in("m.ply"), in("map.pgw"));
    fs::copy_file(in("m.dv"), in("dvmap.pgw"));
    std::ofstream(in("notgpkg.gpkg")) << "not a GeoPackage\n";
    std::ofstream(in("away.csv"))
        << "view_az,view_alt\n200,30\n200,-60\n";  // the second looks up at the terrain
    sh(tool("dem2mesh") + " " + msh + " " + in("p.ply") + " --spacing 50 --pyramid -q");
    {
      std::string bytes = terrain::test::file_bytes(in("p.tpyr"));
      bytes[bytes.size() - 50] ^= 0x5a;  // in the last tile
      std::ofstream(in("flipped_tile.tpyr"), std::ios::binary) << bytes;
      bytes = terrain::test::file_bytes(in("p.tpyr"));
      bytes[8] = 0;  // the version
      std::ofstream(in("version0.tpyr"), std::ios::binary) << bytes;
    }
    // Issue 48: rough, degree-valued and too-wide DEMs; outlets in degrees; crafted headers.
    {
      std::vector<float> checker(40 * 40);
      for (int r = 0; r < 40; ++r)
        for (int c = 0; c < 40; ++c) checker[std::size_t(r * 40 + c)] = float(100 * ((r + c) % 2));
      make_tif(in("checker.tif"), 40, 40, checker, {500000, 30, 0, 4000000, 0, -30}, kUtm10);
      sh("gdal_translate -q -ot Int16 " + in("checker.tif") + " " + in("checker16.tif"));
      make_tif(in("degrees_no_crs.tif"), 20, 20, plane(20, 20),
               {-122.3, 1.0 / 1200, 0, 46.3, 0, -1.0 / 1200}, "");
      GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GTiff");
      std::unique_ptr<GDALDataset> ds(
          drv->Create(in("uint32.tif").c_str(), 20, 20, 1, GDT_UInt32, nullptr));
      double g[6] = {500000, 10, 0, 4000000, 0, -10};
      ds->SetGeoTransform(g);
      OGRSpatialReference srs;
      srs.SetFromUserInput(kUtm10);
      ds->SetSpatialRef(&srs);
      std::vector<std::uint32_t> high(400);
      for (std::size_t i = 0; i < high.size(); ++i)
        high[i] = 4000000000u + 5u * std::uint32_t(i % 20 + i / 20);
      EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 20, 20, high.data(), 20, 20,
                                               GDT_UInt32, 0, 0),
                CE_None);
    }
    std::ofstream(in("lonlat.csv")) << "lon,lat\n-122.19,46.2\n";
    std::ofstream(in("far_eye.csv")) << "easting,northing,elevation\n562500,5117000,5.6e12\n";
    std::ofstream(in("shot.png.csv")) << "view_az,view_alt\n200,30\n";
    {  // the .dv with an origin z of 1e300, with a projected WKT beside EPSG 4326, with garbage WKT
      const std::string bytes = terrain::test::file_bytes(in("m.dv"));
      auto patched = [&](const std::string& name, std::size_t at, const std::string& with) {
        std::string b = bytes;
        b.replace(at, with.size(), with);
        drainage::dv_fix_checksums(b.data(), b.size());
        std::ofstream(in(name), std::ios::binary) << b;
      };
      const double z = 1e300;
      const std::int32_t epsg = 4326;
      patched("origin_z.dv", 80, std::string(reinterpret_cast<const char*>(&z), 8));
      patched("epsg4326.dv", 104, std::string(reinterpret_cast<const char*>(&epsg), 4));
      patched("garbage_wkt.dv", 128, "GARBAGE");  // the WKT starts after the 128-byte fixed header
    }
    // Replays that write onto the viewer's inputs, or give bad arguments.
    auto replay = [&](const std::string& name, const std::string& text) {
      std::ofstream(in(name)) << text;
    };
    auto at = [&](const std::string& n) { return final + n; };
    replay("r_shot_mesh.txt", "screenshot " + at("meshdir/frame_00000.png") + "\nquit\n");
    replay("r_top.pgw", "screenshot " + at("r_top.png") + "\nquit\n");    // its own world file
    replay("r_top_mesh.txt", "save-view " + at("map.png") + "\nquit\n");  // the mesh's name
    replay("r_window_mesh.txt", "window-shot " + at("meshdir/frame_00000.png") + "\nquit\n");
    replay("r_view_frames.txt", "save-view " + at("shot.png") + "\nquit\n");
    replay("r_keys_self.txt",
           "keyframe\norbit 30 0\nkeyframe\nsave-keyframes " + at("r_keys_self.txt") + "\n");
    replay("r_keys_frames.txt", "keyframe\nkeyframe\nsave-keyframes " + at("shot.png.csv") + "\n");
    replay("r_keys_huge.txt",
           "keyframe\norbit 30 0\nkeyframe\nsave-keyframes " + at("never.csv") + " 1000000000\n");
    replay("r_keys_zero.txt",
           "keyframe\norbit 30 0\nkeyframe\nsave-keyframes " + at("never.csv") + " 0\n");
    replay("r_alt.txt", "camera 562500 5117000 4000 200 200\n");
    replay("r_below.txt", "camera 562500 5117000 0 200 30\n");
    replay("r_far.txt", "camera 562500 5117000 5.6e12 200 30\n");
    replay("r_extra.txt", "camera 562500 5117000 4000 200 30 35 7\n");
    replay("r_zoom.txt", "zoom -1e308\n");
    replay("r_wait_nan.txt", "wait nan\n");
    replay("r_wait_abc.txt", "wait abc\n");
    replay("r_wait_neg.txt", "wait -5\n");
    replay("r_view_row.txt", "set view /nonexistent.csv:3\n");
    replay("r_shot_nopath.txt", "screenshot\n");
    replay("r_shot_svg.txt", "screenshot " + at("never.svg") + "\n");
    std::ofstream(in("r_binary.txt"), std::ios::binary)
        << std::string("\x01\x02\xff\xfe\x1b[2J\x00zz\n", 11);
    return ok;
  }
  static std::string in_;  // the inputs' directory, with a trailing slash
};
std::string BadInput::in_;

std::size_t lines(const std::string& s) {
  return std::size_t(std::count(s.begin(), s.end(), '\n'));
}

TEST_P(BadInput, OneLineNoOutputNoHang) {
  const Row& row = GetParam();
  terrain::test::ScratchDir out;
  std::string cmd = row.command;
  for (std::size_t at; (at = cmd.find("IN/")) != std::string::npos;) cmd.replace(at, 3, in_);
  for (std::size_t at; (at = cmd.find("OUT/")) != std::string::npos;)
    cmd.replace(at, 4, out.path(""));
  const auto r = run("timeout -s KILL 60 " + cmd);
  EXPECT_EQ(r.exit_code, row.exit_code) << cmd << "\nstderr: " << r.err;
  if (row.exit_code == 0) {
    EXPECT_NE(r.out.find(row.message), std::string::npos) << cmd << "\nstdout: " << r.out;
    return;
  }
  EXPECT_EQ(lines(r.err), 1u) << cmd << "\nstderr: " << r.err;
  EXPECT_NE(r.err.find(row.message), std::string::npos) << cmd << "\nstderr: " << r.err;
  EXPECT_EQ(out.n_entries(), 0u) << cmd;
}

const std::string d2m = tool("dem2mesh") + " ", bd = tool("build-drainage") + " ",
                  ti = tool("terrain-inspect") + " ", dn = tool("denoise-normals") + " ",
                  tr = tool("terrain-render") + " ",
                  tv = tool("terrain-view") + " --offscreen -q --size 320x180 ";
const std::string msh = data("msh_2007_utm10n_10m.tif") + " ";

INSTANTIATE_TEST_SUITE_P(
    AllTools, BadInput,
    ::testing::Values(
        // dem2mesh: files that are not DEMs
        Row{d2m + "IN/missing.tif OUT/o.ply -q", 1, "no such file"},
        Row{d2m + "IN/pts_two.xyz OUT/o.ply --spacing 10 --src-crs EPSG:32610 -q", 1,
            "a surface needs at least 3"},
        Row{d2m + "IN/pts_line.xyz OUT/o.ply --spacing 10 --src-crs EPSG:32610 -q", 1, "collinear"},
        Row{d2m + "IN/pts_nan2.xyz OUT/o.ply --spacing 10 --src-crs EPSG:32610 -q", 1,
            "point 2 has a non-finite"},
        Row{d2m + "IN/pts.xyz OUT/o.ply --spacing 10 -q", 1, "no CRS: give it with --src-crs"},
        Row{d2m + "IN/pts.xyz OUT/o.ply --src-crs EPSG:32610 -q", 1, "need --spacing"},
        Row{d2m +
                "IN/pts.xyz OUT/o.ply --spacing 10 --src-crs EPSG:32610 --bbox 500 500 600 600 -q",
            1, "outside the points' convex hull"},
        Row{d2m + "IN/pts_case.csv OUT/o.ply --spacing 10 --src-crs EPSG:32610 -q", 1,
            "CSV columns 'X' and 'x' have the same name"},
        Row{d2m + msh + "OUT/o.ply --spacing 50 --fit-iterations 5 -q", 2,
            "--fit-iterations requires --fit-normals"},
        Row{d2m + msh + "OUT/o.ply --spacing 50 --fit-normals --fit-regularization -1 -q", 2,
            "--fit-regularization"},
        Row{d2m + "IN/empty.tif OUT/o.ply -q", 1, "not a raster GDAL can open"},
        Row{d2m + "IN/a_directory OUT/o.ply -q", 1, "it is a directory"},
        Row{d2m + "IN/truncated.tif OUT/o.ply -q", 1, "cannot read"},
        Row{d2m + "IN/png_renamed.tif OUT/o.ply -q", 1, "an image without georeferencing"},
        Row{d2m + "NETCDF:IN/missing.nc:Band1 OUT/o.ply -q", 1, "not a raster GDAL can open"},
        // dem2mesh: DEMs with bad values or shapes
        Row{d2m + "IN/all_nodata.tif OUT/o.ply -q", 1, "every sample is no-data"},
        Row{d2m + "IN/inf_cell.tif OUT/o.ply -q", 1,
            "1 samples are infinite (the first at row 0, column 5)"},
        Row{d2m + "IN/one_by_one.tif OUT/o.ply -q", 1, "a DEM needs at least 2 x 2"},
        Row{d2m + "IN/one_by_n.tif OUT/o.ply -q", 1, "a DEM needs at least 2 x 2"},
        Row{d2m + "IN/two_by_two.tif OUT/o.ply -q", 0, "vertices: 4\n"},
        Row{d2m + "IN/huge.vrt OUT/o.ply -q", 1, "more than a mesh file can index"},
        Row{ti + "info IN/huge.vrt", 1, "more than this machine's memory"},
        Row{d2m + "IN/rotated.tif OUT/o.ply -q", 1, "rotated or sheared geotransform"},
        Row{d2m + "IN/no_crs.tif OUT/o.ply", 0, "crs: none"},
        // dem2mesh: requests
        Row{d2m + msh + "OUT/o.ply --spacing 0", 2, "--spacing"},
        Row{d2m + msh + "OUT/o.ply --spacing -5", 2, "--spacing"},
        Row{d2m + msh + "OUT/o.ply --spacing nan", 2, "--spacing"},
        Row{d2m + msh + "OUT/o.ply --spacing 100000 -q", 1, "a mesh needs at least 2 x 2"},
        Row{d2m + msh + "OUT/o.ply --bbox 0 0 10 10 -q", 1, "lies outside the DEM"},
        Row{d2m + msh + "OUT/o.ply --center 562500 nan --size 100 100", 2, "not a finite number"},
        Row{d2m + msh + "OUT/o.ply --resample nearest", 2, "--resample"},
        Row{d2m + msh + "OUT/o.ply --utm-zone 10N -q", 1,
            "--utm-zone applies to geographic DEMs only"},
        // dem2mesh: geography
        Row{d2m + "IN/cross_zone.tif OUT/o.ply -q", 0, "UTM zone 18N"},
        Row{d2m + "IN/south.tif OUT/o.ply -q", 0, "UTM zone 18S"},
        Row{d2m + "IN/lat85.tif OUT/o.ply -q", 1, "outside the UTM band"},
        // dem2mesh: outputs
        Row{d2m + msh + "OUT/no/such/dir/o.ply -q", 1, "does not exist"},
        Row{d2m + msh + "/proc/o.ply --spacing 50 -q", 1, "cannot write '/proc/o.ply'"},
        Row{d2m + "IN/plane.tif IN/plane.tif -q", 1, "OUTPUT must be a .ply file"},
        Row{d2m + "IN/plane.tif OUT/o.ply --grid-out IN/plane.tif -q", 1, "is the input"},
        Row{d2m + "IN/plane.tif OUT/o.ply --grid-out OUT/o.ply -q", 1,
            "two outputs are the same file"},
        // formats nobody tuned for: dem2mesh and build-drainage --raster work on each
        Row{d2m + "IN/m.envi OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "IN/m.img OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "IN/m.nc OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "NETCDF:IN/m.nc:Band1 OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "IN/m.xyz OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "IN/m.asc OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "IN/mosaic.vrt OUT/o.ply --spacing 50 -q", 0, "vertices: 5368"},
        Row{d2m + "IN/m.dt0 OUT/o.ply -q", 0, "UTM zone 18N"},
        Row{bd + "--raster " + msh + "OUT/o.dv --keep-pits -q", 1,
            "--keep-pits applies to mesh mode"},
        Row{bd + "IN/m.ply OUT/o.dv --keep-pits --fill -q", 2, "--fill excludes --keep-pits"},
        Row{bd + "--raster IN/m.envi OUT/o.dv -q", 0, "points: 133926"},
        Row{bd + "--raster IN/m.img OUT/o.dv -q", 0, "points: 133926"},
        Row{bd + "--raster IN/m.nc OUT/o.dv -q", 0, "points: 133926"},
        Row{bd + "--raster IN/m.xyz OUT/o.dv -q", 0, "points: 133926"},
        Row{bd + "--raster IN/m.asc OUT/o.dv -q", 0, "points: 133926"},
        Row{bd + "--raster IN/mosaic.vrt OUT/o.dv -q", 0, "points: 133926"},
        Row{bd + "--raster IN/m.dt0 OUT/o.dv -q", 0,
            "points: 14641"},  // geographic: per-row metric cells
        Row{bd + "--raster IN/plane.tif OUT/o.dv --spacing 5 -q", 1,
            "--spacing applies to mesh mode only"},
        // build-drainage
        Row{bd + "--raster IN/all_nodata.tif OUT/o.dv -q", 1, "has no valid sample"},
        Row{bd + "--raster IN/all_nodata.tif OUT/o.dv --tile-size 64 -q", 1, "has no valid sample"},
        Row{bd + "IN/truncated.ply OUT/o.dv --memory 100 -q", 1, "--memory applies to --raster"},
        Row{bd + "--raster IN/plane.tif OUT/o.dv --threads 100000", 2, "--threads"},
        Row{bd + "IN/truncated.ply OUT/o.dv -q", 1, "truncated"},
        Row{bd + "IN/wrong_header.ply OUT/o.dv -q", 1, "expected 'element NAME COUNT'"},
        Row{bd + "IN/ascii.ply OUT/o.dv -q", 1, "in ascii format"},
        Row{bd + "IN/extra_element.ply OUT/o.dv -q", 1, "unexpected PLY element 'material'"},
        Row{bd + "IN/m.ply OUT/o.dv --surface IN/m.ply -q", 1, "is the input"},
        Row{bd + "IN/m.ply OUT/o.dv --spacing inf", 2, "--spacing"},
        Row{bd + "IN/m.ply OUT/o.dv --breach 5 --fill", 2, "--fill excludes --breach"},
        Row{bd + "IN/m.ply OUT/o.dv --breach -1", 2, "--breach"},
        Row{bd + "--raster IN/plane.tif OUT/o.dv --breach 5 --tile-size 64 -q", 1,
            "--breach runs untiled only"},
        Row{bd + "IN/m.ply OUT/o.dv --surface OUT/o.dv -q", 1, "two outputs are the same file"},
        Row{bd + "IN/m.ply OUT/o.dv --snap-distance 10 -q", 1, "go with --outlets POINTS"},
        Row{bd + "IN/m.ply OUT/o.dv --outlets IN/missing.gpkg -q", 1, "cannot read outlets from"},
        Row{bd + "IN/m.ply OUT/o.dv --outlets IN/plane.tif -q", 1, "cannot read outlets from"},
        Row{bd + "IN/m.ply OUT/o.dv --outlets IN/plane.tif --watersheds OUT/w.shp -q", 1,
            "must name a .gpkg"},
        Row{bd + "IN/m.ply OUT/o.dv --outlets IN/plane.tif --snap-distance -5", 2,
            "--snap-distance"},
        // terrain-inspect
        Row{ti + "info IN/zero.dv", 1, "not a raster GDAL can open"},
        Row{ti + "info IN/flipped.dv", 1, "checksum mismatch"},
        Row{ti + "preview IN/flipped.dv -o OUT/p.png", 1, "checksum mismatch"},
        Row{ti + "preview IN/empty.tif -o OUT/p.png", 1, "not a raster GDAL can open"},
        Row{ti + "export IN/m.ply --to tif -o IN/m.ply", 1, "is the input"},
        Row{ti + "export IN/m.ply --to stl -o OUT/m.stl", 2, "--to"},
        Row{ti + "export IN/m.dv --to gpkg --layers branches,rivers -o OUT/m.gpkg", 2, "--layers"},
        Row{ti + "export IN/m.dv --to gpkg --layers hachures -o OUT/m.gpkg", 1, "a mesh's layer"},
        Row{ti + "export IN/m.ply --dv IN/m.ply --to svg -o OUT/m.svg", 1,
            "is not a drainage database"},
        Row{ti + "export IN/m.ply --dv IN/m.dv --to obj -o OUT/m.obj", 1,
            "only a mesh's hachure map"},
        Row{ti + "export IN/m.ply --dv IN/missing.dv --to svg -o OUT/m.svg", 2, "--dv"},
        Row{ti + "export IN/m.ply --to gpkg --layers branches -o OUT/m.gpkg", 1,
            "a mesh exports only hachures"},
        Row{ti + "export IN/m.dv --to svg -o OUT/m.svg", 1, "only meshes export to svg"},
        Row{ti + "export IN/m.ply --to svg --scale 0 -o OUT/m.svg", 2, "--scale"},
        Row{ti + "preview IN/m.ply -o OUT/p.png --azimuth nan", 2, "not a finite number"},
        // denoise-normals
        Row{dn + "IN/m.ply OUT/d.ply --sigma-s -1", 2, "--sigma-s"},
        Row{dn + "IN/m.ply OUT/d.ply --sigma-s 0", 2, "--sigma-s"},
        Row{dn + "IN/m.ply OUT/d.ply --sigma-s nan", 2, "--sigma-s"},
        Row{dn + "IN/truncated.ply OUT/d.ply -q", 1, "truncated"},
        Row{dn + "IN/m.ply IN/m.ply -q", 1, "is the input"},
        // terrain-render
        Row{tr + "batch IN/m.ply IN/m.dv IN/nan.csv -o OUT/ -q", 1,
            "nan.csv:2: field 'elevation': 'nan' is not a number"},
        Row{tr + "batch IN/m.ply IN/inf.csv -o OUT/ -q", 1,
            "inf.csv:2: field 'view_alt': 'inf' is not a number"},
        Row{tr + "batch IN/m.ply IN/inside.csv -o OUT/ -q", 1,
            "frame 1: the eye (562500.0, 5117000.0, 1000.0) is inside"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --eye 562500 5117000 1000 -q", 1,
            "is inside the terrain"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --eye 562500 nan 3000", 2, "not a finite number"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --view-az nan", 2,
            "--view-az: 'nan' is not a number"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --view sideways", 2, "--view"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --view IN/none.csv:1 -q", 1, "none.csv"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --view IN/inf.csv -q", 1,
            "inf.csv:2: field 'view_alt': 'inf' is not a number"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --size 0x0", 2, "--size"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --memory 0", 2, "--memory: Value 0 not in range"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --size 100000x100000", 2, "--size"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --layers shaded,contours -q", 2,
            "unknown layer 'contours'"},
        Row{tr + "frame IN/m.ply IN/zero.dv -o OUT/f.png -q", 1, "is not a drainage database"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --layers mask,edges --edges contour,valley -q", 2,
            "unknown edge kind 'valley'"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --layers mask,edges --edge-caps round", 2,
            "--edge-caps"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --layers mask,edges --crease-angle 200", 2,
            "--crease-angle"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --layers mask,silhouettes,silhouettes-adjacency -q",
            2, "choose silhouettes (Toward/Away) or silhouettes-adjacency"},
        Row{tr + "path --from 0 0 nan --to 1 1 1 --frames 3 -o OUT/p.csv", 2,
            "not a finite number"},
        // issue 37: vector output
        Row{tr + "frame IN/m.ply -o OUT/f.eps -q", 1,
            "the output must be a .png, .tif, .svg, .pdf or .gpkg file"},
        Row{tr + "frame IN/m.ply -o OUT/f.svg --vector-underlay relief", 2, "--vector-underlay"},
        Row{tr + "frame IN/m.ply -o OUT/f.pdf --dpi 0", 2, "--dpi"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --line-scale 0", 2, "--line-scale"},
        Row{tr + "batch IN/m.ply IN/inf.csv -o OUT/ --format png,gif -q", 2,
            "unknown format 'gif'"},
        Row{tr + "batch IN/m.ply IN/inf.csv -o OUT/ --format svg,svg -q", 2,
            "'svg' is given twice"},
        Row{tr + "batch IN/m.ply IN/shot.png.csv -o OUT/ --format png,gpkg -q", 1,
            "frame 1 is no map (a top view): --format gpkg holds a map's lines"},
        Row{"env TERRAIN_MEMORY_MIB=1000 " + tr + "frame IN/m.ply -o OUT/f.svg --size 4000x4000 -q",
            1, "the vector output of a 4000 x 4000 frame needs"},
        Row{tr + "path --from 0 0 100 --to 1 1 100 --frames 3 -o /dev/null", 1,
            "not a regular file"},
        // issue 41: hostile metadata, malformed numbers, outputs on inputs, sizes beyond memory
        Row{bd + "--raster IN/big.vrt OUT/o.dv -q", 1,
            "an untiled run of 40000 x 40000 cells needs"},
        Row{bd + "--raster IN/big.vrt OUT/o.dv -q", 1, "run it tiled"},
        Row{d2m + "IN/big.vrt OUT/o.ply -q", 1, "more than this machine's memory available now"},
        Row{d2m + "IN/zero_width.tif OUT/o.ply -q", 1, "georeferenced by ground control points"},
        Row{bd + "--raster IN/zero_width.tif OUT/o.dv -q", 1,
            "georeferenced by ground control points"},
        Row{bd + "--raster IN/lat95.tif OUT/o.dv -q", 1, "lies outside the globe"},
        Row{bd + "IN/m.ply OUT/o.dv --spacing 1e7 -q", 1, "needs at least 2 x 2"},
        Row{bd + "IN/m.ply OUT/o.dv --spacing 1e300 -q", 1, "needs at least 2 x 2"},
        Row{bd + "IN/dx100.ply OUT/o.dv -q", 1, "not on the grid comment's 100 x 50 m lattice"},
        Row{ti + "info IN/dx100.ply", 1, "not on the grid comment's 100 x 50 m lattice"},
        Row{ti + "preview IN/dx100.ply -o OUT/p.png", 1,
            "not on the grid comment's 100 x 50 m lattice"},
        Row{ti + "export IN/dx100.ply --to tif -o OUT/e.tif", 1,
            "not on the grid comment's 100 x 50 m lattice"},
        Row{tr + "frame IN/dx100.ply -o OUT/f.png -q", 1,
            "not on the grid comment's 100 x 50 m lattice"},
        Row{dn + "IN/dx100.ply OUT/d.ply -q", 1, "not on the grid comment's 100 x 50 m lattice"},
        Row{bd + "IN/dx1e300.ply OUT/o.dv -q", 1, "outside what a terrain mesh can be"},
        Row{ti + "info IN/dx1e300.ply", 1, "outside what a terrain mesh can be"},
        Row{bd + "IN/dx5e-324.ply OUT/o.dv -q", 1, "outside what a terrain mesh can be"},
        Row{ti + "info IN/dx5e-324.ply", 1, "outside what a terrain mesh can be"},
        Row{bd + "IN/origin1e300.ply OUT/o.dv -q", 1, "outside what a terrain mesh can be"},
        Row{ti + "info IN/origin1e300.ply", 1, "outside what a terrain mesh can be"},
        Row{ti + "export IN/missing.ply --to tif -o OUT/e.tif", 1, "missing.ply': no such file"},
        Row{ti + "info IN/valid127.dv", 1, "valid points, the header says 127"},
        Row{ti + "preview IN/valid127.dv -o OUT/p.png", 1, "valid points, the header says 127"},
        Row{ti + "export IN/valid127.dv --to gpkg -o OUT/e.gpkg", 1,
            "valid points, the header says 127"},
        Row{tr + "frame IN/m.ply IN/valid127.dv -o OUT/f.png -q", 1,
            "valid points, the header says 127"},
        Row{d2m + "IN/comma.xyz OUT/o.ply --spacing 5 --src-crs EPSG:32610 -q", 1,
            "line 4: expected x y z, got '562270.00 1,5 1915.545' ('1,5' is not a number)"},
        Row{d2m + "IN/four.xyz OUT/o.ply --spacing 5 --src-crs EPSG:32610 -q", 1,
            "line 1: expected x y z"},
        Row{d2m + "IN/x_nan.csv OUT/o.ply --spacing 5 --src-crs EPSG:32610 -q", 1,
            "line 4: no point"},
        Row{d2m + "IN/x_abc.csv OUT/o.ply --spacing 5 --src-crs EPSG:32610 -q", 1,
            "line 4: no point"},
        Row{d2m + "IN/x_empty.csv OUT/o.ply --spacing 5 --src-crs EPSG:32610 -q", 1,
            "line 4: no point"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_view_alt.csv -o OUT/ -q", 1,
            "range_view_alt.csv:2: field 'view_alt': 1000 is outside -90 .. 90"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_light_alt.csv -o OUT/ -q", 1,
            "range_light_alt.csv:2: field 'light_alt': -500 is outside -90 .. 90"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_min_score.csv -o OUT/ -q", 1,
            "range_min_score.csv:2: field 'min_score': 5 is outside 0 .. 1"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_sw.csv -o OUT/ -q", 1,
            "range_sw.csv:2: field 'sw': -5 is outside 0 .. 1"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_falloff.csv -o OUT/ -q", 1,
            "range_falloff.csv:2: field 'falloff': -7 is outside 0 .. 1"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_pel_threshold.csv -o OUT/ -q", 1,
            "range_pel_threshold.csv:2: field 'pel_threshold': -3 is outside 0 .. 1"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/range_fov.csv -o OUT/ -q", 1,
            "range_fov.csv:2: field 'fov': 179.99 is outside 1 .. 170"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --crease-lift -5", 2, "--crease-lift"},
        Row{tr + "batch IN/m.ply IN/m.dv IN/line_stats.csv -o IN/ --line-stats -q", 1,
            "line_stats.csv': give another output name"},
        Row{tr + "batch IN/meshdir/frame_00000.png IN/m.dv IN/line_stats.csv -o IN/meshdir -q", 1,
            "frame_00000.png': give another output name"},
        Row{"env TERRAIN_MEMORY_MIB=4000 " + tr +
                "frame IN/m.ply IN/m.dv -o OUT/f.png --size 16384x16384 -q",
            1, "the largest frame of this shape that fits is about"},
        // issue 48: rough DEMs fit, degrees without a CRS, heights beyond single precision
        Row{d2m + "IN/checker.tif OUT/o.ply --spacing 50 --fit-normals -q", 0, "normals: fitted"},
        Row{d2m + "IN/checker16.tif OUT/o.ply --spacing 50 --fit-normals -q", 0, "normals: fitted"},
        Row{d2m + "IN/checker.tif OUT/o.ply --fit-normals -q", 0, "normals: fitted"},
        Row{d2m + "IN/degrees_no_crs.tif OUT/o.ply -q", 1,
            "no CRS and its coordinates look like degrees"},
        Row{d2m + "IN/degrees_no_crs.tif OUT/o.ply --src-crs EPSG:4326 -q", 0, "UTM zone 10N"},
        Row{d2m + "IN/no_crs.tif OUT/o.ply --src-crs EPSG:26910 -q", 0, "EPSG:26910"},
        Row{d2m + "IN/plane.tif OUT/o.ply --src-crs EPSG:9999999 -q", 1,
            "cannot understand the CRS"},
        Row{d2m + "IN/uint32.tif OUT/o.ply -q", 1, "steps would be lost"},
        // issue 48: outlets that cannot be grid coordinates, snaps beyond the grid
        Row{bd + "IN/m.ply OUT/o.dv --outlets IN/lonlat.csv -q", 1,
            "look like longitude and latitude"},
        Row{bd + "IN/m.ply OUT/o.dv --outlets IN/lonlat.csv --snap-distance 1e7 -q", 1,
            "exceeds the grid's size"},
        // issue 48: crafted .dv headers, refused by every reader
        Row{ti + "info IN/origin_z.dv", 1, "outside what a terrain grid can be"},
        Row{ti + "export IN/origin_z.dv --to tif -o OUT/r", 1,
            "outside what a terrain grid can be"},
        Row{ti + "export IN/epsg4326.dv --to tif -o OUT/r", 1, "its EPSG field says 4326"},
        Row{ti + "export IN/epsg4326.dv --to gpkg -o OUT/e.gpkg", 1, "its EPSG field says 4326"},
        Row{ti + "info IN/garbage_wkt.dv", 1, "CRS WKT does not parse"},
        Row{tr + "frame IN/m.ply IN/garbage_wkt.dv -o OUT/f.png -q", 1, "CRS WKT does not parse"},
        Row{ti + "preview IN/epsg4326.dv -o OUT/p.png", 1, "its EPSG field says 4326"},
        // a failed export leaves no folder it made (before: a/b/c stayed, empty)
        Row{ti + "export IN/flipped.dv --to tif -o OUT/a/b/c", 1, "checksum mismatch"},
        Row{ti + "export IN/m.ply --to tif -o OUT/a/b/c.tif", 1, "does not exist"},
        // issue 48: vector files of no lines, eyes that would draw a blank frame
        Row{tr + "frame IN/m.ply -o OUT/f.svg --layers shaded --vector-underlay none -q", 1,
            "the vector file would be empty"},
        Row{tr + "frame IN/m.ply -o OUT/f.pdf --layers mask,creases --vector-underlay none -q", 1,
            "creases need a .dv"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --eye 562500 5117000 5.6e12 -q", 1, "move it closer"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --eye 1e308 5117000 3000 -q", 1, "move it closer"},
        Row{tr + "batch IN/m.ply IN/far_eye.csv -o OUT/ -q", 1, "far_eye.csv: frame 1: the eye"},
        Row{tr + "path --from 0 0 1e308 --to 1 1 1 --frames 3 -o OUT/p.csv", 2, "--from"},
        // issue 49: --line-scale checked against the drawn range in the table (before: past
        // --help's limits, exit 1)
        Row{tr + "frame IN/m.ply -o OUT/f.png --layers mask,edges --edge-width 20 --line-scale 4",
            2, "--edge-width 20 x --line-scale 4 = 80 pixels is outside the 0 .. 64 pixels drawn"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --line-scale 0.2", 2,
            "--silhouette-width 1 x --line-scale 0.2 = 0 pixels"},
        // issue 48: the viewer writes none of its inputs, and checks its replay as the table checks
        // options
        Row{tv + "IN/meshdir/frame_00000.png IN/m.dv --replay IN/r_shot_mesh.txt", 1,
            "frame_00000.png' is the input"},
        Row{tv + "IN/meshdir/frame_00000.png IN/m.dv --replay IN/r_window_mesh.txt", 1,
            "frame_00000.png' is the input"},
        Row{tv + "IN/m.ply IN/m.dv --frames IN/shot.png.csv --replay IN/r_view_frames.txt", 1,
            "shot.png.csv' is the input"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_keys_self.txt", 1, "replay line 4: the output '"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_keys_self.txt --memory 0", 2,
            "--memory: Value 0 not in range"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_keys_frames.txt --frames IN/shot.png.csv", 1,
            "replay line 3: the output '"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_keys_huge.txt", 1,
            "replay line 4: save-keyframes: N: 1000000000 is outside 2 .. 100000"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_keys_zero.txt", 1,
            "save-keyframes: N: 0 is outside 2 .. 100000"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_alt.txt", 1,
            "replay line 1: camera: view-alt: 200 is outside -90 .. 90"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_below.txt", 1, "is inside the terrain"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_far.txt", 1, "move it closer"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_extra.txt", 1,
            "expected camera E N Z AZ ALT [FOV]"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_zoom.txt", 1, "zoom: SHARE: -1e308 is outside"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_wait_nan.txt", 1,
            "wait: N: 'nan' is not a finite number"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_wait_abc.txt", 1,
            "wait: N: 'abc' is not a finite number"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_wait_neg.txt", 1,
            "wait: N: -5 is outside 0 .. 100000"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_view_row.txt", 1, "nonexistent.csv"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_shot_nopath.txt", 1,
            "expected screenshot PATH [WxH]"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_shot_svg.txt", 1, "give a .png name"},
        Row{tv + "IN/m.ply IN/m.dv --replay IN/r_binary.txt", 1,
            "replay line 1: unknown replay command '????"},
        Row{tv + "IN/m.ply IN/m.dv --frames IN/far_eye.csv --replay IN/r_alt.txt", 1,
            "far_eye.csv: frame 1: the eye"},
        // issue 63: a map's world file is an output; GeoPackages; pictures without terrain;
        // messages
        Row{tr + "frame IN/map.pgw IN/m.dv --view top -o IN/map.png -q", 1,
            "map.pgw' is the input"},
        Row{tr + "frame IN/m.ply IN/dvmap.pgw --view top -o IN/dvmap.png -q", 1,
            "dvmap.pgw' is the input"},
        Row{tv + "IN/m.ply IN/m.dv --view top --replay IN/r_top.pgw", 1, "r_top.pgw' is the input"},
        Row{tv + "IN/map.pgw IN/m.dv --view top --replay IN/r_top_mesh.txt", 1,
            "map.pgw' is the input"},
        Row{ti + "export IN/m.dv --to gpkg -o OUT/x.png", 1, "give -o a name ending in .gpkg, not"},
        Row{ti + "export IN/m.ply --to svg -o OUT/m.pdf", 1, "give -o a name ending in .svg, not"},
        Row{ti + "export IN/m.ply --to obj -o OUT/m.ply", 1, "give -o a name ending in .obj, not"},
        Row{ti + "export IN/m.ply --to tif -o OUT/m.png", 1, "give -o a name ending in .tif, not"},
        Row{ti + "export IN/m.dv --to obj -o OUT/m.obj", 1, "only meshes export to obj"},
        Row{ti + "export IN/m.ply --to gpkg -o OUT/x.png", 1,
            "give -o a name ending in .gpkg, not"},
        Row{ti + "export IN/m.dv --to gpkg -o IN/notgpkg.gpkg", 1,
            "it exists and is not a GeoPackage"},
        Row{ti + "export IN/m.ply --to svg --scale 1e6 -o OUT/s.svg", 1,
            "too small to show the terrain: give a --scale"},
        Row{ti + "export IN/m.ply --to pdf --scale 1e6 -o OUT/s.pdf", 1,
            "too small to show the terrain"},
        Row{"env TERRAIN_MEMORY_MIB=200 " + ti +
                "export IN/m.ply --to svg --scale 0.08 -o OUT/s.svg",
            1, "more than this machine's memory available now (200.0 MiB); give --scale"},
        Row{tr + "frame IN/m.ply IN/m.dv --view top --map-scale 1e4 -o OUT/f.png -q", 1,
            "--map-scale 10000 is too coarse; give"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --view-alt -60 -q", 1, "sees only its underside"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --eye 562500 5117000 4000 --view-alt -60 -q", 1,
            "the frame shows nothing of the terrain"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --eye 1562500 5117000 5000 --view-alt 0 --view-az "
                 "270 -q",
            1, "the eye is too far from it"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --size 320X240", 0, "size: 320 x 240"},
        Row{tr + "batch IN/m.ply IN/away.csv -o OUT/ --size 160x120 -q", 0,
            "frames without terrain: 1"},
        Row{tr + "frame IN/m.ply -o OUT/f.png --size 320x240 --view top --map-scale 0.001", 0,
            "0.001 m a pixel"},
        Row{bd + "IN/m.ply OUT/o.dv --breach -1", 2,
            "--breach: '-1' is not a non-negative number (see"},
        Row{"env TERRAIN_MEMORY_MIB=abc " + bd + "IN/m.ply OUT/o.dv -q", 1,
            "TERRAIN_MEMORY_MIB='abc' is not a number"},
        Row{"env TERRAIN_MEMORY_MIB=-5 " + d2m + msh + "OUT/o.ply -q", 1,
            "TERRAIN_MEMORY_MIB='-5' is not a number"},
        Row{"env TERRAIN_MEMORY_MIB=1e99 " + ti + "info IN/m.ply", 1,
            "TERRAIN_MEMORY_MIB='1e99' is not a number"},
        Row{"env TERRAIN_MEMORY_MIB=1 " + d2m + msh + "OUT/o.ply -q", 1,
            "memory available now (1.0 MiB)"},
        Row{ti + "info IN/flipped_tile.tpyr", 1, "is corrupt (its checksum)"},
        Row{ti + "info IN/version0.tpyr", 1, "corrupt mesh pyramid (version 0)"},
        Row{ti + "info IN/p.tpyr", 0, "tiles_checked: "}),
    row_name);

}  // namespace
