// SIL, formulated silhouettes, first step (renderer::formulated_silhouettes is the CPU
// reference): per pixel, g = -n . u_formulated.xyz (> 0: the drawn surface faces the
// lowered eye) averaged over the terrain pixels of its 3 x 3 window (the drawn normals'
// pixel noise smoothed), or 2 off the terrain. formulated.glsl reads it. A work group
// takes a tile of TR_FACING_TILE x TR_FACING_TILE pixels: each normal of the tile and its
// two-pixel ring is fetched once into shared memory, not nine times. It also marks the
// TR_SILHOUETTE_TILE tiles that hold a pixel facing the lowered eye whose neighbour one
// step on does not (formulated.glsl's first two tests): the only tiles the test is drawn on.
#define TR_FACING_TILE 16  // TR_LOCAL_SIZE invocations, a pixel each
#define TR_FACING_NORMALS (TR_FACING_TILE + 4)  // the tile and two pixels around it
#define TR_FACING_SIDE (TR_FACING_TILE + 2)     // the facing of the tile and one pixel around
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(binding = TR_TEX_SURFACE_NORMAL) uniform sampler2D u_normal;
layout(binding = TR_IMG_FORMULATED_FACING, r32f) uniform writeonly image2D u_facing_out;
layout(binding = TR_IMG_FORMULATED_TILES, r8) uniform writeonly image2D u_formulated_tiles;
layout(location = TR_LOC_FORMULATED) uniform vec4 u_formulated;
layout(location = TR_LOC_FORMULATED_STEP) uniform ivec2 u_formulated_step;
shared float s_g[TR_FACING_NORMALS * TR_FACING_NORMALS];
shared bool s_on[TR_FACING_NORMALS * TR_FACING_NORMALS];
shared float s_facing[TR_FACING_SIDE * TR_FACING_SIDE];
const uint kInvocations = uint(TR_LOCAL_SIZE);
void main() {
  ivec2 size = textureSize(u_normal, 0), tile0 = ivec2(gl_WorkGroupID.xy) * TR_FACING_TILE;
  for (uint i = gl_LocalInvocationIndex; i < uint(TR_FACING_NORMALS * TR_FACING_NORMALS); i += kInvocations) {
    ivec2 r = tile0 - 2 + ivec2(int(i) % TR_FACING_NORMALS, int(i) / TR_FACING_NORMALS);
    bool inside = all(greaterThanEqual(r, ivec2(0))) && all(lessThan(r, size));
    vec4 n = inside ? texelFetch(u_normal, r, 0) : vec4(0.0);
    s_on[i] = inside && n.w > 0.5;
    s_g[i] = -(n.x * u_formulated.x + n.y * u_formulated.y + n.z * u_formulated.z);
  }
  barrier();
  for (uint i = gl_LocalInvocationIndex; i < uint(TR_FACING_SIDE * TR_FACING_SIDE); i += kInvocations) {
    int x = int(i) % TR_FACING_SIDE, y = int(i) / TR_FACING_SIDE;
    int centre = (y + 1) * TR_FACING_NORMALS + x + 1;
    float sum = 0.0, count = 0.0;
    if (s_on[centre])
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int j = centre + dy * TR_FACING_NORMALS + dx;
          if (!s_on[j]) continue;
          sum += s_g[j];
          count += 1.0;
        }
    s_facing[i] = count > 0.0 ? sum / count : 2.0;  // off the image: s_on is false, 2
  }
  barrier();
  ivec2 local = ivec2(int(gl_LocalInvocationIndex) % TR_FACING_TILE, int(gl_LocalInvocationIndex) / TR_FACING_TILE);
  ivec2 p = tile0 + local;
  if (any(greaterThanEqual(p, size))) return;
  float g = s_facing[(local.y + 1) * TR_FACING_SIDE + local.x + 1];
  imageStore(u_facing_out, p, vec4(g));
  ivec2 q = local + 1 + u_formulated_step;
  if (g > 0.0 && s_facing[q.y * TR_FACING_SIDE + q.x] <= 0.0)
    imageStore(u_formulated_tiles, p / TR_SILHOUETTE_TILE, vec4(1.0));
}
