// TFT and AFT: the PN surface, toward-facing fragments to colour and toward depth, away-
// facing fragments to the away depth.
#include <algorithm>
#include <cstdint>

#include "passes.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"

namespace renderer::passes {

void PatchList::reset(const SceneGpu& s) {
  if (!indices.id() || s.patch_capacity > capacity) {
    capacity = std::max<std::size_t>(s.patch_capacity, 1);
    indices = make_buffer(16 + 12 * capacity, nullptr, GL_DYNAMIC_STORAGE_BIT);
    draws = make_buffer(20 * ((capacity + kPatchesPerDraw - 1) / kPatchesPerDraw), nullptr,
                        GL_DYNAMIC_STORAGE_BIT);
  }
  const GLuint zero = 0;
  glNamedBufferSubData(indices.id(), 0, 4, &zero);
  glClearNamedBufferData(draws.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_AWAY_PATCHES, indices.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_AWAY_DRAWS, draws.id());
}

void PatchList::draw(const SceneGpu& s, const GlObject& program, int mode) const {
  s.draw_patch_list(program, mode, indices, draws,
                    (s.n_patches + kPatchesPerDraw - 1) / kPatchesPerDraw);
}

TowardPass::TowardPass(const SceneGpu& scene, bool flat_patches, const Eigen::Vector4f& clear)
    : PassBase(TFT),
      s_(scene),
      flat_patches_(flat_patches),
      clear_(clear),
      fbo_(make_framebuffer(&scene.surface_colour, &scene.toward_depth,
                            scene.surface_normal.id() ? &scene.surface_normal : nullptr)) {
  if (!flat_patches_) return;
  split_prog_ = build_program(ProgramId::SurfaceSplit);
  flat_prog_ = build_program(ProgramId::SurfaceFlat);
}

void TowardPass::execute(const FrameInputs&) {
  const float zero4[4] = {0, 0, 0, 0}, far_depth = s_.clear_depth();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, clear_.data());
  if (s_.surface_normal.id()) glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 1, zero4);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  // The lists take 36 bytes a patch: a frame of more patches than kMaxSplitPatches (a large
  // mesh drawn whole, --lod-error 0) tessellates them all, as without the split, rather
  // than hold a gigabyte of lists (Logan 10 m whole: 28.6 M patches).
  if (!flat_patches_ || s_.n_patches > kMaxSplitPatches) {
    s_.depth_state();
    s_.draw_surface(0);
    return;
  }
  const std::size_t n = s_.n_patches;
  tess_.reset(s_);
  if (!flat_.id() || s_.patch_capacity > flat_capacity_) {
    flat_capacity_ = std::max<std::size_t>(s_.patch_capacity, 1);
    flat_ = make_buffer(40 + 24 * flat_capacity_, nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  // The two lists' draw commands: no index yet, one instance, the first index of each list.
  const GLuint commands[10] = {0, 1, 10, 0, 0, 0, 1, GLuint(10 + 3 * n), 0, 0};
  glNamedBufferSubData(flat_.id(), 0, sizeof commands, commands);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_MESH_POSITIONS, s_.pos_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_SURFACE_INDICES, s_.index_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_FLAT_PATCHES, flat_.id());
  glUseProgram(split_prog_.id());
  glProgramUniform1ui(split_prog_.id(), TR_LOC_PATCH_COUNT, GLuint(n));
  glDispatchCompute(dispatch_groups_x(n), dispatch_groups_y(n), 1);
  glMemoryBarrier(GL_ELEMENT_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  s_.depth_state();
  tess_.draw(s_, s_.surface_prog, 0);
  glUseProgram(flat_prog_.id());
  glProgramUniform1i(flat_prog_.id(), TR_LOC_SURFACE_MODE, 0);
  glBindVertexArray(s_.vao.id());
  glVertexArrayElementBuffer(s_.vao.id(), flat_.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, flat_.id());
  for (const int coarse : {0, 1}) {
    glProgramUniform1f(flat_prog_.id(), TR_LOC_FLAT_COARSE, float(coarse));
    glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                           reinterpret_cast<const void*>(std::uintptr_t(20 * coarse)));
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glVertexArrayElementBuffer(s_.vao.id(), s_.index_buf.id());
}

AwayPass::AwayPass(const SceneGpu& scene, bool enabled)
    : PassBase(AFT),
      s_(scene),
      enabled_(enabled),
      fbo_(make_framebuffer(nullptr, &scene.away_depth)) {
  if (!enabled_) return;
  cull_prog_ = build_program(ProgramId::SurfaceCull);
  prog_ = build_program(ProgramId::SurfaceAway);
}

void AwayPass::execute(const FrameInputs&) {
  const float far_depth = s_.clear_depth();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  glClearTexImage(s_.away_tiles.id(), 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
  if (!enabled_) return;
  // The patches that may face away in view (all threads), then only those drawn: the
  // tessellation control stage that culls the others runs on one thread in llvmpipe. The
  // patches of blocks that face the eye throughout come last and are not looked at
  // (SceneGpu::n_away_patches).
  const std::size_t n = s_.n_away_patches;
  patches_.reset(s_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_MESH_POSITIONS, s_.pos_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_MESH_NORMALS, s_.nrm_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_SURFACE_INDICES, s_.index_buf.id());
  glUseProgram(cull_prog_.id());
  glProgramUniform1ui(cull_prog_.id(), TR_LOC_PATCH_COUNT, GLuint(n));
  glDispatchCompute(dispatch_groups_x(n), dispatch_groups_y(n), 1);
  glMemoryBarrier(GL_ELEMENT_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  s_.depth_state();
  glBindImageTexture(TR_IMG_AWAY_TILES, s_.away_tiles.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
  patches_.draw(s_, prog_, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

}  // namespace renderer::passes
