// AFT, first: the patches that may have an away-facing fragment in view, listed for the
// draw (one invocation per patch; llvmpipe runs this on all threads, the tessellation
// control stage that culls them on one). A patch is left out only where surface.tesc.glsl
// would cull it too, with a margin for rounding: all its control points beyond one side
// of the view or behind the eye, or every product n_j . (eye - b_k) clearly positive (it
// faces the eye everywhere). They are listed as patch_list.glsl lists them. The control points
// are assembled here as surface.tesc.glsl assembles them, not through a shared function:
// moved into one, the control stage's surface changed by 1/255 at a few pixels a frame.
layout(local_size_x = TR_LOCAL_SIZE) in;
layout(std430, binding = TR_SSBO_MESH_POSITIONS) readonly buffer MeshPositions { float pos[]; };
layout(std430, binding = TR_SSBO_MESH_NORMALS) readonly buffer MeshNormals { float nrm[]; };
layout(std430, binding = TR_SSBO_SURFACE_INDICES) readonly buffer SurfaceIndices { uint tri[]; };
layout(location = TR_LOC_PATCH_COUNT) uniform uint u_patches;
vec3 mesh_pos(uint v) { return vec3(pos[3u * v], pos[3u * v + 1u], pos[3u * v + 2u]); }
vec3 mesh_nrm(uint v) { return vec3(nrm[3u * v], nrm[3u * v + 1u], nrm[3u * v + 2u]); }
void main() {
  uint i = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
  if (i >= u_patches) return;
  uint v1 = tri[3u * i], v2 = tri[3u * i + 1u], v3 = tri[3u * i + 2u];
  bool keep = tess_override() > 0.0;  // a fixed level: surface.tesc.glsl culls nothing
  if (!keep) {
    vec3 p1 = exaggerate_position(mesh_pos(v1)), p2 = exaggerate_position(mesh_pos(v2));
    vec3 p3 = exaggerate_position(mesh_pos(v3));
    vec3 n1 = exaggerate_normal(mesh_nrm(v1)), n2 = exaggerate_normal(mesh_nrm(v2)), n3 = exaggerate_normal(mesh_nrm(v3));
    vec3 b[10];
    b[0] = p1, b[1] = p2, b[2] = p3;
    b[3] = edge_point(p1, p2, n1), b[4] = edge_point(p2, p1, n2), b[5] = edge_point(p2, p3, n2);
    b[6] = edge_point(p3, p2, n3), b[7] = edge_point(p3, p1, n3), b[8] = edge_point(p1, p3, n1);
    vec3 e = (b[3] + b[4] + b[5] + b[6] + b[7] + b[8]) / 6.0;
    b[9] = e + (e - (p1 + p2 + p3) / 3.0) / 2.0;
    vec3 fn = cross(p2 - p1, p3 - p1);
    fn = length(fn) > 0.0 ? normalize(fn) : vec3(0.0, 0.0, 1.0);
    vec3 n[6] = vec3[6](n1, n2, n3, mid_normal(p1, p2, n1, n2, fn), mid_normal(p2, p3, n2, n3, fn),
                        mid_normal(p3, p1, n3, n1, fn));
    bvec4 all_out = bvec4(true);
    bool all_behind = true;
    for (int k = 0; k < 10; ++k) {
      vec4 c = u_view_proj * vec4(b[k], 1.0);
      float m = 1e-4 * abs(c.w) + 1e-6;
      all_out = bvec4(all_out.x && c.x < -c.w - m, all_out.y && c.x > c.w + m, all_out.z && c.y < -c.w - m,
                      all_out.w && c.y > c.w + m);
      all_behind = all_behind && c.w < -m;
    }
    bool all_toward = true;
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 10; ++k) {
        vec3 towards = to_eye(b[k]);
        all_toward = all_toward && dot(n[j], towards) > 1e-4 * length(n[j]) * length(towards);
      }
    // A coarse patch (levels of detail) faces by its geometry (surface.frag.glsl).
    vec2 e1 = p2.xy - p1.xy, e2 = p3.xy - p2.xy, e3 = p1.xy - p3.xy;
    if (u_lod.x > 0.0 && max(dot(e1, e1), max(dot(e2, e2), dot(e3, e3))) > u_lod.x) {
      bool all_away;
      geometric_facing(b, all_toward, all_away);
    }
    keep = !(any(all_out) || all_behind || all_toward);
  }
  if (keep) list_patch(v1, v2, v3);
}
