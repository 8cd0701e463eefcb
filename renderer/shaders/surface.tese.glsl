// Evaluates the PN patch: cubic position and quadratic normal (docs/algorithms.md 1.2, 1.3).
// gl_TessCoord = (b1, b2, b3), the weights of corners 0, 1, 2 (P1, P2, P3).
layout(triangles, fractional_odd_spacing, ccw) in;
in vec3 c_pos[];
in vec3 c_nrm[];
patch in vec3 p_b210, p_b120, p_b021, p_b012, p_b102, p_b201, p_b111;
patch in vec3 p_n110, p_n011, p_n101;
patch in float p_coarse;
out vec3 f_pos;
out vec3 f_nrm;
flat out float f_coarse;
// Captured by transform feedback in TerrainRenderer::capture_pn (unused otherwise).
out uint tf_face;
out vec3 tf_bary;
out vec3 tf_pos;
out vec3 tf_nrm;

void main() {
  float b1 = gl_TessCoord.x, b2 = gl_TessCoord.y, b3 = gl_TessCoord.z;
  vec3 p = c_pos[0] * (b1 * b1 * b1) + c_pos[1] * (b2 * b2 * b2) + c_pos[2] * (b3 * b3 * b3) +
           3.0 * (p_b210 * (b1 * b1 * b2) + p_b120 * (b1 * b2 * b2) + p_b201 * (b1 * b1 * b3) +
                  p_b102 * (b1 * b3 * b3) + p_b021 * (b2 * b2 * b3) + p_b012 * (b2 * b3 * b3)) +
           6.0 * p_b111 * (b1 * b2 * b3);
  vec3 n = c_nrm[0] * (b1 * b1) + c_nrm[1] * (b2 * b2) + c_nrm[2] * (b3 * b3) + p_n110 * (b1 * b2) +
           p_n011 * (b2 * b3) + p_n101 * (b1 * b3);
  float len = length(n);
  n = len > 1e-12 ? n / len : c_nrm[0];
  f_pos = p;
  f_nrm = n;
  f_coarse = p_coarse;
  gl_Position = u_view_proj * vec4(p, 1.0);
  tf_face = uint(gl_PrimitiveID);
  tf_bary = gl_TessCoord;
  tf_pos = p;
  tf_nrm = n;
}
