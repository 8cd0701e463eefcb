// LAY: the silhouettes' width and reach, for composite.frag.glsl and the tiles it draws
// (composite_tiles.vert.glsl).
layout(location = TR_LOC_SILHOUETTE_WIDTH) uniform int u_silhouette_width;

// The anti-aliased band's half-width r, pixels.
float silhouette_half_width() { return 0.5 * (float(u_silhouette_width) + 0.8); }

// No silhouette coverage farther than this from every silhouette pixel: anti-aliased,
// r + 1.5 px; pixel-exact, the dilation window's larger side.
int silhouette_reach() {
  return u_style.x != 0.0 ? int(silhouette_half_width() + 1.5) : max((u_silhouette_width - 1) / 2, u_silhouette_width / 2);
}
