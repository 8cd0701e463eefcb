// A frame's line art as paths (renderer/core/vector_art.hpp) and its SVG / PDF (vector_file.hpp),
// GL-free: strokes, masks and segments laid out by hand under a camera looking straight
// down, whose paths are known; the mask traced into regions; the files read back.
#include <gtest/gtest.h>

#include <libxml/parser.h>
#include <libxml/tree.h>
#include "renderer/top_view.hpp"

#include <cmath>
#include <random>
#include <regex>
#include <string>

#include "renderer/core/vector_art.hpp"
#include "renderer/core/vector_file.hpp"
#include "terrain/error.hpp"

namespace renderer {
namespace {

constexpr int kW = 64, kH = 16;

View top_view() { return test::top_view(kW, kH); }

// Metres per pixel along x and the local x of pixel column u, on the ground (z = 0).
double x_of(const View& view, double u) {
  const Projected a = project(view, Eigen::Vector3d(0, 0, 0)),
                  b = project(view, Eigen::Vector3d(1, 0, 0));
  return (u - a.u) / (b.u - a.u);
}

// A stroke along the middle row: `n` segments of 1.98 px from u = 0.2 (two samples each).
CreaseGeometry row_stroke(const View& view, int n) {
  CreaseGeometry g;
  for (int i = 0; i <= n; ++i) {
    g.positions.emplace_back(float(x_of(view, 0.2 + 1.98 * i)), 0.0f, 0.0f);
    g.normals.emplace_back(0.0f, 0.0f, 1.0f);
    g.flow.push_back(float(i + 1) / float(n + 1));
    g.share.push_back(0.0f);
    g.source.push_back(std::uint32_t(i));
  }
  for (std::uint32_t i = 0; i < std::uint32_t(n); ++i)
    g.segments.insert(g.segments.end(), {i, i + 1});
  return g;
}

// Samples from a string of '1' (shown) and '0', two a segment.
std::vector<SegmentSamples> samples_of(const std::string& bits) {
  std::vector<SegmentSamples> m(bits.size() / 2);
  for (std::size_t s = 0; s < m.size(); ++s) {
    m[s].n = 2;
    m[s].step = 0.99f;
    for (int k = 0; k < 2; ++k)
      if (bits[2 * s + std::size_t(k)] == '1') m[s].shown |= 1u << k;
  }
  return m;
}

// Hidden runs cut a stroke into one path per shown run, from the start of its first shown
// sample to the end of its last; a stroke of one width is a stroke, not an outline.
TEST(VectorArt, CreasePathsAreTheShownRunsOfEachStroke) {
  const View view = top_view();
  const CreaseGeometry g = row_stroke(view, kW / 2);
  const std::string bits = "1111111111111111111110001111111000000000000000000000001111111111";
  const std::vector<float> drawn(g.n_segments(), 1.0f);
  std::size_t strokes = 0;
  const auto paths = crease_paths(g, drawn, samples_of(bits), view, 1.0, 1.0, 3.0, &strokes);
  EXPECT_EQ(strokes, 1u);
  ASSERT_EQ(paths.size(), 3u);
  // Sample k of segment s covers u in 0.2 + 1.98 s + 0.99 [k, k + 1].
  const double ends[3][2] = {{0.2, 0.2 + 21 * 0.99},
                             {0.2 + 24 * 0.99, 0.2 + 31 * 0.99},
                             {0.2 + 54 * 0.99, 0.2 + 64 * 0.99}};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& p = paths[i].line.points;
    ASSERT_GE(p.size(), 2u);
    EXPECT_NEAR(p.front().x(), ends[i][0], 1e-3) << i;
    EXPECT_NEAR(p.back().x(), ends[i][1], 1e-3) << i;
    EXPECT_NEAR(p.front().y(), kH / 2.0, 1e-3);
    EXPECT_EQ(p.size(), 2u) << "a straight run simplifies to its ends";
    EXPECT_TRUE(paths[i].widths.empty());
    EXPECT_FLOAT_EQ(paths[i].width, 1.0f);  // share 0: the minimum width
    EXPECT_FLOAT_EQ(paths[i].opacity, 1.0f);
  }
}

// A stroke whose width grows (the basin share rises) is one filled outline with the width
// of crease.vert at each point; a fading head is its own path at its mean opacity.
TEST(VectorArt, AWideningStrokeIsAnOutlineAndAFadingHeadItsOwnPath) {
  const View view = top_view();
  CreaseGeometry g = row_stroke(view, 8);
  for (std::size_t i = 0; i < g.share.size(); ++i)
    g.share[i] = float(i * i) / 64.0f;  // sqrt: i / 8
  std::vector<float> drawn(g.n_segments(), 1.0f);
  drawn[0] = 0.2f;
  drawn[1] = 0.6f;
  const auto paths = crease_paths(g, drawn, samples_of(std::string(16, '1')), view, 1.0, 1.0, 3.0);
  ASSERT_EQ(paths.size(), 2u);
  // The head: segments 0 and 1, 1.98 px each, at (0.2 + 0.6) / 2.
  EXPECT_NEAR(paths[0].opacity, 0.4f, 1e-6);
  EXPECT_NEAR(paths[0].line.points.back().x(), 0.2 + 2 * 1.98, 1e-3);
  EXPECT_FLOAT_EQ(paths[1].opacity, 1.0f);
  EXPECT_EQ(paths[1].line.points.front(), paths[0].line.points.back());  // the pieces meet
  ASSERT_EQ(paths[1].widths.size(), paths[1].line.points.size());
  EXPECT_NEAR(paths[1].widths.front(), 1.0 + 2.0 * 2 / 8, 1e-5);  // vertex 2
  EXPECT_NEAR(paths[1].widths.back(), 3.0, 1e-5);                 // vertex 8: share 1
}

// A ring of silhouette pixels is one closed line about the ring's centre line; a small
// piece at half opacity keeps it.
TEST(VectorArt, SilhouettePathsOfARingAndAFadedPiece) {
  const int w = 48, h = 48;
  std::vector<std::uint8_t> o(std::size_t(w * h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double r = std::hypot(x + 0.5 - 24, y + 0.5 - 24);
      if (std::abs(r - 15) < 0.75) o[std::size_t(y * w + x)] = 255;
    }
  for (int x = 2; x < 6; ++x) o[std::size_t(45 * w + x)] = 128;
  std::size_t pieces = 0;
  const auto paths = silhouette_paths(o, w, h, 1.8f, &pieces);
  EXPECT_EQ(pieces, 2u);
  ASSERT_EQ(paths.size(), 2u);
  const VectorPath& ring = paths[0].line.closed ? paths[0] : paths[1];
  const VectorPath& piece = paths[0].line.closed ? paths[1] : paths[0];
  EXPECT_TRUE(ring.line.closed);
  EXPECT_FLOAT_EQ(ring.opacity, 1.0f);
  EXPECT_FLOAT_EQ(ring.width, 1.8f);
  for (const auto& p : ring.line.points) EXPECT_NEAR(std::hypot(p.x() - 24, p.y() - 24), 15.0, 0.8);
  EXPECT_LT(ring.line.points.size(), 60u) << "simplified";
  EXPECT_FALSE(piece.line.closed);
  EXPECT_NEAR(piece.opacity, 0.5f, 1e-6);
}

using test::toward_of;

// A line on the ground behind a ridge: the part behind it is left out, by line.frag's test
// (the farthest surface of the 3 x 3 pixels: the ridge hides the columns inside it but its
// first and last) or by the composite's own pixel; consecutive segments chain into one path.
TEST(VectorArt, SegmentPathsLeaveOutWhatIsHidden) {
  const View view = top_view();
  const std::string columns = "GGGGGGGGGGGGGGGGGGGGRRRRRRRRRRRGGGGGGGGGGGGGGGGGGGGGGGGGGGGGGGGG";
  const std::vector<float> toward = toward_of(view, columns);
  const double y = 0;
  std::vector<SceneSegment> segs;
  for (int i = 0; i < 6; ++i)  // u from 2 to 62 in six segments
    segs.push_back({Eigen::Vector3d(x_of(view, 2 + 10 * i), y, 0),
                    Eigen::Vector3d(x_of(view, 12 + 10 * i), y, 0), 1});
  for (const bool antialias : {true, false}) {
    std::size_t chains = 0;
    const auto paths = segment_paths(segs, view, 1.0, toward, antialias, 1.5f, &chains);
    ASSERT_EQ(paths.size(), 2u) << antialias;
    EXPECT_EQ(chains, 2u);
    const auto& a =
        paths[0].line.points.front().x() < paths[1].line.points.front().x() ? paths[0] : paths[1];
    const auto& b = &a == &paths[0] ? paths[1] : paths[0];
    const double hidden_from = antialias ? 21 : 20, hidden_to = antialias ? 30 : 31;
    EXPECT_NEAR(a.line.points.front().x(), 2, 1e-3);
    EXPECT_NEAR(a.line.points.back().x(), hidden_from, 0.5) << antialias;
    EXPECT_NEAR(b.line.points.front().x(), hidden_to, 0.5) << antialias;
    EXPECT_NEAR(b.line.points.back().x(), 62, 1e-3);
    EXPECT_EQ(b.line.points.size(), 2u)
        << "the segments beyond the ridge chain into one straight path";
  }
}

// The area an outline encloses, its Bezier pieces sampled 16 times each.
double shoelace(const Outline& o) {
  std::vector<Eigen::Vector2f> p{o.start};
  for (const auto& c : o.curves) {
    const Eigen::Vector2f a = p.back();
    for (int k = 1; k <= 16; ++k) {
      const float t = float(k) / 16, u = 1 - t;
      p.push_back(u * u * u * a + 3 * u * u * t * c[0] + 3 * u * t * t * c[1] + t * t * t * c[2]);
    }
  }
  double a = 0;
  for (std::size_t k = 0; k + 1 < p.size(); ++k)
    a += double(p[k].x()) * p[k + 1].y() - double(p[k + 1].x()) * p[k].y();
  return 0.5 * std::abs(a);
}

// A square with a hole and a separate blob: two regions, the first with its hole.
TEST(VectorArt, TraceRegionsKeepsHolesWithTheirRegion) {
  const int w = 40, h = 30;
  std::vector<std::uint8_t> m(std::size_t(w * h), 0);
  for (int y = 2; y < 22; ++y)
    for (int x = 2; x < 22; ++x)
      m[std::size_t(y * w + x)] = !(x >= 9 && x < 15 && y >= 9 && y < 15);
  for (int y = 5; y < 15; ++y)
    for (int x = 28; x < 36; ++x) m[std::size_t(y * w + x)] = 1;
  auto regions = trace_regions(m, w, h);
  ASSERT_EQ(regions.size(), 2u);
  if (regions[0].size() == 1) std::swap(regions[0], regions[1]);
  ASSERT_EQ(regions[0].size(), 2u);  // the square and its hole
  ASSERT_EQ(regions[1].size(), 1u);
  EXPECT_NEAR(shoelace(regions[0][0]), 400, 40);
  EXPECT_NEAR(shoelace(regions[0][1]), 32,
              5);  // potrace rounds a 6 px square hole towards its disc (28)
  EXPECT_NEAR(shoelace(regions[1][0]), 80, 10);
  for (const auto& c : regions[1][0].curves) {  // on the blob's border, y down as the mask
    EXPECT_GE(c[2].x(), 27.5f);
    EXPECT_LE(c[2].y(), 15.5f);
  }
}

std::string prop(xmlNode* n, const char* name, const char* ns = nullptr) {
  xmlChar* v = ns ? xmlGetNsProp(n, BAD_CAST name, BAD_CAST ns) : xmlGetProp(n, BAD_CAST name);
  std::string s = v ? reinterpret_cast<const char*>(v) : "";
  xmlFree(v);
  return s;
}

std::size_t count_elements(xmlNode* n, const char* name) {
  std::size_t k = 0;
  for (xmlNode* c = n->children; c; c = c->next)
    if (c->type == XML_ELEMENT_NODE)
      k += (xmlStrEqual(c->name, BAD_CAST name) ? 1 : 0) + count_elements(c, name);
  return k;
}

VectorArt small_art() {
  VectorArt art;
  art.width = 64;
  art.height = 32;
  art.surface.assign(64 * 32, 0);
  for (int y = 16; y < 32; ++y)
    for (int x = 0; x < 64; ++x) art.surface[std::size_t(y * 64 + x)] = 1;
  VectorLayer creases{"creases", {0, 0, 1}, LineCap::Round, {}, 2};
  creases.paths.push_back({Polyline{{{1.123f, 20}, {30.456f, 25}}, false}, 1.25f, 1.0f, {}});
  creases.paths.push_back(
      {Polyline{{{2, 28}, {20, 28}, {40, 29}}, false}, 2.0f, 0.5f, {1.0f, 2.0f, 3.0f}});
  VectorLayer sil{"silhouettes", {0, 0, 0}, LineCap::Round, {}, 1};
  sil.paths.push_back({Polyline{{{0, 16}, {63, 16}}, false}, 1.8f, 1.0f, {}});
  art.layers = {creases, sil};
  return art;
}

// The SVG: one Inkscape layer group per layer, in drawing order, each with its paths
// (the varying-width crease one filled outline), coordinates with 2 decimals at most, the
// page in pixels, or in inches at another dpi; the PDF: one page of the frame's size.
TEST(VectorFile, SvgLayersArePathsInInkscapeLayerGroups) {
  const VectorArt art = small_art();
  const std::string svg = vector_bytes(art, VectorFormat::Svg, 96, "test <&> provenance");
  std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)> doc(
      xmlReadMemory(svg.data(), int(svg.size()), "t.svg", nullptr, 0), xmlFreeDoc);
  ASSERT_TRUE(doc) << svg;
  xmlNode* root = xmlDocGetRootElement(doc.get());
  EXPECT_EQ(prop(root, "width"), "64px");
  EXPECT_EQ(prop(root, "viewBox"), "0 0 64 32");
  const char* ink = "http://www.inkscape.org/namespaces/inkscape";
  std::vector<std::string> ids;
  std::vector<std::size_t> paths;
  for (xmlNode* c = root->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE || !xmlStrEqual(c->name, BAD_CAST "g")) continue;
    EXPECT_EQ(prop(c, "groupmode", ink), "layer");
    EXPECT_EQ(prop(c, "label", ink), prop(c, "id"));
    ids.push_back(prop(c, "id"));
    paths.push_back(count_elements(c, "path"));
  }
  EXPECT_EQ(ids, (std::vector<std::string>{"surface", "creases", "silhouettes"}));
  EXPECT_EQ(paths, (std::vector<std::size_t>{1, 2, 1}));  // the surface: one region
  EXPECT_NE(svg.find("test &lt;&amp;&gt; provenance"), std::string::npos);
  EXPECT_NE(svg.find("M 1.12 20 L 30.46 25"), std::string::npos) << svg;
  const std::regex long_number(R"(\d\.\d{3})");
  for (std::size_t p = svg.find(" d=\""); p != std::string::npos; p = svg.find(" d=\"", p + 1)) {
    const std::string d = svg.substr(p + 4, svg.find('"', p + 4) - p - 4);
    EXPECT_FALSE(std::regex_search(d, long_number)) << d;
  }
  const std::string at300 = vector_bytes(art, VectorFormat::Svg, 300, "");
  EXPECT_NE(at300.find("width=\"0.2133in\""), std::string::npos);
  EXPECT_NE(at300.find("viewBox=\"0 0 64 32\""), std::string::npos);

