// Outputs that belong together and inputs that change under a reader (issue 63): a
// GeoPackage export adds or replaces its own layers and keeps the others, atomically; a
// map's PNG and its world file land together; a render while dem2mesh rewrites its mesh
// and pyramid draws one of the two terrains whole, or says the pair changed.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <sys/mount.h>

#include <filesystem>
#include <regex>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using terrain::test::data;
using terrain::test::run;
using terrain::test::tool;

// The layers ogrinfo lists, in its order, and the feature count of `layer`.
std::string layers_of(const std::string& gpkg) {
  const auto r = run("ogrinfo -q " + gpkg);
  std::string out;
  const std::regex line(R"(\d+: (\w+) \()");
  for (std::sregex_iterator it(r.out.begin(), r.out.end(), line), end; it != end; ++it)
    out += (*it)[1].str() + " ";
  return out;
}
// The layers the QGIS styles (layer_styles) are for, one a row, in order.
std::string styled_layers_of(const std::string& gpkg) {
  const auto r =
      run("ogrinfo -q -sql \"SELECT f_table_name FROM layer_styles ORDER BY id\" " + gpkg);
  std::string out;
  const std::regex line(R"(f_table_name \(String\) = (\w+))");
  for (std::sregex_iterator it(r.out.begin(), r.out.end(), line), end; it != end; ++it)
    out += (*it)[1].str() + " ";
  return out;
}
long count_of(const std::string& gpkg, const std::string& layer) {
  const auto r = run("ogrinfo -q -sql \"SELECT COUNT(*) FROM " + layer + "\" " + gpkg);
  std::smatch m;
  return std::regex_search(r.out, m, std::regex(R"(= (\d+))")) ? std::stol(m[1]) : -1;
}

struct Inputs {
  terrain::test::ScratchDir dir;
  std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv");
  Inputs() {
    EXPECT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                  " --spacing 50 -q")
                  .exit_code,
              0);
    EXPECT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --spacing 25 -q").exit_code,
              0);
  }
};

// A QGIS user exported the drainage layers and then the hachure map: the defaults are two
// files (M.gpkg, M_map.gpkg); into one named file, the second export adds its layer and the
// first's stay, whole; exported again, a layer is replaced, not doubled; an export that
// fails (a file-size limit) leaves the GeoPackage as it was, byte for byte.
TEST(OutputSets, AGeoPackageExportKeepsTheOtherLayers) {
  Inputs in;
  const std::string ti = tool("terrain-inspect") + " export ";
  ASSERT_EQ(run(ti + in.dv + " --to gpkg -q").exit_code, 0);
  ASSERT_EQ(run(ti + in.mesh + " --to gpkg -q").exit_code, 0);
  EXPECT_EQ(layers_of(in.dir.path("m.gpkg")), "branches basins divides layer_styles ");
  EXPECT_EQ(styled_layers_of(in.dir.path("m.gpkg")), "branches basins divides ");
  EXPECT_EQ(layers_of(in.dir.path("m_map.gpkg")), "hachures layer_styles ");
  EXPECT_EQ(styled_layers_of(in.dir.path("m_map.gpkg")), "hachures ");

  const std::string both = in.dir.path("both.gpkg");
  ASSERT_EQ(run(ti + in.dv + " --to gpkg -o " + both + " -q").exit_code, 0);
  const long branches = count_of(both, "branches"), basins = count_of(both, "basins");
  ASSERT_GT(branches, 100);
  ASSERT_EQ(run(ti + in.mesh + " --to gpkg -o " + both + " -q").exit_code, 0);
  const long hachures = count_of(both, "hachures");
  ASSERT_GT(hachures, 100);
  EXPECT_EQ(layers_of(both), "branches basins divides hachures layer_styles ");
  EXPECT_EQ(count_of(both, "branches"), branches);
  EXPECT_EQ(count_of(both, "basins"), basins);
  ASSERT_EQ(run(ti + in.mesh + " --to gpkg -o " + both + " -q").exit_code, 0);
  EXPECT_EQ(count_of(both, "hachures"), hachures);
  EXPECT_EQ(layers_of(both), "branches basins divides hachures layer_styles ");
  // One style a layer: a layer written again has its style replaced, the others kept.
  EXPECT_EQ(styled_layers_of(both), "branches basins divides hachures ");
  // The drainage layers added to a map's GeoPackage under a file-size limit they exceed.
  const std::string map = in.dir.path("m_map.gpkg"), before = terrain::test::file_bytes(map);
  const auto failed = run("ulimit -f " + std::to_string(fs::file_size(map) / 512 + 8) + "; exec " +
                          ti + in.dv + " --to gpkg -o " + map);
  EXPECT_EQ(failed.exit_code, 1) << failed.err;
  EXPECT_NE(failed.err.find("cannot write '" + map + "'"), std::string::npos) << failed.err;
  EXPECT_EQ(std::count(failed.err.begin(), failed.err.end(), '\n'), 1) << failed.err;
  EXPECT_TRUE(terrain::test::file_bytes(map) == before) << "a failed export changed the GeoPackage";
  std::string left;
  for (const auto& e : fs::directory_iterator(in.dir.path("")))
    if (e.path().filename().string().find(".tmp") != std::string::npos)
      left += e.path().string() + " ";
  EXPECT_EQ(left, "");
}

