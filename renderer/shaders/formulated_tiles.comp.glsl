// SIL, formulated silhouettes, before the facing: marks each TR_SILHOUETTE_TILE tile that
// holds a terrain pixel whose own facing -n . u_formulated.xyz is at most -strength (a
// little above, for the rounding of formulated_facing.frag.glsl's mean). A formulated pixel
// needs a smoothed facing <= -strength within TR_FORMULATED_REACH pixels along its step, so
// such a pixel within TR_FORMULATED_REACH + 1 (formulated.glsl); the facing and the test are
// drawn only there (image_passes.cpp), with the same pixels as over the whole image.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(binding = TR_TEX_SURFACE_NORMAL) uniform sampler2D u_normal;
layout(binding = TR_IMG_FORMULATED_TILES, r8) uniform writeonly image2D u_formulated_marks;
layout(location = TR_LOC_FORMULATED) uniform vec4 u_formulated;
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  ivec2 tiles = imageSize(u_formulated_marks), size = textureSize(u_normal, 0);
  if (i >= uint(tiles.x * tiles.y)) return;
  ivec2 t = ivec2(int(i) % tiles.x, int(i) / tiles.x), p0 = t * TR_SILHOUETTE_TILE;
  ivec2 p1 = min(p0 + TR_SILHOUETTE_TILE, size);
  float below = -u_formulated.w + 1e-4;
  bool mark = false;
  for (int y = p0.y; y < p1.y && !mark; ++y)
    for (int x = p0.x; x < p1.x && !mark; ++x) {
      vec4 n = texelFetch(u_normal, ivec2(x, y), 0);
      mark = n.w > 0.5 && -(n.x * u_formulated.x + n.y * u_formulated.y + n.z * u_formulated.z) <= below;
    }
  imageStore(u_formulated_marks, t, vec4(mark ? 1.0 : 0.0));
}
