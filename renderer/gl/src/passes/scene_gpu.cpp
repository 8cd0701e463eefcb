#include <chrono>
#include <vector>

#include "passes.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"
#include "terrain/error.hpp"

namespace renderer::passes {

SceneGpu::SceneGpu(const terrain::GridMesh& mesh, int w, int h, bool rev, bool normals,
                   bool all_patches, bool resident)
    : width(w), height(h), reversed(rev), topo(mesh.topo) {
  // Positions and normals in two buffers (the whole mesh's, or room for one vertex until
  // set_lod_mesh), faces as patches of 3.
  vertex_capacity = resident ? mesh.n_vertices() : 1;
  pos_buf = make_buffer(vertex_capacity * sizeof(Eigen::Vector3f),
                        resident ? mesh.positions.data() : nullptr,
                        resident ? 0 : GL_DYNAMIC_STORAGE_BIT);
  nrm_buf =
      make_buffer(vertex_capacity * sizeof(Eigen::Vector3f),
                  resident ? mesh.normals.data() : nullptr, resident ? 0 : GL_DYNAMIC_STORAGE_BIT);
  // The faces drawn: every face of the grid but those outside the data (GridMesh::face_kept).
  const std::vector<std::uint32_t> faces =
      all_patches ? mesh.kept_faces() : std::vector<std::uint32_t>{};
  std::vector<std::uint32_t> idx(all_patches ? faces.size() * 3 : 3);
  for (std::size_t j = 0; j < faces.size(); ++j) {
    const auto t = mesh.topo.face(faces[j]);
    std::copy(t.begin(), t.end(), idx.begin() + long(3 * j));
  }
  index_buf =
      make_buffer(std::max<std::size_t>(idx.size(), 3) * 4, idx.data(), GL_DYNAMIC_STORAGE_BIT);
  n_patches = patch_capacity = n_away_patches = faces.size();
  vao = GlObject(GlKind::VertexArray);
  for (const auto& [a, buf] : {std::pair<GLuint, const GlObject*>{TR_ATTR_POSITION, &pos_buf},
                               {TR_ATTR_NORMAL, &nrm_buf}}) {
    glVertexArrayVertexBuffer(vao.id(), a, buf->id(), 0, sizeof(Eigen::Vector3f));
    glVertexArrayAttribFormat(vao.id(), a, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao.id(), a, a);
    glEnableVertexArrayAttrib(vao.id(), a);
  }
  glVertexArrayElementBuffer(vao.id(), index_buf.id());
  empty_vao = GlObject(GlKind::VertexArray);
  ubo = make_buffer(sizeof(FrameBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
  surface_prog = build_program(ProgramId::Surface);
  surface_colour = make_texture(GL_RGBA8, width, height);
  toward_depth = make_texture(GL_DEPTH_COMPONENT32F, width, height);
  away_depth = make_texture(GL_DEPTH_COMPONENT32F, width, height);
  if (normals) surface_normal = make_texture(GL_RGBA32F, width, height);
  tile_rects_buf = make_buffer(16 + 16 * tile_count(), nullptr, GL_DYNAMIC_STORAGE_BIT);
  tile_rects_prog = build_program(ProgramId::TileRects);
  away_tiles = make_tile_texture();
  glClearTexImage(away_tiles.id(), 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
}

GlObject SceneGpu::make_tile_texture() const { return make_texture(GL_R8, tiles_x(), tiles_y()); }

void SceneGpu::draw_near_tiles(const GlObject& marks, int reach_x, int reach_y,
                               const GlObject& program) const {
  const GLuint header[4] = {0, 1, 0, 0};
  glNamedBufferSubData(tile_rects_buf.id(), 0, sizeof header, header);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_TILE_RECTS, tile_rects_buf.id());
  glBindTextureUnit(TR_TEX_TILE_MARKS, marks.id());
  glBindTextureUnit(TR_TEX_TOWARD_DEPTH, toward_depth.id());
  glUseProgram(tile_rects_prog.id());
  glProgramUniform2i(tile_rects_prog.id(), TR_LOC_TILE_REACH, reach_x, reach_y);
  glDispatchCompute(dispatch_groups_x(tile_count()), dispatch_groups_y(tile_count()), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  glUseProgram(program.id());
  glBindVertexArray(empty_vao.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, tile_rects_buf.id());
  glDrawArraysIndirect(GL_TRIANGLES, nullptr);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

void SceneGpu::depth_state() const {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(reversed ? GL_GREATER : GL_LESS);
  glDepthMask(GL_TRUE);
}

void SceneGpu::set_patches(const std::vector<std::uint32_t>& indices, std::size_t may_face_away) {
  if (indices.size() > 3 * topo.n_faces())
    throw terrain::Error("internal: more patches than the mesh's faces");
  n_patches = indices.size() / 3;
  n_away_patches = std::min(n_patches, may_face_away);
  if (n_patches >
      patch_capacity) {  // a quarter more room, so that a moving view seldom grows it again
    patch_capacity = std::min(topo.n_faces(), n_patches + n_patches / 4);
    index_buf = make_buffer(3 * patch_capacity * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    glVertexArrayElementBuffer(vao.id(), index_buf.id());
  }
  glNamedBufferSubData(index_buf.id(), 0, GLsizeiptr(indices.size() * 4), indices.data());
}

void SceneGpu::set_lod_mesh(const LodMesh& m, const terrain::GridMesh& mesh) {
  const std::size_t n = m.vertices.size();
  if (n > vertex_capacity) {  // a quarter more room, as set_patches
    vertex_capacity = n + n / 4;
    pos_buf =
        make_buffer(vertex_capacity * sizeof(Eigen::Vector3f), nullptr, GL_DYNAMIC_STORAGE_BIT);
    nrm_buf =
        make_buffer(vertex_capacity * sizeof(Eigen::Vector3f), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glVertexArrayVertexBuffer(vao.id(), TR_ATTR_POSITION, pos_buf.id(), 0, sizeof(Eigen::Vector3f));
    glVertexArrayVertexBuffer(vao.id(), TR_ATTR_NORMAL, nrm_buf.id(), 0, sizeof(Eigen::Vector3f));
  }
  std::vector<Eigen::Vector3f> gathered(n);
  for (const auto& [buf, source] :
       {std::pair{&pos_buf, &mesh.positions}, std::pair{&nrm_buf, &mesh.normals}}) {
    for (std::size_t i = 0; i < n; ++i) gathered[i] = (*source)[m.vertices[i]];
    glNamedBufferSubData(buf->id(), 0, GLsizeiptr(n * sizeof(Eigen::Vector3f)), gathered.data());
  }
  set_patches(m.patches, m.may_face_away);
}

void SceneGpu::draw_surface(int mode) const { draw_patches(surface_prog, mode); }

// Patches per draw call: kPatchesPerDraw (passes.hpp).

void SceneGpu::draw_patches(const GlObject& program, int mode) const {
  glUseProgram(program.id());
  glProgramUniform1i(program.id(), TR_LOC_SURFACE_MODE, mode);
  glBindVertexArray(vao.id());
  glPatchParameteri(GL_PATCH_VERTICES, 3);
  const std::size_t n = n_patches;
  std::vector<GLsizei> counts;
  std::vector<const void*> offsets;
  for (std::size_t first = 0; first < n; first += kPatchesPerDraw) {
    counts.push_back(GLsizei(3 * std::min(kPatchesPerDraw, n - first)));
    offsets.push_back(reinterpret_cast<const void*>(3 * first * sizeof(std::uint32_t)));
  }
  glMultiDrawElements(GL_PATCHES, counts.data(), GL_UNSIGNED_INT, offsets.data(),
                      GLsizei(counts.size()));
}

void SceneGpu::draw_patch_list(const GlObject& program, int mode, const GlObject& indices,
                               const GlObject& draws, std::size_t n_draws) const {
  glUseProgram(program.id());
  glProgramUniform1i(program.id(), TR_LOC_SURFACE_MODE, mode);
  glBindVertexArray(vao.id());
  glVertexArrayElementBuffer(vao.id(), indices.id());
  glPatchParameteri(GL_PATCH_VERTICES, 3);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, draws.id());
  glMultiDrawElementsIndirect(GL_PATCHES, GL_UNSIGNED_INT, nullptr, GLsizei(n_draws), 0);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glVertexArrayElementBuffer(vao.id(), index_buf.id());
}

GlObject make_framebuffer(const GlObject* colour, const GlObject* depth, const GlObject* colour1) {
  GlObject fbo(GlKind::Framebuffer);
  if (colour) glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, colour->id(), 0);
  if (depth) glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth->id(), 0);
  if (colour1 && colour) {
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT1, colour1->id(), 0);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(fbo.id(), 2, both);
  } else {
    glNamedFramebufferDrawBuffer(fbo.id(), colour ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  }
  if (glCheckNamedFramebufferStatus(fbo.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw terrain::Error("internal: incomplete framebuffer");
  return fbo;
}

LineTarget::LineTarget(const SceneGpu& scene, bool antialias)
    : colour(make_texture(GL_R8, scene.width, scene.height)),
      depth(antialias ? GlObject()
                      : make_texture(GL_DEPTH_COMPONENT32F, scene.width, scene.height)),
      fbo(make_framebuffer(&colour, antialias ? nullptr : &depth)),
      antialias(antialias) {}

void LineTarget::clear(const SceneGpu& scene) const {
  const float zero4[4] = {0, 0, 0, 0}, far_depth = scene.clear_depth();
  glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, zero4);
  if (!antialias) glClearNamedFramebufferfv(fbo.id(), GL_DEPTH, 0, &far_depth);
}

void LineTarget::draw_indirect(const SceneGpu& scene, const GlObject& program,
                               const GlObject& command) const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  if (antialias) {
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendEquation(GL_MAX);
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, scene.toward_depth.id());
  } else {
    scene.depth_state();
  }
  glUseProgram(program.id());
  glBindVertexArray(scene.empty_vao.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, command.id());
  glDrawArraysIndirect(GL_TRIANGLES, nullptr);
  glDisable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
}

std::size_t indirect_segments(const GlObject& command) {
  std::uint32_t cmd[4] = {};
  glGetNamedBufferSubData(command.id(), 0, sizeof cmd, cmd);
  return cmd[0] / 6;
}

void PassBase::run(const FrameInputs& in, FrameTimings& t) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  glBeginQuery(GL_TIME_ELAPSED, query_.id());
  execute(in);
  glEndQuery(GL_TIME_ELAPSED);
  glFinish();
  t.wall_ms[id_] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void PassBase::read_timer(FrameTimings& t) const {
  GLuint64 ns = 0;
  glGetQueryObjectui64v(query_.id(), GL_QUERY_RESULT, &ns);
  t.gpu_ms[id_] = double(ns) * 1e-6;
}

}  // namespace renderer::passes