// A map's PNG and its world file are one output set: on a disk with room for the PNG and
// not for the world file, neither is written and the previous pair stays (a small tmpfs,
// filled; skipped where this process may not mount one).
TEST(OutputSets, AMapsPngAndWorldFileLandTogether) {
  Inputs in;
  const std::string disk = in.dir.path("disk");
  fs::create_directory(disk);
  if (::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  struct Unmount {
    std::string at;
    ~Unmount() { ::umount(at.c_str()); }
  } unmount{disk};
  const std::string frame = tool("terrain-render") + " frame " + in.mesh + " " + in.dv +
                            " --view top --size 320x240 -q -o ";
  ASSERT_EQ(run(frame + in.dir.path("top.png")).exit_code, 0);
  ASSERT_TRUE(fs::exists(in.dir.path("top.pgw")));
  fs::copy_file(in.dir.path("top.png"), disk + "/top.png");
  fs::copy_file(in.dir.path("top.pgw"), disk + "/top.pgw");
  // Room for one PNG and its temporary: the old pair is replaced only when both fit.
  const auto df = run("df -B4096 --output=avail " + disk + " | tail -1");
  const long pages = std::stol(df.out),
             png_pages = long(fs::file_size(in.dir.path("top.png")) + 4095) / 4096;
  ASSERT_EQ(run("dd if=/dev/zero of=" + disk +
                "/fill bs=4096 count=" + std::to_string(pages - png_pages) + " 2>/dev/null")
                .exit_code,
            0);
  const std::string png = terrain::test::file_bytes(disk + "/top.png"),
                    pgw = terrain::test::file_bytes(disk + "/top.pgw");
  const auto r = run(frame + disk + "/top.png --map-scale 7");  // another map: other bytes
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(terrain::test::file_bytes(disk + "/top.png") == png)
      << "the PNG was replaced without its world file";
  EXPECT_TRUE(terrain::test::file_bytes(disk + "/top.pgw") == pgw);
  std::string entries;
  for (const auto& e : fs::directory_iterator(disk)) entries += e.path().filename().string() + " ";
  EXPECT_EQ(entries.size(), std::string("fill top.png top.pgw ").size()) << entries;
}

// The pixels of a PNG.
std::vector<unsigned char> pixels_of(const std::string& png) {
  OIIO::ImageBuf buf(png);
  EXPECT_TRUE(buf.read(0, 0, true, OIIO::TypeDesc::UINT8)) << png;
  std::vector<unsigned char> px(std::size_t(buf.spec().width) * std::size_t(buf.spec().height) * 4);
  buf.get_pixels(buf.roi(), OIIO::TypeDesc::UINT8, px.data());
  return px;
}

// The probe's race: renders of m.ply while dem2mesh rewrites m.ply and m.tpyr, two meshes
// of one grid in turn (uniform and angle-weighted normals). Before, 7 % of the reads took
// the header of one PLY and the size of the next ("truncated"), and about 1 in 40 drew the
// preview of one terrain with the level of the other. Now every render draws one of the two
// terrains exactly, or ends with the one line that says the pair changed as it was read.
TEST(Races, ARenderWhileDem2meshRewritesItsMesh) {
  Inputs in;
  const std::string dem = data("msh_2007_utm10n_10m.tif"), d2m = tool("dem2mesh") + " " + dem + " ";
  const std::string m = in.dir.path("r.ply");
  // --memory 0.05 (51 KiB, the mesh's 5,300 vertices take 127 KB): a preview level, then the
  // level the view draws, read from the pyramid in two reads.
  const std::string frame =
      tool("terrain-render") + " frame " + m + " --size 160x120 --memory 0.05 -q -o ";
  // Each terrain drawn from its pyramid, and from its PLY alone (what a reader that finds
  // the pyramid not yet renamed over draws: the PLY, whole).
  std::vector<std::vector<unsigned char>> refs;
  for (const std::string w : {"uniform", "angle"}) {
    ASSERT_EQ(run(d2m + m + " --spacing 50 --pyramid --normal-weighting " + w + " -q").exit_code,
              0);
    ASSERT_EQ(run(frame + in.dir.path("ref_" + w + ".png")).exit_code, 0);
    refs.push_back(pixels_of(in.dir.path("ref_" + w + ".png")));
    fs::rename(in.dir.path("r.tpyr"), in.dir.path("away.tpyr"));
    ASSERT_EQ(run(frame + in.dir.path("ref_ply_" + w + ".png")).exit_code, 0);
    refs.push_back(pixels_of(in.dir.path("ref_ply_" + w + ".png")));
  }
  ASSERT_NE(refs[0], refs[2]);
  terrain::test::Background writer("sh -c 'while true; do " + d2m + m +
                                   " --spacing 50 --pyramid -q; " + d2m + m +
                                   " --spacing 50 --pyramid --normal-weighting angle -q; done'");
  int drawn = 0, changed = 0;
  for (int i = 0; i < 10; ++i) {
    const std::string out = in.dir.path("f" + std::to_string(i) + ".png");
    const auto r = run(frame + out);
    if (r.exit_code == 0) {
      const auto px = pixels_of(out);
      EXPECT_TRUE(std::find(refs.begin(), refs.end(), px) != refs.end())
          << "render " << i << " drew neither terrain";
      ++drawn;
    } else {
      EXPECT_NE(r.err.find("changed while they were read"), std::string::npos) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      ++changed;
    }
  }
  writer.signal(SIGKILL);
  (void)writer.wait();
  std::cout << drawn << " renders drew a terrain, " << changed << " found the pair changed\n";
  EXPECT_GT(drawn, 0);
}

}  // namespace
