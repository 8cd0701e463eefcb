// TFT and AFT: the PN surface, toward-facing fragments to colour and toward depth, away-
// facing fragments to the away depth.
#include "passes.hpp"

namespace renderer::passes {

TowardPass::TowardPass(const SceneGpu& scene)
    : PassBase(TFT), s_(scene), fbo_(make_framebuffer(&scene.surface_colour, &scene.toward_depth)) {}

void TowardPass::execute(const FrameInputs&) {
  const float zero4[4] = {0, 0, 0, 0}, far_depth = s_.clear_depth();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero4);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  s_.depth_state();
  s_.draw_surface(0);
}

AwayPass::AwayPass(const SceneGpu& scene, bool enabled)
    : PassBase(AFT), s_(scene), enabled_(enabled), fbo_(make_framebuffer(nullptr, &scene.away_depth)) {}

void AwayPass::execute(const FrameInputs&) {
  const float far_depth = s_.clear_depth();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_depth);
  if (!enabled_) return;
  s_.depth_state();
  s_.draw_surface(1);
}

}  // namespace renderer::passes
