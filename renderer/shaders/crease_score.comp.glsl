// DM, step 1: the rendering score of every crease vertex (docs/algorithms.md 9.1; CPU
// reference: renderer::crease_score).
//   rs = (sw*sc + iw*ic + fw*fc) / divisor - rs_min,  sc = 1 - n.z,  ic = 1 - n.l,
//   rs_min = min + (1 - min) * falloff * clamp((d - d_near) / (d_far - d_near), 0, 1).
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_CREASE_SCORES) writeonly buffer Scores { float score[]; };
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (i >= uint(u_misc.z)) return;
  vec4 pf = cv[3u * i];
  vec3 p = exaggerate_position(pf.xyz);
  vec3 n = exaggerate_normal(cv[3u * i + 1u].xyz);
  float sc = 1.0 - n.z;
  float ic = 1.0 - dot(n, u_light.xyz);
  float raw = (u_weights.x * sc + u_weights.y * ic + u_weights.z * pf.w) / u_weights.w;
  float rs_min = u_score.x + (1.0 - u_score.x) * u_score.y *
                 clamp((view_distance(p) - u_style.z) / (u_score.z - u_style.z), 0.0, 1.0);
  // Channels begin where the page's area drains (StrokeRule::min_area): below it, no score.
  score[i] = cv[3u * i + 2u].x < u_strokes.w ? -1.0 : raw - rs_min;
}
