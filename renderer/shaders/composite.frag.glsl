// LAY: the background, the surface (shaded or mask colour) where a toward surface is,
// PEL, crease and object-space edge pixels whose depth is not behind that surface,
// silhouettes at their pixels' opacity (the piece rule lowers it on short pieces).
// Pixel-exact: the silhouette pixels dilated to the silhouette width. Anti-aliased
// (u_style.x != 0): PELs and creases blend by their coverage (hidden lines were removed
// when they were drawn); silhouettes, found per pixel, are drawn as a band TR_SILHOUETTE_BAND (0.8) px wider
// than the silhouette width about the line fitted to the silhouette pixels around each
// pixel (silhouette_band).
//
// Two programs from this file: the base (no silhouettes) draws every pixel; with
// TR_COMPOSITE_SILHOUETTES defined it draws again, the whole colour with the silhouettes,
// only the rectangles of pixels near tiles that SIL marked (tile_rects.comp.glsl), and a
// pixel there out of the silhouettes' reach discards (the silhouettes add nothing there,
// so the base's colour is the frame's). llvmpipe runs both sides of an `if` for its groups
// of pixels, lanes masked, and a discard does not end a group early: drawn over every
// pixel, the band's code would cost its time everywhere, even where no silhouette is.
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(binding = TR_TEX_SURFACE_COLOUR) uniform sampler2D u_surface_colour;
layout(binding = TR_TEX_CREASE_COLOUR) uniform sampler2D u_crease;
layout(binding = TR_TEX_CREASE_DEPTH) uniform sampler2D u_crease_depth;
layout(binding = TR_TEX_SILHOUETTE) uniform sampler2D u_silhouette;
layout(binding = TR_TEX_SILHOUETTE_TILES) uniform sampler2D u_silhouette_tiles;
layout(location = TR_LOC_LAYERS) uniform ivec4 u_layers;  // shaded, mask, creases, silhouettes
layout(location = TR_LOC_BACKGROUND) uniform vec3 u_background;
layout(location = TR_LOC_MASK_COLOUR) uniform vec3 u_mask_colour;
layout(location = TR_LOC_CREASE_COLOUR) uniform vec3 u_crease_colour;
layout(location = TR_LOC_SILHOUETTE_COLOUR) uniform vec3 u_silhouette_colour;
layout(location = TR_LOC_SILHOUETTE_WIDTH) uniform int u_silhouette_width;
// No silhouette coverage farther than this from every silhouette pixel (CompositePass
// sets it: anti-aliased, the band's half-width + 1.5 px; pixel-exact, the dilation's).
layout(location = TR_LOC_TILE_REACH) uniform int u_reach;
layout(binding = TR_TEX_PEL_COLOUR) uniform sampler2D u_pel;
layout(binding = TR_TEX_PEL_DEPTH) uniform sampler2D u_pel_depth;
layout(location = TR_LOC_PEL_COLOUR) uniform vec3 u_pel_colour;
layout(location = TR_LOC_PELS) uniform int u_pels;
layout(binding = TR_TEX_EDGE_COLOUR) uniform sampler2D u_edge;
layout(binding = TR_TEX_EDGE_DEPTH) uniform sampler2D u_edge_depth;
layout(location = TR_LOC_EDGE_COLOUR) uniform vec3 u_edge_colour;
layout(location = TR_LOC_EDGES) uniform int u_edges;
layout(location = 0) out vec4 o_colour;

// A line of colour `col` covering `cov` of a pixel laid over it: over the opaque frame a
// mix; over a transparent background (TR_COMPOSITE_TRANSPARENT) the "over" operator with
// straight alpha, so a line's rim outside the terrain is the line's colour, part covered.
#ifdef TR_COMPOSITE_TRANSPARENT
void lay(inout vec3 c, inout float a, vec3 col, float cov) {
  float b = cov + a * (1.0 - cov);
  c = b > 0.0 ? (col * cov + c * a * (1.0 - cov)) / b : col;
  a = b;
}
#define LAY(col, cov) lay(c, a, col, cov)
#else
#define LAY(col, cov) c = mix(c, col, cov)
#endif