  const std::string pdf = vector_bytes(art, VectorFormat::Pdf, 96, "provenance");
  EXPECT_EQ(pdf.rfind("%PDF-", 0), 0u);
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 48 24 ]"),
            std::string::npos);  // 64 x 32 px at 96 dpi, in points

  VectorArt none = art;
  none.underlay = VectorUnderlay::None;
  const std::string bare = vector_bytes(none, VectorFormat::Svg, 96, "");
  EXPECT_EQ(bare.find("<rect"), std::string::npos);
  EXPECT_THROW(vector_bytes(art, VectorFormat::Svg, 0, ""), terrain::Error);
  EXPECT_EQ(vector_format_of("a/B.SVG"), VectorFormat::Svg);
  EXPECT_EQ(vector_format_of("x.pdf"), VectorFormat::Pdf);
  EXPECT_THROW(vector_format_of("x.png"), terrain::Error);
  EXPECT_THROW(parse_underlay("relief"), terrain::Error);
}

// The frame formats' table: each extension found in any case, the vector ones the line art
// (vector_format_of takes them), only the PNG with a world file; anything else none.
// Strahler's order on a hand-made crease network: two heads meet (2), a third head joins
// that stem lower down (still 2), another stem of order 2 meets it (3); a lone vertex 0.
//   0 -> 2, 1 -> 2, 2 -> 3, 4 -> 3, 3 -> 5, 6 -> 8, 7 -> 8, 8 -> 5, 5 -> 9; vertex 10 alone
// draw_on_rgba in bands of rows side by side gives the pixels of one band: strokes of
// every cap and join, lines of varying width, faint ones, dots, across the bands' edges
// (rows 13 and 26 of 40 for three bands, every row for 40), over an opaque frame and a
// transparent one.
TEST(VectorFile, LinesDrawnInBandsAreTheLinesDrawnAtOnce) {
  const int w = 90, h = 40;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> x(-5.0f, float(w) + 5.0f), y(-5.0f, float(h) + 5.0f);
  std::vector<VectorLayer> layers;
  for (const LineCap cap : {LineCap::Butt, LineCap::Round, LineCap::Square}) {
    VectorLayer l{"lines", Eigen::Vector3f(0.1f, 0.2f, 0.7f), cap, {}, 0};
    for (int k = 0; k < 12; ++k) {
      VectorPath p;
      for (int j = 0; j < 2 + k % 4; ++j) p.line.points.emplace_back(x(rng), y(rng));
      p.line.closed = k % 5 == 0;
      p.width = 0.5f + float(k % 7);
      p.opacity = k % 3 == 0 ? 0.35f : 1.0f;
      if (k % 4 == 3)
        for (std::size_t j = 0; j < p.line.points.size(); ++j) p.widths.push_back(1.0f + float(j));
      l.paths.push_back(p);
    }
    VectorPath dot;
    dot.line.points = {Eigen::Vector2f(45.0f, 26.0f)};
    dot.width = 5;
    l.paths.push_back(dot);
    layers.push_back(l);
  }
  for (const std::uint8_t alpha : {std::uint8_t(255), std::uint8_t(0)})
    for (const VectorLayer& l : layers) {
      std::vector<std::uint8_t> frame(std::size_t(4 * w * h));
      for (std::size_t i = 0; i < frame.size(); ++i)
        frame[i] = i % 4 == 3 ? alpha : std::uint8_t(i * 37 % 251);
      std::vector<std::uint8_t> one = frame;
      draw_on_rgba(l, w, h, one, 1);
      EXPECT_NE(one, frame);  // something drawn
      for (const int bands : {2, 3, 40}) {
        std::vector<std::uint8_t> many = frame;
        draw_on_rgba(l, w, h, many, bands);
        EXPECT_EQ(many, one) << bands << " bands, alpha " << int(alpha);
      }
    }
}

