// TFT and AFT: the PN surface, toward-facing fragments to colour and toward depth, away-
// facing fragments to the away depth.
#include <algorithm>

#include "passes.hpp"
#include "renderer/gl_contract.hpp"
#include "renderer/programs.hpp"

namespace renderer::passes {

TowardPass::TowardPass(const SceneGpu& scene)
    : PassBase(TFT),
      s_(scene),
      fbo_(make_framebuffer(&scene.surface_colour, &scene.toward_depth,
                            scene.surface_normal.id() ? &scene.surface_normal : nullptr)) {}

void TowardPass::execute(const FrameInputs&) {
  const float zero4[4] = {0, 0, 0, 0}, far_depth = s_.clear_depth();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero4);
  if (s_.surface_normal.id()) glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 1, zero4);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  s_.depth_state();
  s_.draw_surface(0);
}

AwayPass::AwayPass(const SceneGpu& scene, bool enabled)
    : PassBase(AFT), s_(scene), enabled_(enabled), fbo_(make_framebuffer(nullptr, &scene.away_depth)) {
  if (!enabled_) return;
  cull_prog_ = build_program(ProgramId::SurfaceCull);
}

void AwayPass::execute(const FrameInputs&) {
  const float far_depth = s_.clear_depth();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  if (!enabled_) return;
  // The patches that may face away in view (all threads), then only those drawn: the
  // tessellation control stage that culls the others runs on one thread in llvmpipe.
  const std::size_t n = s_.n_patches, n_draws = (n + kPatchesPerDraw - 1) / kPatchesPerDraw;
  if (!patches_.id() || s_.patch_capacity > capacity_) {
    capacity_ = s_.patch_capacity;
    patches_ = make_buffer(16 + 12 * std::max<std::size_t>(capacity_, 1), nullptr, GL_DYNAMIC_STORAGE_BIT);
    draws_ = make_buffer(20 * std::max<std::size_t>((capacity_ + kPatchesPerDraw - 1) / kPatchesPerDraw, 1), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
  }
  const GLuint zero = 0;
  glNamedBufferSubData(patches_.id(), 0, 4, &zero);
  glClearNamedBufferData(draws_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_MESH_POSITIONS, s_.pos_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_MESH_NORMALS, s_.nrm_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_SURFACE_INDICES, s_.index_buf.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_AWAY_PATCHES, patches_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_AWAY_DRAWS, draws_.id());
  glUseProgram(cull_prog_.id());
  glProgramUniform1ui(cull_prog_.id(), TR_LOC_PATCH_COUNT, GLuint(n));
  glDispatchCompute(dispatch_groups_x(n), dispatch_groups_y(n), 1);
  glMemoryBarrier(GL_ELEMENT_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  s_.depth_state();
  s_.draw_patch_list(s_.surface_prog, 1, patches_, draws_, n_draws);
}

}  // namespace renderer::passes
