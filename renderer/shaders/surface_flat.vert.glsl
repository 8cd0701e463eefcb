// TFT's flat patches (surface_split.comp.glsl): each patch's corners as the tessellation
// evaluation stage gives them at level 1 (surface.tese.glsl at gl_TessCoord (1, 0, 0), ...:
// the corner's point, its normal renormalised), to the same fragment stage.
layout(location = TR_ATTR_POSITION) in vec3 a_position;
layout(location = TR_ATTR_NORMAL) in vec3 a_normal;
layout(location = TR_LOC_FLAT_COARSE) uniform float u_flat_coarse;  // 1: coarse patches (levels of detail)
out vec3 f_pos;
out vec3 f_nrm;
flat out float f_coarse;
void main() {
  vec3 p = exaggerate_position(a_position);
  vec3 n = exaggerate_normal(a_normal);
  float len = length(n);
  f_pos = p;
  f_nrm = len > 1e-12 ? n / len : n;
  f_coarse = u_flat_coarse;
  gl_Position = u_view_proj * vec4(p, 1.0);
}
