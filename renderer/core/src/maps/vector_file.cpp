#include "renderer/core/vector_file.hpp"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <omp.h>
#include <potracelib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>

#include "terrain/error.hpp"

namespace renderer {

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// ---- drawing (one routine for both surfaces) ----

void draw_surface(cairo_t* cr, const VectorArt& art) {
  if (art.underlay == VectorUnderlay::None) return;
  cairo_set_source_rgb(cr, art.background.x(), art.background.y(), art.background.z());
  cairo_rectangle(cr, 0, 0, art.width, art.height);
  cairo_fill(cr);
  if (art.underlay == VectorUnderlay::Mask) {
    cairo_set_source_rgb(cr, art.mask_colour.x(), art.mask_colour.y(), art.mask_colour.z());
    cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
    for (const Region& region : trace_regions(art.surface, art.width, art.height)) {
      cairo_new_path(cr);
      for (const Outline& o : region) {
        cairo_move_to(cr, o.start.x(), o.start.y());
        for (const auto& c : o.curves)
          cairo_curve_to(cr, c[0].x(), c[0].y(), c[1].x(), c[1].y(), c[2].x(), c[2].y());
        cairo_close_path(cr);
      }
      cairo_fill(cr);
    }
    return;
  }
  // The shaded surface as an image, transparent where no surface shows.
  cairo_surface_t* img = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, art.width, art.height);
  cairo_surface_flush(img);
  unsigned char* data = cairo_image_surface_get_data(img);
  const int stride = cairo_image_surface_get_stride(img);
  for (int y = 0; y < art.height; ++y)
    for (int x = 0; x < art.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(art.width) + std::size_t(x);
      const std::uint32_t a = art.surface[i] ? 255u : 0u;  // premultiplied: 0 or the colour
      const std::uint8_t* c = &art.shaded[4 * i];
      const std::uint32_t px =
          (a << 24) | (a ? (std::uint32_t(c[0]) << 16) | (std::uint32_t(c[1]) << 8) | c[2] : 0);
      std::memcpy(data + std::size_t(y) * std::size_t(stride) + 4 * std::size_t(x), &px, 4);
    }
  cairo_surface_mark_dirty(img);
  cairo_set_source_surface(cr, img, 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_surface_destroy(img);
}

// A line of varying width as one filled path: the union of its segments' capsules (the
// convex hull of the discs at its two ends), each a subpath turning the same way, so the
// nonzero rule fills their overlaps once.
void fill_outline(cairo_t* cr, const VectorPath& p) {
  constexpr double kPi = std::numbers::pi;
  cairo_new_path(cr);
  const auto& q = p.line.points;
  for (std::size_t k = 0; k + 1 < q.size() || k == 0; ++k) {
    const std::size_t j = std::min(k + 1, q.size() - 1);
    const Eigen::Vector2d a = q[k].cast<double>(), b = q[j].cast<double>();
    const double ra = 0.5 * p.widths[k], rb = 0.5 * p.widths[j], d = (b - a).norm();
    cairo_new_sub_path(cr);
    if (d <= std::abs(ra - rb)) {  // one disc holds the other
      const Eigen::Vector2d& c = ra >= rb ? a : b;
      cairo_arc_negative(cr, c.x(), c.y(), std::max(ra, rb), 2 * kPi, 0);
    } else {
      const double phi = std::atan2(b.y() - a.y(), b.x() - a.x()),
                   beta = 0.5 * kPi - std::asin((ra - rb) / d);
      cairo_arc_negative(cr, b.x(), b.y(), rb, phi + beta, phi - beta);
      cairo_arc_negative(cr, a.x(), a.y(), ra, phi - beta, phi + beta);
    }
    cairo_close_path(cr);
  }
  cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
  cairo_fill(cr);
}

// Whether path p's ink may reach rows [y0, y1): its points' rows, widened by what a stroke
// adds about them (a miter join up to cairo's default limit of 10 half-widths).
bool reaches_rows(const VectorPath& p, LineCap cap, double y0, double y1) {
  double w = p.width;
  for (const float x : p.widths) w = std::max(w, double(x));
  const double margin = (p.widths.empty() && cap != LineCap::Round ? 5.0 : 0.5) * w + 2.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& q : p.line.points)
    lo = std::min(lo, double(q.y())), hi = std::max(hi, double(q.y()));
  return hi + margin >= y0 && lo - margin < y1;
}

