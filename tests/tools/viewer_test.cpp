// terrain-view under Xvfb (a real window, GLX on llvmpipe) and --offscreen: its replayed
// screenshots are terrain-render frame's PNGs for the same camera and options; its saved
// command line, run, gives the same PNG; its keyframes make a frames CSV that batch
// renders; options set through the replay change the frame as the CLI options do (two of
// each type); --list-options holds every option of the table.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>

#include "renderer/core/options.hpp"
#include "test_support.hpp"

namespace {

using terrain::test::data;
using terrain::test::file_bytes;
using terrain::test::run;
using terrain::test::tool;

// At most 1 % of the pixels differ by more than 8 levels (of 255) in any channel.
bool same_picture(const std::string& a, const std::string& b) {
  return run("oiiotool --fail 0.0314 --failpercent 1 --diff " + a + " " + b).exit_code == 0;
}

// Options set through the replay (and again as they were after the screenshot): about two
// of each type of the option table, as "--name value" pairs of the command line.
const std::vector<std::vector<std::pair<std::string, std::string>>> kChanges = {
    {{"min-score", "0.4"}},         {{"crease-width", "2.5"}},
    {{"min-area", "100000"}},     // numbers
    {{"silhouette-width", "3"}},  // integers (the other, --pel-smooth, draws on PELs only)
    {{"aliased", "true"}},          {{"literal-score", "true"}},                        // flags
    {{"flow-scale", "linear"}},     {{"layers", "mask,edges"}, {"edge-caps", "none"}},  // choices
    {{"crease-colour", "red"}},     {{"background", "#ffffff"}},                        // colours
    {{"layers", "shaded,creases"}}, {{"layers", "mask,edges"}, {"edges", "contour"}},   // lists
};

// The window test replays everything; the offscreen one the default view and a saved
// view (the same commands run either way; the sanitizer build runs the window
// test, and the bad-input rows run the offscreen context there).
void check_viewer(bool window) {
  terrain::test::ScratchDir dir;
  // The window test at the relief view (--view relief: silhouettes in sight, for the changes
  // below), the offscreen one at the automatic view.
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv"),
                    size = std::string(" --size 320x180") + (window ? " --view relief" : "");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 50 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --breach 10 -q").exit_code, 0);
  std::string replay = "screenshot " + dir.path("home.png") + "\nsave-view " +
                       dir.path("view.png") + "\nsave-view " + dir.path("big.png") + " 400x240\n" +
                       "keyframe\norbit 30 0\nkeyframe\norbit 30 5\nkeyframe\nsave-keyframes " +
                       dir.path("keys.csv") + " 5\nkey home\n";
  for (std::size_t i = 0; window && i < kChanges.size(); ++i) {
    for (const auto& [name, value] : kChanges[i]) replay += "set " + name + " " + value + "\n";
    replay += "screenshot " + dir.path("set" + std::to_string(i) + ".png") + "\n";
    for (const auto& [name, value] : kChanges[i])
      replay += "set " + name + " " + renderer::find_option(name)->default_text + "\n";
  }
  replay += "wait 2\nquit\n";
  std::ofstream(dir.path("replay.txt")) << replay;
  const std::string viewer =
      tool("terrain-view") + " " + mesh + " " + dv + size + " --replay " + dir.path("replay.txt");
  const auto v =
      run(window ? "xvfb-run -a -s '-screen 0 640x480x24' " + viewer : viewer + " --offscreen");
  ASSERT_EQ(v.exit_code, 0) << v.err;

  const std::string render =
      tool("terrain-render") + " frame " + mesh + " " + dv + size + " -q -o ";
  ASSERT_EQ(run(render + dir.path("cli_home.png")).exit_code, 0);
  EXPECT_TRUE(same_picture(dir.path("home.png"), dir.path("cli_home.png"))) << "the default view";
  // The saved command lines (at the window's size and at 400 x 240), run as they are
  // (their output renamed), give the same PNGs.
  EXPECT_EQ(v.out.rfind("terrain-render frame", 0), 0u)
      << "save-view prints the command line: " << v.out;
  for (const std::string saved : {"view", "big"}) {
    std::string cmd = file_bytes(dir.path(saved + ".png.txt"));
    ASSERT_FALSE(cmd.empty()) << saved;
    cmd.replace(cmd.find("terrain-render"), 14, tool("terrain-render"));
    cmd.replace(cmd.find(dir.path(saved + ".png")), dir.path(saved + ".png").size(),
                dir.path("cmd.png"));
    cmd.pop_back();  // the newline
    ASSERT_EQ(run(cmd + " -q").exit_code, 0) << cmd;
    EXPECT_TRUE(same_picture(dir.path(saved + ".png"), dir.path("cmd.png"))) << cmd;
  }
  EXPECT_NE(file_bytes(dir.path("big.png.txt")).find("--size '400x240'"), std::string::npos);
  // The keyframes: a frames CSV of 5 frames that batch renders.
  const auto b = run(tool("terrain-render") + " batch " + mesh + " " + dv + " " +
                     dir.path("keys.csv") + " -o " + dir.path("kf") + size + " -q");
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(std::filesystem::exists(dir.path("kf/frame_00004.png")));
  EXPECT_FALSE(std::filesystem::exists(dir.path("kf/frame_00005.png")));
  // Each option set in the viewer draws what the CLI option draws, and changes the frame.
  for (std::size_t i = 0; window && i < kChanges.size(); ++i) {
    std::string options;
    for (const auto& [name, value] : kChanges[i])
      options += " --" + name +
                 (value == "true" ? std::string() : " '" + value + "'");  // a flag takes no value
    const std::string png = dir.path("cli" + std::to_string(i) + ".png"),
                      set = dir.path("set" + std::to_string(i) + ".png");
    ASSERT_EQ(run(render + png + options).exit_code, 0) << options;
    EXPECT_TRUE(same_picture(set, png)) << options;
    EXPECT_FALSE(same_picture(set, dir.path("home.png"))) << options << " did not change the frame";
  }
}

// Issue 49: one frame, resolved once (renderer/scene/frame_setup.hpp). For option sets that give
// the camera or not, the light, each view mode, layers, --line-scale and the size, the
// viewer's start view (its screenshot, offscreen) has exactly terrain-render frame's
// pixels; before, the viewer's Home replaced the light given (--light-az 90) and its own
// automatic view ignored --view-az. save-view to .svg and .pdf writes terrain-render's
// files (the SVG's text with its provenance line left out; the PDF rasterized), where it
// wrote PNG bytes under those names.
TEST(Viewer, StartViewIsTerrainRendersFrameForEveryOptionSet) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 100 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --spacing 20 --breach 10 -q")
                .exit_code,
            0);
  const std::vector<std::string> sets = {
      "",
      "--light-az 90",
      "--view-az 180",
      "--view top",
      "--view relief --light-alt 20",
      "--eye 565000 5112000 4000 --view-az 330 --view-alt 25",
      "--layers shaded,creases",
      "--line-scale 2",
      "--size 240x200 --fov 50",
      "--view-alt 50 --exaggeration 2",
      "--layers mask,silhouettes-adjacency --light-az 300",
      "--layers mask,hachures,creases --hachure-style rows --hachure-spacing 4",
  };
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const std::string options =
        (sets[i].find("--size") == std::string::npos ? " --size 192x108 " : " ") + sets[i];
    const std::string k = std::to_string(i), cli = dir.path("cli" + k + ".png"),
                      shot = dir.path("view" + k + ".png");
    std::string replay = "screenshot " + shot + "\n";
    if (i == 0)
      replay +=
          "save-view " + dir.path("view0.svg") + "\nsave-view " + dir.path("view0.pdf") + "\n";
    std::ofstream(dir.path("r" + k + ".txt")) << replay << "quit\n";
    const auto v = run(tool("terrain-view") + " " + mesh + " " + dv + options +
                       " --offscreen -q --replay " + dir.path("r" + k + ".txt"));
    ASSERT_EQ(v.exit_code, 0) << options << "\n" << v.err;
    const std::string render =
        tool("terrain-render") + " frame " + mesh + " " + dv + options + " -q -o ";
    ASSERT_EQ(run(render + cli).exit_code, 0) << options;
    const auto diff = run("oiiotool --fail 0 --failpercent 0 --diff " + cli + " " + shot);
    EXPECT_EQ(diff.exit_code, 0) << "'" << sets[i] << "': the viewer's start view differs\n"
                                 << diff.out;
    if (i != 0) continue;
    ASSERT_EQ(run(render + dir.path("cli0.svg")).exit_code, 0);
    ASSERT_EQ(run(render + dir.path("cli0.pdf")).exit_code, 0);
    const std::regex desc("<desc>[^<]*</desc>");
    const std::string a = std::regex_replace(file_bytes(dir.path("cli0.svg")), desc, "");
    const std::string b = std::regex_replace(file_bytes(dir.path("view0.svg")), desc, "");
    EXPECT_NE(a.find("<svg"), std::string::npos);
    EXPECT_TRUE(a == b) << "save-view's SVG is not terrain-render's";
    for (const char* f : {"cli0", "view0"})
      ASSERT_EQ(run(std::string("pdftoppm -png -singlefile -r 96 ") +
                    dir.path(std::string(f) + ".pdf") + " " + dir.path(std::string(f) + "_pdf"))
                    .exit_code,
                0);
    EXPECT_EQ(run("oiiotool --fail 0 --failpercent 0 --diff " + dir.path("cli0_pdf.png") + " " +
                  dir.path("view0_pdf.png"))
                  .exit_code,
              0)
        << "save-view's PDF is not terrain-render's";
  }
}