// A line layer's pixel p is drawn when it is covered and not behind the surface (distance t).
bool line_visible(sampler2D colour, sampler2D depth, ivec2 p, float t) {
  return texelFetch(colour, p, 0).r > 0.0 && far_of(texelFetch(depth, p, 0).r) <= t;
}

// A crease or PEL layer's coverage of pixel p: anti-aliased, the layer's value (line.frag
// kept it to the surface); pixel-exact, 1 where line_visible on the surface (t < 1: these
// lines lie on it; a segment spanning a skyline would otherwise reach into the sky).
float line_cover(sampler2D colour, sampler2D depth, ivec2 p, float t) {
  if (u_style.x != 0.0) return texelFetch(colour, p, 0).r;
  return t < 1.0 && line_visible(colour, depth, p, t) ? 1.0 : 0.0;
}

// Anti-aliased silhouette coverage of pixel p, from the silhouette pixels q of its window
// (3 px, or r + 1.5 if wider), taken one line at a time: a line is the pixels of the window
// 8-connected to its nearest pixel (two silhouettes a few pixels apart are two lines, not
// one knot). A line's pixels, weighted by their opacity and a Gaussian of their distance
// (sigma 1.5 px), give a centre and a principal direction (the weighted covariance); where
// they lie along a line (minor eigenvalue under 0.3 of the major), p's coverage is the
// exact share of p inside the band of half-width r about it (pixel_share_below), otherwise
// a disc of radius r about the nearest pixel; at most r + 1.5 px beyond the nearest pixel
// (line ends), at that pixel's opacity. The lines' coverages add up (to 1 at most): two
// lines are at least 2 px apart, so at the default width their bands do not overlap. The
// nearest three lines at most.
const int SIL_MAX_WIN = 6;  // r + 1.5 for --silhouette-width 9
const int SIL_ROWS = 2 * SIL_MAX_WIN + 1;

// The silhouette opacity at q, 0 outside the image.
float silhouette_at(ivec2 q, ivec2 size) {
  return any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)) ? 0.0 : texelFetch(u_silhouette, q, 0).r;
}

// The weighted moments of window pixels: total weight, first moment, second moments (xx,
// xy, yy); each pixel v (offset from the centre) weighs its opacity o times a Gaussian of
// its distance (sigma 1.5 px).
struct Moments {
  float sw;
  vec2 m;
  vec3 mom;
};
void add_pixel(inout Moments a, vec2 v, float o) {
  float w = o * exp(-dot(v, v) / 4.5);
  a.sw += w;
  a.m += w * v;
  a.mom += w * vec3(v.x * v.x, v.x * v.y, v.y * v.y);
}

// The coverage of the window's centre by a band of half-width r about the line that pixels
// of moments a follow; a disc about their nearest pixel (near_d away) where they follow no
// line.
float band_cover(Moments a, float near_d, float r) {
  vec2 m = a.m / a.sw;
  float cxx = a.mom.x / a.sw - m.x * m.x, cxy = a.mom.y / a.sw - m.x * m.y, cyy = a.mom.z / a.sw - m.y * m.y;
  float disc = sqrt((cxx - cyy) * (cxx - cyy) + 4.0 * cxy * cxy);
  float l1 = 0.5 * (cxx + cyy + disc), l2 = 0.5 * (cxx + cyy - disc);
  if (!(l1 > 0.0 && l2 < 0.3 * l1)) return clamp(r + 0.5 - near_d, 0.0, 1.0);
  float th = 0.5 * atan(2.0 * cxy, cxx - cyy);
  vec2 n = vec2(-sin(th), cos(th));
  float s = -dot(m, n);  // the centre's signed distance from the line
  return pixel_share_below(r - s, n) - pixel_share_below(-r - s, n);
}