TEST(VectorArt, CreaseOrdersAreStrahlers) {
  CreaseGeometry g;
  g.positions.assign(11, Eigen::Vector3f::Zero());
  g.segments = {0, 2, 1, 2, 2, 3, 4, 3, 3, 5, 6, 8, 7, 8, 8, 5, 5, 9};
  const std::vector<std::uint8_t> o = crease_orders(g);
  EXPECT_EQ(o, (std::vector<std::uint8_t>{1, 1, 2, 2, 1, 3, 1, 1, 2, 3, 0}));
}

TEST(VectorFile, FrameFormatsAreOneTable) {
  for (const FrameFormat& f : kFrameFormats) {
    const std::string lower = std::string("dir.v2/frame.") + f.name;
    std::string upper = lower;
    for (std::size_t i = upper.size() - 3; i < upper.size(); ++i) upper[i] = char(upper[i] - 32);
    EXPECT_EQ(frame_format(lower), &f) << lower;
    EXPECT_EQ(frame_format(upper), &f) << upper;
    EXPECT_EQ(frame_format_named(f.name), &f);
    EXPECT_EQ(is_vector_path(upper), f.vector) << upper;
    if (f.vector && std::string(f.name) != "gpkg")  // gpkg: a map's lines, write_map_gpkg
      EXPECT_NO_THROW(vector_format_of(upper));
    else
      EXPECT_THROW(vector_format_of(upper), terrain::Error);
    EXPECT_NE(frame_format_names().find(f.name), std::string::npos);
  }
  EXPECT_FALSE(frame_format_named("png")->vector);
  EXPECT_TRUE(frame_format_named("png")->world_file);
  for (const char* other : {"x.jpg", "x.tiff", "x", "png", "x.png.txt", "x.svgz"})
    EXPECT_EQ(frame_format(other), nullptr) << other;
}

}  // namespace
}  // namespace renderer
