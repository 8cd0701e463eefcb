// Issue 37's acceptance test: terrain-render batch --format png,svg,pdf on the demo's Mount
// St. Helens and Logan views and three frames of its flight, one layer at a time and all
// together; the SVG rasterized by rsvg-convert and the PDF by pdftoppm at the frame's size
// must put their ink where the PNG does: at least 95 % of the vector ink pixels within 1 px
// of PNG ink and at least 95 % of the PNG ink within 1 px of vector ink. The MSH view's SVG
// is read back with libxml2: its layer groups, paths per drawn stroke, size, decimals.
#include <gtest/gtest.h>
#include <libxml/parser.h>
#include <libxml/tree.h>

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "test_support.hpp"
#include "tools/ink.hpp"

namespace {

using terrain::test::count;
using terrain::test::data;
using terrain::test::Ink;
using terrain::test::ink_of;
using terrain::test::near_share;
using terrain::test::run;
using terrain::test::tool;

// Renders the frames of `csv` as PNG, SVG and PDF with `options`, rasterizes the vector files
// and checks their ink against the PNG's, frame by frame.
void check_agreement(const terrain::test::ScratchDir& dir, const std::string& inputs,
                     const std::string& csv, int frames, int w, int h, const std::string& options,
                     const std::string& name) {
  const std::string out = dir.path(name);
  const auto r = run(tool("terrain-render") + " batch " + inputs + " " + csv + " -o " + out +
                     " --format png,svg,pdf -q --size " + std::to_string(w) + "x" +
                     std::to_string(h) + " " + options);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int i = 0; i < frames; ++i) {
    const std::string base = out + "/frame_0000" + std::to_string(i);
    const auto s = run("rsvg-convert -w " + std::to_string(w) + " -h " + std::to_string(h) + " " +
                       base + ".svg -o " + base + "_svg.png");
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const auto p = run("pdftoppm -png -singlefile -scale-to-x " + std::to_string(w) +
                       " -scale-to-y " + std::to_string(h) + " " + base + ".pdf " + base + "_pdf");
    ASSERT_EQ(p.exit_code, 0) << p.err;
    const Ink png = ink_of(base + ".png");
    ASSERT_EQ(png.w, w);
    ASSERT_GT(count(png), std::size_t(200)) << name << " frame " << i << ": the view draws lines";
    for (const char* kind : {"svg", "pdf"}) {
      const Ink vec = ink_of(base + "_" + kind + ".png");
      ASSERT_EQ(vec.w, w);
      ASSERT_EQ(vec.h, h);
      const double vector_near_png = near_share(vec, png), png_near_vector = near_share(png, vec);
      EXPECT_GE(vector_near_png, 0.95)
          << name << " frame " << i << " " << kind << ": " << count(vec) << " ink px";
      EXPECT_GE(png_near_vector, 0.95)
          << name << " frame " << i << " " << kind << ": " << count(png) << " ink px";
      std::cout << name << " frame " << i << " " << kind << ": vector ink near PNG ink "
                << vector_near_png << ", PNG ink near vector ink " << png_near_vector << " ("
                << count(png) << " PNG ink px)\n";
    }
  }
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

const char* kHeader = "easting,northing,elevation,view_az,view_alt,fov,light_az,light_alt\n";

// The demo's Mount St. Helens view (the relief view, the default before the automatic view), each
// line layer alone and all together; then the SVG read back.
TEST(VectorOutput, MountStHelensViewAgreesWithThePng) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 50 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --spacing 10 --breach 10 -q")
                .exit_code,
            0);
  const std::string csv = dir.path("view.csv");
  write(csv, std::string(kHeader) + "562843.9,5120300.6,3742.5,180,30,35,270,35\n");
  const std::string inputs = mesh + " " + dv;
  for (const std::string layers : {"creases", "silhouettes", "creases,silhouettes"})
    check_agreement(dir, inputs, csv, 1, 1280, 720, "--layers mask," + layers, "msh_" + layers);
  check_agreement(dir, mesh, csv, 1, 1280, 720, "--layers mask,edges --crease-angle 25",
                  "msh_edges");

  // The SVG of the whole view: layer groups, at most 2 paths per drawn stroke (creases) or
  // piece (silhouettes), as --line-stats counts them, under 2 MB, 2 decimals.
  const std::string svg_path = dir.path("msh_creases,silhouettes/frame_00000.svg");
  const std::string svg = terrain::test::file_bytes(svg_path);
  EXPECT_LT(svg.size(), std::size_t(2'000'000));
  const auto stats = run(tool("terrain-render") + " frame " + inputs + " -o " + dir.path("s.png") +
                         " --eye 562843.9 5120300.6 3742.5 --view-az 180 --view-alt 30 "
                         "--light-az 270 --light-alt 35 --line-stats");
  ASSERT_EQ(stats.exit_code, 0) << stats.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(stats.out, m, std::regex("crease strokes: (\\d+)")));
  const std::size_t strokes = std::stoul(m[1]);
  ASSERT_TRUE(std::regex_search(stats.out, m, std::regex("silhouette pieces: (\\d+)")));
  const std::size_t pieces = std::stoul(m[1]);
  std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)> doc(
      xmlReadFile(svg_path.c_str(), nullptr, XML_PARSE_HUGE), xmlFreeDoc);
  ASSERT_TRUE(doc);
  std::map<std::string, std::size_t> paths;
  std::vector<std::string> order;
  for (xmlNode* c = xmlDocGetRootElement(doc.get())->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE || !xmlStrEqual(c->name, BAD_CAST "g")) continue;
    xmlChar* id = xmlGetProp(c, BAD_CAST "id");
    xmlChar* mode = xmlGetNsProp(c, BAD_CAST "groupmode",
                                 BAD_CAST "http://www.inkscape.org/namespaces/inkscape");
    ASSERT_TRUE(id && mode);
    EXPECT_STREQ(reinterpret_cast<const char*>(mode), "layer");
    order.emplace_back(reinterpret_cast<const char*>(id));
    for (xmlNode* p = c->children; p; p = p->next)
      paths[order.back()] += p->type == XML_ELEMENT_NODE;
    xmlFree(id);
    xmlFree(mode);
  }
  EXPECT_EQ(order, (std::vector<std::string>{"surface", "creases", "silhouettes"}));
  std::cout << "MSH view: " << paths["creases"] << " crease paths for " << strokes << " strokes, "
            << paths["silhouettes"] << " silhouette paths for " << pieces << " pieces, "
            << svg.size() << " bytes\n";
  EXPECT_GT(paths["creases"], strokes / 2);
  EXPECT_LE(paths["creases"], 2 * strokes);
  EXPECT_LE(paths["silhouettes"], 2 * pieces);
  EXPECT_FALSE(std::regex_search(svg, std::regex(R"( d="[^"]*\d\.\d{3})")));
}

