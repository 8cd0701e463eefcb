// LAY: the background, the surface (shaded or mask colour) where a toward surface is,
// PEL, crease and object-space edge pixels whose depth is not behind that surface,
// silhouette pixels (dilated to the silhouette width, at their opacity: the piece rule
// lowers it on short pieces). Anti-aliased (u_style.x != 0):
// PELs and creases blend by their coverage (hidden lines were removed when they were
// drawn); silhouettes, found per pixel, are softened by a ring one pixel wide at 40 %.
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(binding = TR_TEX_SURFACE_COLOUR) uniform sampler2D u_surface_colour;
layout(binding = TR_TEX_CREASE_COLOUR) uniform sampler2D u_crease;
layout(binding = TR_TEX_CREASE_DEPTH) uniform sampler2D u_crease_depth;
layout(binding = TR_TEX_SILHOUETTE) uniform sampler2D u_silhouette;
layout(location = TR_LOC_LAYERS) uniform ivec4 u_layers;  // shaded, mask, creases, silhouettes
layout(location = TR_LOC_BACKGROUND) uniform vec3 u_background;
layout(location = TR_LOC_MASK_COLOUR) uniform vec3 u_mask_colour;
layout(location = TR_LOC_CREASE_COLOUR) uniform vec3 u_crease_colour;
layout(location = TR_LOC_SILHOUETTE_COLOUR) uniform vec3 u_silhouette_colour;
layout(location = TR_LOC_SILHOUETTE_WIDTH) uniform int u_silhouette_width;
layout(binding = TR_TEX_PEL_COLOUR) uniform sampler2D u_pel;
layout(binding = TR_TEX_PEL_DEPTH) uniform sampler2D u_pel_depth;
layout(location = TR_LOC_PEL_COLOUR) uniform vec3 u_pel_colour;
layout(location = TR_LOC_PELS) uniform int u_pels;
layout(binding = TR_TEX_EDGE_COLOUR) uniform sampler2D u_edge;
layout(binding = TR_TEX_EDGE_DEPTH) uniform sampler2D u_edge_depth;
layout(location = TR_LOC_EDGE_COLOUR) uniform vec3 u_edge_colour;
layout(location = TR_LOC_EDGES) uniform int u_edges;
layout(location = 0) out vec4 o_colour;

// A line layer's pixel p is drawn when it is covered and not behind the surface (distance t).
bool line_visible(sampler2D colour, sampler2D depth, ivec2 p, float t) {
  return texelFetch(colour, p, 0).r > 0.0 && far_of(texelFetch(depth, p, 0).r) <= t;
}

// A line layer's coverage of pixel p: anti-aliased, the layer's value; pixel-exact, 1
// where line_visible.
float line_cover(sampler2D colour, sampler2D depth, ivec2 p, float t) {
  if (u_style.x != 0.0) return texelFetch(colour, p, 0).r;
  return line_visible(colour, depth, p, t) ? 1.0 : 0.0;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(u_toward, 0);
  float t = far_of(texelFetch(u_toward, p, 0).r);
  bool surface = t < 1.0;
  vec3 c = u_background;
  if (surface && u_layers.x != 0) c = texelFetch(u_surface_colour, p, 0).rgb;
  else if (surface && u_layers.y != 0) c = u_mask_colour;
  if (u_pels != 0) c = mix(c, u_pel_colour, line_cover(u_pel, u_pel_depth, p, t));
  if (u_layers.z != 0) c = mix(c, u_crease_colour, line_cover(u_crease, u_crease_depth, p, t));
  if (u_edges != 0 && line_visible(u_edge, u_edge_depth, p, t)) c = u_edge_colour;
  if (u_layers.w != 0) {
    // The dilation window [r0, r1]^2; anti-aliased, one more pixel around it at 40 %.
    int r0 = -(u_silhouette_width - 1) / 2, r1 = u_silhouette_width / 2;
    int ring = u_style.x != 0.0 ? 1 : 0;
    float sil = 0.0;
    for (int dy = r0 - ring; dy <= r1 + ring; ++dy)
      for (int dx = r0 - ring; dx <= r1 + ring; ++dx) {
        ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
        bool core = dx >= r0 && dx <= r1 && dy >= r0 && dy <= r1;
        sil = max(sil, texelFetch(u_silhouette, q, 0).r * (core ? 1.0 : 0.4));
      }
    c = mix(c, u_silhouette_colour, sil);
  }
  o_colour = vec4(c, 1.0);
}