// The nearest window pixel so far (squared distance, opacity, bit position dx + win, dy +
// win): pixel d with opacity o replaces it when nearer, or as near and more opaque.
struct Nearest {
  float d2, o;
  ivec2 seed;
};
void take_nearer(inout Nearest a, ivec2 d, float o, int win) {
  float d2 = float(d.x * d.x + d.y * d.y);
  if (d2 < a.d2 || (d2 == a.d2 && o > a.o)) a = Nearest(d2, o, d + win);
}

// Whether a tile that SIL marked (one holding a silhouette pixel) lies within `reach`
// pixels of p.
bool near_marked_tile(ivec2 p, ivec2 size, int reach) {
  ivec2 t0 = max(p - reach, ivec2(0)) / TR_SILHOUETTE_TILE, t1 = min(p + reach, size - 1) / TR_SILHOUETTE_TILE;
  bool any_tile = false;
  for (int ty = t0.y; ty <= t1.y && !any_tile; ++ty)
    for (int tx = t0.x; tx <= t1.x && !any_tile; ++tx) any_tile = texelFetch(u_silhouette_tiles, ivec2(tx, ty), 0).r > 0.0;
  return any_tile;
}

float silhouette_band(ivec2 p, ivec2 size, float r) {
  // No coverage beyond r + 1.5 px of every silhouette pixel (the caller looked at the
  // tiles): look in the pixels first.
  int reach = int(r + 1.5);
  bool any_near = false;
  for (int dy = -reach; dy <= reach && !any_near; ++dy)
    for (int dx = -reach; dx <= reach && !any_near; ++dx)
      any_near = float(dx * dx + dy * dy) < (r + 1.5) * (r + 1.5) && silhouette_at(p + ivec2(dx, dy), size) > 0.0;
  if (!any_near) return 0.0;
  int win = min(max(3, reach), SIL_MAX_WIN), n = 2 * win + 1;
  // The window's silhouette pixels, a bit mask per row (bit dx + win of row dy + win), the
  // moments of them all, and the nearest.
  uint rows[SIL_ROWS];
  Moments all = Moments(0.0, vec2(0.0), vec3(0.0));
  Nearest near = Nearest(1e9, 0.0, ivec2(0));
  for (int dy = -win; dy <= win; ++dy) {
    uint bits = 0u;
    for (int dx = -win; dx <= win; ++dx) {
      float o = silhouette_at(p + ivec2(dx, dy), size);
      if (!(o > 0.0)) continue;
      bits |= 1u << uint(dx + win);
      add_pixel(all, vec2(dx, dy), o);
      take_nearer(near, ivec2(dx, dy), o, win);
    }
    rows[dy + win] = bits;
  }
  float sum = 0.0;
  for (int line = 0; line < 3; ++line) {
    if (line > 0) {  // the nearest pixel not yet taken
      near = Nearest(1e9, 0.0, ivec2(0));
      for (int dy = -win; dy <= win; ++dy)
        for (int dx = -win; dx <= win; ++dx)
          if ((rows[dy + win] & (1u << uint(dx + win))) != 0u && float(dx * dx + dy * dy) <= near.d2)
            take_nearer(near, ivec2(dx, dy), silhouette_at(p + ivec2(dx, dy), size), win);
    }
    float near_d = sqrt(near.d2), near_o = near.o;
    ivec2 seed = near.seed;
    if (near_d >= r + 1.5) break;  // none left within reach
    // Its line: the pixels 8-connected to it within the window (a flood fill of the masks).
    uint comp[SIL_ROWS];
    for (int j = 0; j < n; ++j) comp[j] = 0u;
    comp[seed.y] = 1u << uint(seed.x);
    for (bool grew = true; grew;) {
      grew = false;
      for (int j = 0; j < n; ++j) {
        uint c = comp[j], nb = c | (c << 1) | (c >> 1);
        if (j > 0) nb |= comp[j - 1] | (comp[j - 1] << 1) | (comp[j - 1] >> 1);
        if (j + 1 < n) nb |= comp[j + 1] | (comp[j + 1] << 1) | (comp[j + 1] >> 1);
        uint g = nb & rows[j];
        if (g != c) {
          comp[j] = g;
          grew = true;
        }
      }
    }
    bool whole = true;  // the line is every pixel left: its moments are those of them all
    for (int j = 0; j < n; ++j) {
      whole = whole && comp[j] == rows[j];
      rows[j] &= ~comp[j];
    }
    Moments own = all;
    if (!whole || line > 0) {
      own = Moments(0.0, vec2(0.0), vec3(0.0));
      for (int dy = -win; dy <= win; ++dy)
        for (int dx = -win; dx <= win; ++dx)
          if ((comp[dy + win] & (1u << uint(dx + win))) != 0u) add_pixel(own, vec2(dx, dy), silhouette_at(p + ivec2(dx, dy), size));
    }
    sum += min(band_cover(own, near_d, r), clamp(r + 1.5 - near_d, 0.0, 1.0)) * near_o;
    if (whole) break;
  }
  return min(sum, 1.0);
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_toward, 0);
#ifdef TR_COMPOSITE_SILHOUETTES
  if (!near_marked_tile(p, size, u_reach)) discard;