// The layer's paths, in order; with `rows`, only those that may reach them.
void draw_layer(cairo_t* cr, const VectorLayer& layer,
                std::optional<std::pair<double, double>> rows = std::nullopt) {
  cairo_set_line_cap(cr, layer.cap == LineCap::Round    ? CAIRO_LINE_CAP_ROUND
                         : layer.cap == LineCap::Square ? CAIRO_LINE_CAP_SQUARE
                                                        : CAIRO_LINE_CAP_BUTT);
  cairo_set_line_join(cr,
                      layer.cap == LineCap::Round ? CAIRO_LINE_JOIN_ROUND : CAIRO_LINE_JOIN_MITER);
  for (const VectorPath& p : layer.paths) {
    if (p.line.points.empty()) continue;
    if (rows && !reaches_rows(p, layer.cap, rows->first, rows->second)) continue;
    cairo_set_source_rgba(cr, layer.colour.x(), layer.colour.y(), layer.colour.z(), p.opacity);
    if (!p.widths.empty()) {
      fill_outline(cr, p);
      continue;
    }
    cairo_set_line_width(cr, p.width);
    cairo_new_path(cr);
    cairo_move_to(cr, p.line.points[0].x(), p.line.points[0].y());
    if (p.line.points.size() == 1)
      cairo_line_to(cr, p.line.points[0].x(), p.line.points[0].y());  // a dot
    for (std::size_t k = 1; k < p.line.points.size(); ++k)
      cairo_line_to(cr, p.line.points[k].x(), p.line.points[k].y());
    if (p.line.closed) cairo_close_path(cr);
    cairo_stroke(cr);
  }
}

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void check(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS)
    throw terrain::Error(
        fmt::format("cairo could not write the {}: {}", what, cairo_status_to_string(status)));
}

// Draws on surface `s` with `draw`, finishes and frees it; Error naming `what` on a failure.
template <class Draw>
void draw_and_finish(cairo_surface_t* s, Draw draw, const char* what) {
  cairo_t* cr = cairo_create(s);
  draw(cr);
  const cairo_status_t status = cairo_status(cr);
  cairo_destroy(cr);
  cairo_surface_finish(s);
  const cairo_status_t finished = cairo_surface_status(s);
  cairo_surface_destroy(s);
  check(status, what);
  check(finished, what);
}

// One cairo SVG document of the frame's size (pixels) with what `draw` draws.
template <class Draw>
std::string svg_document(const VectorArt& art, Draw draw) {
  std::string out;
  cairo_surface_t* s = cairo_svg_surface_create_for_stream(append, &out, art.width, art.height);
  cairo_svg_surface_set_document_unit(s, CAIRO_SVG_UNIT_PX);
  draw_and_finish(s, draw, "SVG");
  return out;
}

// ---- joining the layers' documents (libxml2) ----

using Doc = std::unique_ptr<xmlDoc, decltype(&xmlFreeDoc)>;

Doc parse(const std::string& text) {
  Doc d(xmlReadMemory(text.data(), int(text.size()), "layer.svg", nullptr,
                      XML_PARSE_NONET | XML_PARSE_HUGE),
        xmlFreeDoc);
  if (!d) throw terrain::Error("could not read back cairo's SVG");
  return d;
}

