// SIL and LAY: full-screen passes over the other passes' images.
#include <algorithm>

#include "passes.hpp"
#include "renderer/gl_contract.hpp"
#include "renderer/programs.hpp"

namespace renderer::passes {

SilhouettePass::SilhouettePass(const SceneGpu& scene, bool enabled)
    : PassBase(SIL),
      s_(scene),
      enabled_(enabled),
      mask_(make_texture(GL_R8, scene.width, scene.height)),
      fbo_(make_framebuffer(&mask_, nullptr)),
      prog_(build_program(ProgramId::Silhouette)) {}

void SilhouettePass::draw() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glUseProgram(prog_.id());
  glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
  glBindTextureUnit(TR_TEX_AWAY_DEPTH, s_.away_depth.id());
  glBindVertexArray(s_.empty_vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

void SilhouettePass::execute(const FrameInputs&) {
  const float zero4[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero4);
  if (!enabled_) return;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glDisable(GL_DEPTH_TEST);
  draw();
}

void SilhouettePass::warm_up_timer() const {
  GlObject q(GlKind::Query, GL_TIME_ELAPSED);
  const float zero4[4] = {0, 0, 0, 0};
  glBeginQuery(GL_TIME_ELAPSED, q.id());
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero4);
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, s_.ubo.id());
  draw();
  glEndQuery(GL_TIME_ELAPSED);
  GLuint64 ns = 0;
  glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
}

CompositePass::CompositePass(const SceneGpu& scene, const Layers& layers, const Style& style,
                             const CreasePass& creases, const PelPass& pels, const SilhouettePass& silhouettes)
    : PassBase(LAY),
      s_(scene),
      layers_(layers),
      style_(style),
      creases_(creases),
      pels_(pels),
      silhouettes_(silhouettes),
      colour_(make_texture(GL_RGBA8, scene.width, scene.height)),
      fbo_(make_framebuffer(&colour_, nullptr)),
      prog_(build_program(ProgramId::Composite)) {}

void CompositePass::execute(const FrameInputs&) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glDisable(GL_DEPTH_TEST);
  const GLuint p = prog_.id();
  glUseProgram(p);
  glProgramUniform4i(p, TR_LOC_LAYERS, layers_.shaded, layers_.mask, layers_.creases, layers_.silhouettes);
  glProgramUniform3fv(p, TR_LOC_BACKGROUND, 1, style_.background.data());
  glProgramUniform3fv(p, TR_LOC_MASK_COLOUR, 1, style_.mask.data());
  glProgramUniform3fv(p, TR_LOC_CREASE_COLOUR, 1, style_.crease_colour.data());
  glProgramUniform3fv(p, TR_LOC_SILHOUETTE_COLOUR, 1, style_.silhouette_colour.data());
  glProgramUniform1i(p, TR_LOC_SILHOUETTE_WIDTH, std::max(1, style_.silhouette_width));
  glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
  glBindTextureUnit(TR_TEX_SURFACE_COLOUR, s_.surface_colour.id());
  glBindTextureUnit(TR_TEX_CREASE_COLOUR, creases_.colour().id());
  glBindTextureUnit(TR_TEX_CREASE_DEPTH, creases_.depth().id());
  glBindTextureUnit(TR_TEX_SILHOUETTE, silhouettes_.mask().id());
  glBindTextureUnit(TR_TEX_PEL_COLOUR, pels_.colour().id());
  glBindTextureUnit(TR_TEX_PEL_DEPTH, pels_.depth().id());
  glProgramUniform3fv(p, TR_LOC_PEL_COLOUR, 1, style_.pel_colour.data());
  glProgramUniform1i(p, TR_LOC_PELS, pels_.active() ? 1 : 0);
  glBindVertexArray(s_.empty_vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

}  // namespace renderer::passes
