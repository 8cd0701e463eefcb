// TFT, first: the patches split between the two ways of drawing them (one invocation per
// patch, on all of llvmpipe's threads). A patch whose three edges span at most the target
// pixels per edge (with a margin: surface.tesc.glsl's edge_level is then exactly 1, every
// edge and the inside one segment) tessellates into its own flat triangle, the corners
// (gl_TessCoord (1, 0, 0) ...: the PN patch's corner points and normals): it is listed in
// FlatPatches and drawn as that triangle, without the tessellation stages (which llvmpipe
// runs on one thread, about 1 us a patch whatever its level). Every other patch is listed
// (patch_list.glsl, as surface_cull.comp.glsl lists AFT's) and tessellated; the
// control stage culls those as before. A flat patch entirely beyond one side of the view is
// left out (its triangle would draw nothing); one facing away is drawn and its fragments
// discarded, as the control stage's facing cull would have dropped them. FlatPatches: two
// DrawElementsIndirectCommands (5 uints each: fine patches, then coarse ones: levels of
// detail, facing by geometry), then the fine patches' indices from uint 10 and the coarse
// ones' from uint 10 + 3 u_patches.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_MESH_POSITIONS) readonly buffer MeshPositions { float pos[]; };
layout(std430, binding = TR_SSBO_SURFACE_INDICES) readonly buffer SurfaceIndices { uint tri[]; };
layout(std430, binding = TR_SSBO_FLAT_PATCHES) buffer FlatPatches { uint flat_tri[]; };
layout(location = TR_LOC_PATCH_COUNT) uniform uint u_patches;
vec3 mesh_pos(uint v) { return vec3(pos[3u * v], pos[3u * v + 1u], pos[3u * v + 2u]); }
vec2 to_pixels(vec4 c) { return (c.xy / c.w * 0.5 + 0.5) * u_viewport.xy; }
// Whether surface.tesc.glsl's edge_level of this edge is 1, with room for rounding.
bool one_segment(vec4 ci, vec4 cj) {
  return ci.w > u_misc.x && cj.w > u_misc.x && distance(to_pixels(ci), to_pixels(cj)) <= 0.999 * u_viewport.z;
}
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (i >= u_patches) return;
  uint v1 = tri[3u * i], v2 = tri[3u * i + 1u], v3 = tri[3u * i + 2u];
  vec3 p1 = exaggerate_position(mesh_pos(v1)), p2 = exaggerate_position(mesh_pos(v2));
  vec3 p3 = exaggerate_position(mesh_pos(v3));
  vec4 c1 = u_view_proj * vec4(p1, 1.0), c2 = u_view_proj * vec4(p2, 1.0), c3 = u_view_proj * vec4(p3, 1.0);
  if (tess_override() > 0.0 || !(one_segment(c2, c3) && one_segment(c3, c1) && one_segment(c1, c2))) {
    list_patch(v1, v2, v3);
    return;
  }
  if ((c1.x < -c1.w && c2.x < -c2.w && c3.x < -c3.w) || (c1.x > c1.w && c2.x > c2.w && c3.x > c3.w) ||
      (c1.y < -c1.w && c2.y < -c2.w && c3.y < -c3.w) || (c1.y > c1.w && c2.y > c2.w && c3.y > c3.w))
    return;
  // Coarse as surface.tesc.glsl's p_coarse: a plan edge longer than a fine cell's diagonal.
  vec2 e1 = p2.xy - p1.xy, e2 = p3.xy - p2.xy, e3 = p1.xy - p3.xy;
  bool coarse = u_lod.x > 0.0 && max(dot(e1, e1), max(dot(e2, e2), dot(e3, e3))) > u_lod.x;
  uint list = coarse ? 5u : 0u;
  uint slot = atomicAdd(flat_tri[list], 3u) / 3u;
  uint at = flat_tri[list + 2u] + 3u * slot;
  flat_tri[at] = v1, flat_tri[at + 1u] = v2, flat_tri[at + 2u] = v3;
}
