// SIL, formulated silhouettes, first step (renderer::formulated_silhouettes is the CPU
// reference): per pixel, g = -n . u_formulated.xyz (> 0: the drawn surface faces the
// lowered eye) averaged over the terrain pixels of its 3 x 3 window (the drawn normals'
// pixel noise smoothed), or 2 off the terrain. formulated.glsl reads it.
layout(binding = TR_TEX_SURFACE_NORMAL) uniform sampler2D u_normal;
layout(location = TR_LOC_FORMULATED) uniform vec4 u_formulated;
layout(location = 0) out vec4 o_facing;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy), size = textureSize(u_normal, 0);
  float sum = 0.0, count = 0.0;
  if (texelFetch(u_normal, p, 0).w > 0.5)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 r = p + ivec2(dx, dy);
        if (any(lessThan(r, ivec2(0))) || any(greaterThanEqual(r, size))) continue;
        vec4 n = texelFetch(u_normal, r, 0);
        if (!(n.w > 0.5)) continue;
        sum += -(n.x * u_formulated.x + n.y * u_formulated.y + n.z * u_formulated.z);
        count += 1.0;
      }
  o_facing = vec4(count > 0.0 ? sum / count : 2.0);
}