// save-view's SVG takes --dpi and --vector-underlay as terrain-render frame does, and the
// command line it records (SVG.txt) carries them.
TEST(Viewer, SaveViewTakesTheVectorOptions) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv");
  ASSERT_TRUE(terrain::test::mesh_and_drainage("msh_2007_utm10n_10m.tif", mesh, dv, "--spacing 100",
                                               "--spacing 20"));
  const std::string options = " --size 192x108 --dpi 300 --vector-underlay mask";
  std::ofstream(dir.path("r.txt")) << "save-view " << dir.path("view.svg") << "\nquit\n";
  const auto v = run(tool("terrain-view") + " " + mesh + " " + dv + options +
                     " --offscreen -q --replay " + dir.path("r.txt"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  const std::string render = tool("terrain-render") + " frame " + mesh + " " + dv + " -q -o ";
  ASSERT_EQ(run(render + dir.path("cli.svg") + options).exit_code, 0);
  ASSERT_EQ(run(render + dir.path("plain.svg") + " --size 192x108").exit_code, 0);
  const std::regex desc("<desc>[^<]*</desc>");
  const auto text = [&](const char* f) {
    return std::regex_replace(file_bytes(dir.path(f)), desc, "");
  };
  EXPECT_TRUE(text("view.svg") == text("cli.svg"))
      << "save-view's SVG is not terrain-render's with the same options";
  EXPECT_FALSE(text("plain.svg") == text("cli.svg")) << "the options changed nothing";
  const std::string cmd = file_bytes(dir.path("view.svg.txt"));
  EXPECT_NE(cmd.find(" --dpi 300"), std::string::npos) << cmd;
  EXPECT_NE(cmd.find(" --vector-underlay mask"), std::string::npos) << cmd;
}

TEST(Viewer, WindowUnderXvfbDrawsWhatTerrainRenderDraws) { check_viewer(true); }

TEST(Viewer, OffscreenReplayDrawsWhatTerrainRenderDraws) { check_viewer(false); }

// A mesh larger than --memory, with its pyramid (MSH at 20 m: 151 x 221 vertices, 0.8 MB;
// --memory 0.25 holds 256 KiB): the viewer reads the level its start view draws (a map at
// 60 m a pixel, a 2 px bound: level 3), as terrain-render frame does, and when the view comes
// nearer than that level serves (5 m a pixel: level 0, whose cells span 5.7 px, level 1's
// 11 px exceeding the tessellation target), its full frame reads a finer one
// within the bound (level 1). Each saved view's command line carries the bound, and run,
// draws the same PNG, pixel for pixel (a saved map's command line, --view top with the
// eye, used to be refused: --map-scale needs the orthographic view).
TEST(Viewer, AMeshLargerThanTheMemoryBoundFollowsTheView) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 20 --pyramid -q")
                .exit_code,
            0);
  std::ofstream(dir.path("replay.txt")) << "save-view " + dir.path("far.png") +
                                               "\nset map-scale 5\nsave-view " +
                                               dir.path("near.png") + "\nquit\n";
  const auto v = run(tool("terrain-view") + " " + mesh +
                     " --size 320x180 --view top --map-scale 60 --lod-error 2 " +
                     "--layers mask,silhouettes --memory 0.25 -v --offscreen --replay " +
                     dir.path("replay.txt"));
  ASSERT_EQ(v.exit_code, 0) << v.err;
  EXPECT_NE(v.err.find("mesh read at level 3 of its pyramid after the preview at level 2: the view "
                       "draws level 3"),
            std::string::npos)
      << v.err;
  EXPECT_NE(
      v.err.find(
          "the view came nearer: mesh read at level 1 of its pyramid in place of level 3: the "
          "view draws level 0 at its finest; level 1 read, the finest within the memory bound"),
      std::string::npos)
      << v.err;
  for (const std::string saved : {"far", "near"}) {
    std::string cmd = file_bytes(dir.path(saved + ".png.txt"));
    ASSERT_NE(cmd.find(" --memory 0.25"), std::string::npos) << cmd;
    cmd.replace(cmd.find("terrain-render"), 14, tool("terrain-render"));
    cmd.replace(cmd.find(dir.path(saved + ".png")), dir.path(saved + ".png").size(),
                dir.path("cmd.png"));
    cmd.pop_back();  // the newline
    ASSERT_EQ(run(cmd + " -q").exit_code, 0) << cmd;
    EXPECT_EQ(run("oiiotool --fail 0 --failpercent 0 --diff " + dir.path(saved + ".png") + " " +
                  dir.path("cmd.png"))
                  .exit_code,
              0)
        << cmd;
  }
  // A near view under a bound the mesh exceeds but the blocks in view fit (--memory 0.75):
  // the viewer reads those blocks, as terrain-render frame does, and its saved view's
  // command line draws the same PNG; turned to look south, its full frame reads what frame
  // reads for that view, and its command line draws the same PNG too.
  std::ofstream(dir.path("near.txt")) << "save-view " + dir.path("window.png") +
                                             "\ncamera 562800 5117200 2300 180 10\nsave-view " +
                                             dir.path("back.png") + "\nquit\n";
  const auto w = run(
      tool("terrain-view") + " " + mesh + " --size 320x180 --eye 562800 5117200 2300 --view-az 0 " +
      "--view-alt 10 --fov 40 --layers mask,silhouettes --memory 0.75 -v --offscreen --replay " +
      dir.path("near.txt"));
  ASSERT_EQ(w.exit_code, 0) << w.err;
  EXPECT_NE(w.err.find("the view draws level 0 at its finest; the blocks in view, rows 0 .. 2 and "
                       "columns 0 .. 2 of "
                       "4 x 3, read"),
            std::string::npos)
      << w.err;
  EXPECT_NE(w.err.find("the view moved: mesh read at level"), std::string::npos) << w.err;
  for (const std::string saved : {"window", "back"}) {
    std::string cmd = file_bytes(dir.path(saved + ".png.txt"));
    cmd.replace(cmd.find("terrain-render"), 14, tool("terrain-render"));
    cmd.replace(cmd.find(dir.path(saved + ".png")), dir.path(saved + ".png").size(),
                dir.path("cmd.png"));
    cmd.pop_back();
    ASSERT_EQ(run(cmd + " -q").exit_code, 0) << cmd;
    EXPECT_EQ(run("oiiotool --fail 0 --failpercent 0 --diff " + dir.path(saved + ".png") + " " +
                  dir.path("cmd.png"))
                  .exit_code,
              0)
        << cmd;
  }
}