#endif
#if defined(TR_COMPOSITE_ANTIALIASED) && defined(TR_COMPOSITE_NO_EDGES) && \
    !defined(TR_COMPOSITE_SURFACE_COPIED)
  // Anti-aliased lines do not look at the depth here (line.frag hid them), and the toward
  // pass wrote alpha 1 exactly where it wrote a depth: one fetch fewer. (Not where the
  // toward pass cleared its colour to the opaque background, CompositePass::surface_is_base:
  // the background is then u_background, as in the frames that draw every pixel here.)
  vec4 sc = texelFetch(u_surface_colour, p, 0);
  bool surface = sc.a > 0.0;
  float t = surface ? 0.0 : 1.0;
#else
  float t = far_of(texelFetch(u_toward, p, 0).r);
  bool surface = t < 1.0;
  vec4 sc = texelFetch(u_surface_colour, p, 0);
#endif
  vec3 c = u_background;
  if (surface && u_layers.x != 0) c = sc.rgb;
  else if (surface && u_layers.y != 0) c = u_mask_colour;
  float a = 1.0;  // the pixel's alpha: 1 but where the background is none
#ifdef TR_COMPOSITE_TRANSPARENT
  if (!(surface && (u_layers.x != 0 || u_layers.y != 0))) a = 0.0;  // no surface drawn there
#endif
  // A layer the frame does not draw is compiled out (TR_COMPOSITE_NO_*, CompositePass):
  // llvmpipe would run its fetches under a mask.
#ifndef TR_COMPOSITE_NO_PELS
  if (u_pels != 0) LAY(u_pel_colour, line_cover(u_pel, u_pel_depth, p, t));
#endif
#ifndef TR_COMPOSITE_NO_CREASES
  if (u_layers.z != 0) LAY(u_crease_colour, line_cover(u_crease, u_crease_depth, p, t));
#endif
#ifndef TR_COMPOSITE_NO_EDGES
  if (u_edges != 0 && line_visible(u_edge, u_edge_depth, p, t)) LAY(u_edge_colour, 1.0);
#endif
#ifdef TR_COMPOSITE_SILHOUETTES
  float sil = 0.0;
  if (u_style.x != 0.0) {
    sil = silhouette_band(p, size, 0.5 * (float(u_silhouette_width) + float(TR_SILHOUETTE_BAND)));
  } else {
    // The dilation window [r0, r1]^2.
    int r0 = -(u_silhouette_width - 1) / 2, r1 = u_silhouette_width / 2;
    for (int dy = r0; dy <= r1; ++dy)
      for (int dx = r0; dx <= r1; ++dx)
        sil = max(sil, texelFetch(u_silhouette, clamp(p + ivec2(dx, dy), ivec2(0), size - 1), 0).r);
  }
  LAY(u_silhouette_colour, sil);
#endif
  o_colour = vec4(c, a);
}