// "12.121094" -> "12.12": every number of a path's d attribute with 2 decimals at most.
std::string round_numbers(const std::string& d) {
  std::string out;
  out.reserve(d.size());
  for (std::size_t i = 0; i < d.size();) {
    const char c = d[i];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.') {
      char* end = nullptr;
      const double v = std::strtod(d.c_str() + i, &end);
      std::string t = fmt::format("{:.2f}", v);
      while (t.back() == '0') t.pop_back();
      if (t.back() == '.') t.pop_back();
      if (t == "-0") t = "0";
      out += t;
      i = std::size_t(end - d.c_str());
    } else {
      out += c;
      ++i;
    }
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// Ids prefixed by the layer's name (each cairo document numbers its own from 1), with the
// references to them; path data rounded.
void rename(xmlNode* n, const std::string& prefix) {
  for (; n; n = n->next) {
    if (n->type != XML_ELEMENT_NODE) continue;
    for (xmlAttr* a = n->properties; a; a = a->next) {
      const std::string name = reinterpret_cast<const char*>(a->name);
      xmlChar* raw = xmlNodeListGetString(n->doc, a->children, 1);
      const std::string v = raw ? reinterpret_cast<const char*>(raw) : "";
      xmlFree(raw);
      std::string nv = v;
      if (name == "id")
        nv = prefix + v;
      else if (name == "href" && v.starts_with("#"))
        nv = "#" + prefix + v.substr(1);
      else if (name == "d" && std::string(reinterpret_cast<const char*>(n->name)) == "path")
        nv = round_numbers(v);
      for (std::size_t p = nv.find("url(#"); p != std::string::npos;
           p = nv.find("url(#", p + 5 + prefix.size()))
        nv.insert(p + 5, prefix);
      if (nv != v) xmlSetNsProp(n, a->ns, a->name, BAD_CAST nv.c_str());
    }
    rename(n->children, prefix);
  }
}

xmlNode* child(xmlNode* parent, const char* name) {
  for (xmlNode* c = parent->children; c; c = c->next)
    if (c->type == XML_ELEMENT_NODE && xmlStrEqual(c->name, BAD_CAST name)) return c;
  return nullptr;
}

// Moves the children of `from` (in `src`) to the end of `to` (in `dst`).
void move_children(xmlDoc* src, xmlNode* from, xmlDoc* dst, xmlNode* to) {
  for (xmlNode* c = from->children; c;) {
    xmlNode* next = c->next;
    xmlUnlinkNode(c);
    if (xmlDOMWrapAdoptNode(nullptr, src, c, dst, to, 0) != 0)
      throw terrain::Error("could not join the SVG layers");
    xmlAddChild(to, c);
    c = next;
  }
}

std::string join_svg(const VectorArt& art,
                     const std::vector<std::pair<std::string, std::string>>& parts, double dpi,
                     const std::string& description) {
  const std::string size =
      dpi == 96 ? fmt::format("width=\"{}px\" height=\"{}px\"", art.width, art.height)
                : fmt::format("width=\"{:.4f}in\" height=\"{:.4f}in\"", art.width / dpi,
                              art.height / dpi);
  Doc doc = parse(fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
      "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" {} viewBox=\"0 0 {} {}\" "
      "version=\"1.1\">"
      "<desc/><defs/></svg>",
      size, art.width, art.height));
  xmlNode* root = xmlDocGetRootElement(doc.get());
  xmlNodeAddContent(child(root, "desc"), BAD_CAST description.c_str());
  xmlNs* inkscape = xmlSearchNs(doc.get(), root, BAD_CAST "inkscape");
  xmlNode* defs = child(root, "defs");
  for (const auto& [name, text] : parts) {
    Doc part = parse(text);
    xmlNode* proot = xmlDocGetRootElement(part.get());
    rename(proot->children, name + "-");
    xmlNode* layer = xmlNewChild(root, nullptr, BAD_CAST "g", nullptr);
    xmlNewProp(layer, BAD_CAST "id", BAD_CAST name.c_str());
    xmlNewNsProp(layer, inkscape, BAD_CAST "groupmode", BAD_CAST "layer");
    xmlNewNsProp(layer, inkscape, BAD_CAST "label", BAD_CAST name.c_str());
    for (xmlNode* c = proot->children; c; c = c->next) {
      if (c->type != XML_ELEMENT_NODE) continue;
      if (xmlStrEqual(c->name, BAD_CAST "defs"))
        move_children(part.get(), c, doc.get(), defs);
      else if (xmlStrEqual(c->name, BAD_CAST "g"))
        move_children(part.get(), c, doc.get(), layer);
    }
  }
  if (!defs->children) {
    xmlUnlinkNode(defs);
    xmlFreeNode(defs);
  }
  xmlChar* mem = nullptr;
  int len = 0;
  xmlDocDumpFormatMemoryEnc(doc.get(), &mem, &len, "UTF-8", 1);
  std::string out(reinterpret_cast<const char*>(mem), std::size_t(len));
  xmlFree(mem);
  return out;
}

}  // namespace