TEST(Viewer, ListsEveryOptionOfTheTable) {
  const auto r = run(tool("terrain-view") + " --list-options");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t lines = 0;
  for (const renderer::OptionSpec& o : renderer::render_options()) {
    // The type by its name, as --help writes it (before: the enum's number).
    EXPECT_NE(
        r.out.find(o.name + "\t" + o.group + "\t" + renderer::option_type_name(o.type) + "\t"),
        std::string::npos)
        << o.name;
    EXPECT_NE(r.out.find("\t" + o.default_text + "\n"), std::string::npos) << o.name;
    ++lines;
  }
  EXPECT_EQ(std::size_t(std::count(r.out.begin(), r.out.end(), '\n')), lines);
}

// --list-options=json (terrain-render's and terrain-view's, the same): every row of the
// table with its range, choices and help, as a program builds its parameters from it.
TEST(Viewer, ListsEveryOptionAsJson) {
  for (const char* t : {"terrain-view", "terrain-render"}) {
    const auto r = run(tool(t) + " --list-options=json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json all = nlohmann::json::parse(r.out);
    const auto& table = renderer::render_options();
    ASSERT_EQ(all.size(), table.size()) << t;
    for (std::size_t i = 0; i < table.size(); ++i) {
      const renderer::OptionSpec& o = table[i];
      const nlohmann::json& j = all[i];
      EXPECT_EQ(j["name"], o.name);
      EXPECT_EQ(j["default"], o.default_text) << o.name;
      EXPECT_EQ(j["type"], renderer::option_type_name(o.type)) << o.name;
      EXPECT_EQ(j["choices"].get<std::vector<std::string>>(), o.choices) << o.name;
      EXPECT_EQ(j["help"], o.help) << o.name;
      if (o.type == renderer::OptionType::Number && !o.unbounded()) {
        EXPECT_EQ(j["min"].get<double>(), o.min) << o.name;
        EXPECT_EQ(j["max"].get<double>(), o.max) << o.name;
      }
    }
  }
  EXPECT_EQ(run(tool("terrain-render") + " --list-options=yaml").exit_code, 2);
}

}  // namespace
