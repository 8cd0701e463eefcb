// PN triangle control points (Vlachos et al. 2001; docs/algorithms.md 1.1, 1.3; the CPU
// reference is libterrain's make_pn_patch) and adaptive tessellation levels.
layout(vertices = 3) out;
in vec3 v_pos[];
in vec3 v_nrm[];
out vec3 c_pos[];
out vec3 c_nrm[];
patch out vec3 p_b210, p_b120, p_b021, p_b012, p_b102, p_b201, p_b111;
patch out vec3 p_n110, p_n011, p_n101;
// 1 on a coarse patch (levels of detail; u_lod): its facing is its geometry's.
patch out float p_coarse;
layout(location = TR_LOC_SURFACE_MODE) uniform int u_mode;  // 0: TFT (toward-facing fragments), 1: AFT (away-facing)

vec2 to_pixels(vec4 c) { return (c.xy / c.w * 0.5 + 0.5) * u_viewport.xy; }

// Level of an edge: its screen length over the target pixels per edge, in [1, max]. An
// end at or behind the near plane gets the maximum. Computed from the edge's two corners
// only, so both patches sharing the edge agree (no cracks).
float edge_level(vec4 ci, vec4 cj) {
  if (ci.w <= u_misc.x || cj.w <= u_misc.x) return u_viewport.w;
  return clamp(distance(to_pixels(ci), to_pixels(cj)) / u_viewport.z, 1.0, u_viewport.w);
}

void main() {
  c_pos[gl_InvocationID] = v_pos[gl_InvocationID];
  c_nrm[gl_InvocationID] = v_nrm[gl_InvocationID];
  if (gl_InvocationID != 0) return;

  vec3 p1 = v_pos[0], p2 = v_pos[1], p3 = v_pos[2];
  vec3 n1 = v_nrm[0], n2 = v_nrm[1], n3 = v_nrm[2];
  p_b210 = edge_point(p1, p2, n1);
  p_b120 = edge_point(p2, p1, n2);
  p_b021 = edge_point(p2, p3, n2);
  p_b012 = edge_point(p3, p2, n3);
  p_b102 = edge_point(p3, p1, n3);
  p_b201 = edge_point(p1, p3, n1);
  vec3 e = (p_b210 + p_b120 + p_b021 + p_b012 + p_b102 + p_b201) / 6.0;
  vec3 v = (p1 + p2 + p3) / 3.0;
  p_b111 = e + (e - v) / 2.0;
  vec3 fn = cross(p2 - p1, p3 - p1);
  fn = length(fn) > 0.0 ? normalize(fn) : vec3(0.0, 0.0, 1.0);
  p_n110 = mid_normal(p1, p2, n1, n2, fn);
  p_n011 = mid_normal(p2, p3, n2, n3, fn);
  p_n101 = mid_normal(p3, p1, n3, n1, fn);
  vec2 e1 = p2.xy - p1.xy, e2 = p3.xy - p2.xy, e3 = p1.xy - p3.xy;
  p_coarse = u_lod.x > 0.0 && max(dot(e1, e1), max(dot(e2, e2), dot(e3, e3))) > u_lod.x ? 1.0 : 0.0;

  if (tess_override() > 0.0) {  // fixed level (tests, capture)
    gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = tess_override();
    gl_TessLevelInner[0] = tess_override();
    return;
  }
  // Cull: the patch lies in the convex hull of its 10 control points; drop it when they
  // are all beyond one side plane of the view, or all behind the eye.
  vec4 c[10] = vec4[10](u_view_proj * vec4(p1, 1), u_view_proj * vec4(p2, 1), u_view_proj * vec4(p3, 1),
                        u_view_proj * vec4(p_b210, 1), u_view_proj * vec4(p_b120, 1),
                        u_view_proj * vec4(p_b021, 1), u_view_proj * vec4(p_b012, 1),
                        u_view_proj * vec4(p_b102, 1), u_view_proj * vec4(p_b201, 1),
                        u_view_proj * vec4(p_b111, 1));
  bvec4 all_out = bvec4(true);
  bool all_behind = true;
  for (int i = 0; i < 10; ++i) {
    all_out = bvec4(all_out.x && c[i].x < -c[i].w, all_out.y && c[i].x > c[i].w,
                    all_out.z && c[i].y < -c[i].w, all_out.w && c[i].y > c[i].w);
    all_behind = all_behind && c[i].w <= 0.0;
  }
  // Facing cull: on the patch, n(b) = sum_j B_j n_j and eye - p(b) = sum_k B_k (eye - b_k)
  // with Bernstein weights B >= 0, so n . (eye - p) has the sign of every product
  // n_j . (eye - b_k) when they all agree: a patch facing the eye everywhere has no
  // away-facing fragment (skip it in AFT), one facing away everywhere none toward (TFT).
  vec3 nc[6] = vec3[6](n1, n2, n3, p_n110, p_n011, p_n101);
  vec3 bc[10] = vec3[10](p1, p2, p3, p_b210, p_b120, p_b021, p_b012, p_b102, p_b201, p_b111);
  bool all_toward = true, all_away = true;
  for (int j = 0; j < 6; ++j)
    for (int k = 0; k < 10; ++k) {
      float d = dot(nc[j], to_eye(bc[k]));
      all_toward = all_toward && d > 0.0;
      all_away = all_away && d < 0.0;
    }
  // A coarse patch's fragments face by its geometry, not by its (fine) normals: no facing
  // cull here (this stage runs on one thread in llvmpipe; AFT's compute pass culls coarse
  // patches by their geometry, surface_cull.comp.glsl).
  bool facing_cull = p_coarse < 0.5 && ((u_mode == 1 && all_toward) || (u_mode == 0 && all_away));
  if (any(all_out) || all_behind || facing_cull) {
    gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 0.0;
    gl_TessLevelInner[0] = 0.0;
    return;
  }
  // Outer level k belongs to the edge opposite corner k (gl_TessCoord[k] = 0 there).
  float l0 = edge_level(c[1], c[2]), l1 = edge_level(c[2], c[0]), l2 = edge_level(c[0], c[1]);
  gl_TessLevelOuter[0] = l0;
  gl_TessLevelOuter[1] = l1;
  gl_TessLevelOuter[2] = l2;
  gl_TessLevelInner[0] = max(l0, max(l1, l2));
}
