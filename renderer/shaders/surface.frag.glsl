// TFT (u_mode 0): toward-facing fragments write the shaded colour and the toward depth.
// AFT (u_mode 1): away-facing fragments write the away depth only (and, surface_away.glsl,
// mark their tiles). Facing uses the PN normal and the line of sight: toward when
// n . (eye - p) > 0. On a coarse patch (levels of detail) the fine normals it carries may
// turn from the eye where its geometry faces it, and the ray would find no surface (a
// hole): there facing is the geometry's, the tessellated triangle's winding
// (gl_FrontFacing); its shading keeps the fine normals.
in vec3 f_pos;
in vec3 f_nrm;
flat in float f_coarse;
layout(location = 0) out vec4 o_colour;
layout(location = 1) out vec4 o_normal;  // TFT with hachures: the unit normal as drawn (hachure_field.comp.glsl)
layout(location = TR_LOC_SURFACE_MODE) uniform int u_mode;
#ifdef TR_SURFACE_AWAY_TILES
layout(binding = TR_IMG_AWAY_TILES, r8) uniform writeonly image2D u_away_tiles;
#endif
void main() {
  vec3 n = normalize(f_nrm);
  bool toward = f_coarse > 0.5 ? gl_FrontFacing : dot(n, to_eye(f_pos)) > 0.0;
  if ((u_mode == 0) != toward) discard;
#ifdef TR_SURFACE_AWAY_TILES
  // An away-facing fragment kept: its pixel gets an away depth, this one's or a nearer one's
  // (a silhouette pixel has one within a pixel of it: silhouette.frag.glsl).
  imageStore(u_away_tiles, ivec2(gl_FragCoord.xy) / TR_SILHOUETTE_TILE, vec4(1.0));
#endif
  float lambert = max(dot(n, u_light.xyz), 0.0);
  o_colour = vec4(vec3(0.2 + 0.8 * lambert), 1.0);
  o_normal = vec4(n, 1.0);
}
