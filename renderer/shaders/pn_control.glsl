// PN triangle control points (Vlachos et al. 2001; docs/algorithms.md 1.1, 1.3; the CPU
// reference is libterrain's make_pn_patch), for the surface's tessellation control stage
// and AFT's patch cull (surface_cull.comp.glsl).

// Point 1/3 along Pi -> Pj projected into the tangent plane of Pi.
vec3 edge_point(vec3 pi, vec3 pj, vec3 ni) { return (2.0 * pi + pj - dot(pj - pi, ni) * ni) / 3.0; }

// How the cubic's own geometry faces the viewer (a coarse patch's facing, surface.frag.glsl;
// AFT's patch cull, surface_cull.comp.glsl),
// from its control points b (b300 b030 b003 b210 b120 b021 b012 b102 b201 b111). Its
// derivatives along b2 and b3 are quadratics with control vectors a_m and c_m, so its
// normal dP/du x dP/dv is sum B_m B_n (a_m x c_n) and, with to_eye(P) = sum C_k to_eye(b_k)
// (Bernstein weights >= 0), n . to_eye has the sign of all 360 products (a_m x c_n) .
// to_eye(b_k) when they agree: toward everywhere, or away everywhere (with a margin for
// rounding).
void geometric_facing(vec3 b[10], out bool all_toward, out bool all_away) {
  vec3 a[6] = vec3[6](b[3] - b[0], b[1] - b[4], b[6] - b[7], b[4] - b[3], b[5] - b[9], b[9] - b[8]);
  vec3 c[6] = vec3[6](b[8] - b[0], b[5] - b[4], b[2] - b[7], b[9] - b[3], b[6] - b[9], b[7] - b[8]);
  all_toward = true;
  all_away = true;
  for (int m = 0; m < 6; ++m)
    for (int n = 0; n < 6; ++n) {
      vec3 x = cross(a[m], c[n]);
      for (int k = 0; k < 10; ++k) {
        vec3 t = to_eye(b[k]);
        float d = dot(x, t), margin = 1e-4 * length(x) * length(t);
        all_toward = all_toward && d > margin;
        all_away = all_away && d < -margin;
      }
    }
}

// Mid-edge normal: Ni + Nj reflected in the plane perpendicular to the edge.
vec3 mid_normal(vec3 pi, vec3 pj, vec3 ni, vec3 nj, vec3 face_n) {
  vec3 e = pj - pi;
  float ee = dot(e, e);
  vec3 h = ee > 0.0 ? ni + nj - 2.0 * dot(e, ni + nj) / ee * e : ni + nj;
  float len = length(h);
  return len > 1e-12 ? h / len : face_n;
}
