// PEL fields, one stage per dispatch (u_stage): 0: f = max(0, N . L); 1: g = grad f, m = |g|
// and the maximum of m; 2: s = grad(m) . w; 3: c = grad(s) . w, with w = g / m.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(location = TR_LOC_PEL_STAGE) uniform int u_stage;
layout(location = TR_LOC_PEL_LIGHT) uniform vec3 u_pel_light;
void main() {
  uint v = invocation_index();
  if (v >= u_grid.x * u_grid.y) return;
  if (u_stage == 0) {
    field[v].f = max(0.0, dot(normal_at(v), u_pel_light));
  } else if (u_stage == 1) {
    vec2 g = vertex_gradient(v, 0);
    field[v].g = g;
    float m = length(g);
    field[v].m = m;
    atomicMax(max_m_bits, floatBitsToUint(m));  // m >= 0: the bits order like the values
  } else {
    float m = field[v].m;
    vec2 grad = vertex_gradient(v, u_stage - 1);  // of m (stage 2) or s (stage 3)
    float along = m > 0.0 ? dot(grad, field[v].g) / m : 0.0;
    if (u_stage == 2) field[v].s = along;
    else field[v].c = along;
  }
}