const FrameFormat* frame_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext.empty() ? nullptr : frame_format_named(ext.substr(1));
}

const FrameFormat* frame_format_named(const std::string& name) {
  for (const FrameFormat& f : kFrameFormats)
    if (name == f.name) return &f;
  return nullptr;
}

std::string frame_format_names() {
  std::string out;
  for (const FrameFormat& f : kFrameFormats) out += (out.empty() ? "" : ", ") + std::string(f.name);
  return out;
}

bool is_vector_path(const std::string& path) {
  const FrameFormat* f = frame_format(path);
  return f && f->vector;
}

VectorFormat vector_format_of(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".svg") return VectorFormat::Svg;
  if (ext == ".pdf") return VectorFormat::Pdf;
  throw terrain::Error("'" + path + "' is neither .svg nor .pdf");
}

std::vector<Region> trace_regions(const std::vector<std::uint8_t>& mask, int w, int h) {
  std::vector<Region> out;
  if (w <= 0 || h <= 0 || mask.size() != std::size_t(w) * std::size_t(h)) return out;
  constexpr int kBits = 8 * sizeof(potrace_word);
  const int dy = (w + kBits - 1) / kBits;
  std::vector<potrace_word> map(std::size_t(dy) * std::size_t(h), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (mask[std::size_t(y) * std::size_t(w) + std::size_t(x)])
        map[std::size_t(y) * std::size_t(dy) + std::size_t(x / kBits)] |=
            potrace_word(1) << (kBits - 1 - x % kBits);
  potrace_bitmap_t bm{w, h, dy, map.data()};
  std::unique_ptr<potrace_param_t, decltype(&potrace_param_free)> param(potrace_param_default(),
                                                                        potrace_param_free);
  if (!param) throw terrain::Error("potrace: out of memory");
  param->turdsize = 2;
  std::unique_ptr<potrace_state_t, decltype(&potrace_state_free)> st(
      potrace_trace(param.get(), &bm), potrace_state_free);
  if (!st || st->status != POTRACE_STATUS_OK)
    throw terrain::Error("potrace could not trace the surface mask");
  auto pt = [](const potrace_dpoint_t& p) { return Eigen::Vector2f(float(p.x), float(p.y)); };
  auto outline = [&](const potrace_path_t* p) {
    Outline o;
    const potrace_curve_t& c = p->curve;
    if (c.n == 0) return o;
    o.start = pt(c.c[c.n - 1][2]);
    Eigen::Vector2f at = o.start;
    for (int i = 0; i < c.n; ++i) {
      if (c.tag[i] == POTRACE_CURVETO) {
        o.curves.push_back({pt(c.c[i][0]), pt(c.c[i][1]), pt(c.c[i][2])});
      } else {  // a corner: two straight pieces
        const Eigen::Vector2f v = pt(c.c[i][1]), e = pt(c.c[i][2]);
        o.curves.push_back({at, v, v});
        o.curves.push_back({v, e, e});
      }
      at = pt(c.c[i][2]);
    }
    return o;
  };
  for (const potrace_path_t* p = st->plist; p; p = p->next) {
    if (p->sign != '+') continue;  // holes go with their region
    Region r{outline(p)};
    for (const potrace_path_t* hole = p->childlist; hole; hole = hole->sibling)
      r.push_back(outline(hole));
    out.push_back(std::move(r));
  }
  return out;
}

void draw_on_rgba(const VectorLayer& layer, int width, int height, std::vector<std::uint8_t>& rgba,
                  int bands) {
  // cairo's ARGB32 is premultiplied BGRA in a little-endian word: opaque pixels need only
  // their red and blue swapped, both ways; the others (--background none) premultiplied
  // before and divided after.
  const std::size_t n = std::size_t(width) * std::size_t(height);
  auto scale = [&](std::size_t i, bool multiply) {
    const unsigned a = rgba[4 * i + 3];
    if (a == 255) return;
    for (int k = 0; k < 3; ++k) {
      std::uint8_t& v = rgba[4 * i + std::size_t(k)];
      v = multiply ? std::uint8_t((v * a + 127) / 255)
                   : std::uint8_t(a ? std::min(255u, (v * 255u + a / 2) / a) : 0u);
    }
  };
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) std::swap(rgba[4 * i], rgba[4 * i + 2]), scale(i, true);
  // Bands of rows drawn side by side, each a surface of its own over the same pixels with
  // the paths that reach it: a pixel's coverage is cairo's for the whole image (the bands'
  // edges lie on pixel edges).
  if (bands <= 0) bands = std::clamp(omp_get_max_threads(), 1, std::max(1, height / 64));
  bands = std::clamp(bands, 1, std::max(1, height));
  cairo_status_t status = CAIRO_STATUS_SUCCESS;
#pragma omp parallel for schedule(static, 1)
  for (int b = 0; b < bands; ++b) {
    const int y0 = int(std::int64_t(height) * b / bands),
              y1 = int(std::int64_t(height) * (b + 1) / bands);
    cairo_surface_t* s =
        cairo_image_surface_create_for_data(rgba.data() + std::size_t(y0) * std::size_t(width) * 4,
                                            CAIRO_FORMAT_ARGB32, width, y1 - y0, width * 4);
    cairo_t* cr = cairo_create(s);
    cairo_translate(cr, 0, -y0);
    draw_layer(cr, layer, std::pair{double(y0), double(y1)});
    const cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_finish(s);
    cairo_surface_destroy(s);
#pragma omp critical(draw_on_rgba_status)
    if (st != CAIRO_STATUS_SUCCESS) status = st;
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) scale(i, false), std::swap(rgba[4 * i], rgba[4 * i + 2]);
  check(status, "hachures");
}

std::string vector_bytes(const VectorArt& art, VectorFormat format, double dpi,
                         const std::string& description) {
  if (!(dpi > 0 && dpi <= 10000))
    throw terrain::Error("the vector page's dpi must be in (0, 10000]");
  if (format == VectorFormat::Svg) {
    std::vector<std::pair<std::string, std::string>> parts;
    parts.emplace_back("surface", svg_document(art, [&](cairo_t* cr) { draw_surface(cr, art); }));
    for (const VectorLayer& l : art.layers)
      parts.emplace_back(l.name, svg_document(art, [&](cairo_t* cr) { draw_layer(cr, l); }));
    return join_svg(art, parts, dpi, description);
  }
  std::string out;
  const double scale = 72.0 / dpi;  // points per pixel
  cairo_surface_t* s =
      cairo_pdf_surface_create_for_stream(append, &out, art.width * scale, art.height * scale);
  cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_SUBJECT, description.c_str());
  cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, "terrain-render");
  draw_and_finish(
      s,
      [&](cairo_t* cr) {
        cairo_scale(cr, scale, scale);
        draw_surface(cr, art);
        for (const VectorLayer& l : art.layers) draw_layer(cr, l);
      },
      "PDF");
  return out;
}

}  // namespace renderer
