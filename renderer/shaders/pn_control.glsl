// PN triangle control points (Vlachos et al. 2001; docs/algorithms.md 1.1, 1.3; the CPU
// reference is libterrain's make_pn_patch), for the surface's tessellation control stage
// and AFT's patch cull (surface_cull.comp.glsl).

// Point 1/3 along Pi -> Pj projected into the tangent plane of Pi.
vec3 edge_point(vec3 pi, vec3 pj, vec3 ni) { return (2.0 * pi + pj - dot(pj - pi, ni) * ni) / 3.0; }

// Mid-edge normal: Ni + Nj reflected in the plane perpendicular to the edge.
vec3 mid_normal(vec3 pi, vec3 pj, vec3 ni, vec3 nj, vec3 face_n) {
  vec3 e = pj - pi;
  float ee = dot(e, e);
  vec3 h = ee > 0.0 ? ni + nj - 2.0 * dot(e, ni + nj) / ee * e : ni + nj;
  float len = length(h);
  return len > 1e-12 ? h / len : face_n;
}