// The demo's Logan view (2x exaggeration), each line layer alone and together, and its PELs.
TEST(VectorOutput, LoganViewAgreesWithThePng) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("l.ply"), dv = dir.path("l.dv"), denoised = dir.path("ld.ply");
  ASSERT_EQ(
      run(tool("dem2mesh") + " " + data("logan_utm12n_100m.tif") + " " + mesh + " -q").exit_code,
      0);
  ASSERT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --spacing 30 --breach 10 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("denoise-normals") + " " + mesh + " " + denoised + " -q").exit_code, 0);
  const std::string csv = dir.path("view.csv");
  write(csv, std::string(kHeader) + "430000,4628000,4200,50,12,40,315,45\n");
  for (const std::string layers : {"creases", "silhouettes", "creases,silhouettes"})
    check_agreement(dir, mesh + " " + dv, csv, 1, 1280, 720,
                    "--exaggeration 2 --layers mask," + layers, "logan_" + layers);
  check_agreement(dir, denoised, csv, 1, 1280, 720, "--exaggeration 2 --layers mask,pels",
                  "logan_pels");
}

// Three frames of the demo's flight over the crater (960 x 540), all layers.
// Issue 48: --layers shaded written as SVG got the flat mask, not the relief. The underlay
// follows the layers: the shaded relief, embedded as the raster it is, whose rasterized
// SVG matches the PNG; without shaded the mask (vector regions, no image).
TEST(VectorOutput, TheUnderlayFollowsTheLayers) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 100 -q")
                .exit_code,
            0);
  const std::string cmd = tool("terrain-render") + " frame " + mesh + " --size 320x180 -q ";
  ASSERT_EQ(run(cmd + "--layers shaded -o " + dir.path("s.svg")).exit_code, 0);
  ASSERT_EQ(run(cmd + "--layers shaded -o " + dir.path("s.png")).exit_code, 0);
  ASSERT_EQ(run(cmd + "--layers mask,silhouettes -o " + dir.path("m.svg")).exit_code, 0);
  EXPECT_NE(terrain::test::file_bytes(dir.path("s.svg")).find("<image"), std::string::npos)
      << "no embedded relief";
  EXPECT_EQ(terrain::test::file_bytes(dir.path("m.svg")).find("<image"), std::string::npos)
      << "the mask is vector regions";
  ASSERT_EQ(run("rsvg-convert -w 320 -h 180 " + dir.path("s.svg") + " -o " + dir.path("s_svg.png"))
                .exit_code,
            0);
  // The relief's grey levels where the PNG has them: at most 1 % of pixels differ by more than 8
  // levels.
  const auto diff = run("oiiotool --fail 0.0314 --failpercent 1 --diff --ch R,G,B " +
                        dir.path("s.png") + " --ch R,G,B " + dir.path("s_svg.png"));
  EXPECT_EQ(diff.exit_code, 0) << diff.out;
}

TEST(VectorOutput, FlightFramesAgreeWithThePng) {
  terrain::test::ScratchDir dir;
  const std::string mesh = dir.path("m.ply"), dv = dir.path("m.dv"), path = dir.path("path.csv");
  ASSERT_EQ(run(tool("dem2mesh") + " " + data("msh_2007_utm10n_10m.tif") + " " + mesh +
                " --spacing 50 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("build-drainage") + " " + mesh + " " + dv + " --spacing 10 --breach 10 -q")
                .exit_code,
            0);
  ASSERT_EQ(run(tool("terrain-render") +
                " path --from 561800 5113500 3300 --to 562900 5116000 3000 --frames 12 "
                "--view-alt 25 -o " +
                path)
                .exit_code,
            0);
  // Frames 0, 5 and 11 of the twelve.
  std::ifstream in(path);
  std::string line, csv_text;
  std::vector<std::string> rows;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') rows.push_back(line);
  ASSERT_EQ(rows.size(), 13u);
  csv_text = rows[0] + "\n" + rows[1] + "\n" + rows[6] + "\n" + rows[12] + "\n";
  const std::string csv = dir.path("frames.csv");
  write(csv, csv_text);
  check_agreement(dir, mesh + " " + dv, csv, 3, 960, 540, "", "flight");
}

}  // namespace
