// Hachures' field (renderer/core/hachures.hpp: hachure_field is the CPU reference):
// for each pixel TFT drew (its toward depth), the point is unprojected (u_inverse, the
// frame's inverse view-projection), the normal is the PN normal TFT wrote there (the
// surface as drawn, heights exaggerated: u_normal), and a step of 1 m down the fall line
// is projected back: the fall line's unit direction on the screen (u right, v down), the
// slope as drawn, the tone (u_tone 1: the light's, the shadow 1 - n.l less kFlatShare of
// the flat's; 0: the slope's, tan of the slope, black at 45 degrees) and the true height.
// One vec4 a pixel in the CPU field's order (row 0 at the top): (the fall line's angle
// atan2(v, u), slope, tone, height); slope -1 where no surface is, fall angle 4 where the
// ground has no fall line.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_HACHURE_FIELD) writeonly buffer HachureField { vec4 field[]; };
layout(binding = TR_TEX_TOWARD_DEPTH) uniform sampler2D u_toward;
layout(binding = TR_TEX_SURFACE_NORMAL) uniform sampler2D u_normal;
layout(location = TR_LOC_HACHURE_INVERSE) uniform mat4 u_inverse;
layout(location = TR_LOC_HACHURE_TONE) uniform int u_tone;
const float kFlatShare = 0.5;  // renderer::kFlatShare

vec2 to_pixel(vec3 p) {
  vec4 c = u_view_proj * vec4(p, 1.0);
  vec2 ndc = c.xy / c.w;
  return vec2((ndc.x + 1.0) * 0.5 * u_viewport.x, (1.0 - ndc.y) * 0.5 * u_viewport.y);
}

void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  int w = int(u_viewport.x), h = int(u_viewport.y);
  if (i >= uint(w * h)) return;
  int u = int(i) % w, v = int(i) / w;
  float depth = texelFetch(u_toward, ivec2(u, h - 1 - v), 0).r;
  field[i] = vec4(4.0, -1.0, 0.0, 0.0);
  if (far_of(depth) >= 1.0) return;  // no surface here
  float z_ndc = reversed_z() ? depth : 2.0 * depth - 1.0;
  vec4 q = u_inverse * vec4((float(u) + 0.5) / float(w) * 2.0 - 1.0, 1.0 - (float(v) + 0.5) / float(h) * 2.0, z_ndc, 1.0);
  vec3 p = q.xyz / q.w;  // exaggerated local frame
  vec3 ne = normalize(texelFetch(u_normal, ivec2(u, h - 1 - v), 0).xyz);  // the drawn surface's
  float e = u_eye.w;
  vec3 nt = normalize(vec3(ne.xy, ne.z * e));  // the true surface's
  vec2 grad = -nt.xy / max(nt.z, 1e-6);        // dz/dx, dz/dy, metres a metre
  float g = length(grad), drawn = g * e;
  float tone = u_tone == 1 ? clamp(1.0 - dot(ne, u_light.xyz) - kFlatShare * (1.0 - u_light.z), 0.0, 1.0)
                           : clamp(drawn, 0.0, 1.0);
  float angle = 4.0;
  if (g >= 1e-9) {
    vec2 d = to_pixel(p + vec3(-grad / g, -g * e)) - to_pixel(p);
    if (length(d) > 0.0) angle = atan(d.y, d.x);
  }
  field[i] = vec4(angle, atan(drawn), tone, p.z / e);
}
