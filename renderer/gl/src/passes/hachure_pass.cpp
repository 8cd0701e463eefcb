// HACH: the hachures' field (hachure_field.comp.glsl), on demand after a frame: each pixel's
// fall line, slope, tone and height from TFT's depth and the normals it drew. The
// hachures are traced from it on the CPU (renderer/core/hachures.hpp, which holds the CPU
// reference of the field, renderer::hachure_field) and drawn over the frame.
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "passes.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"
#include "terrain/error.hpp"

namespace renderer::passes {

HachurePass::HachurePass(const SceneGpu& scene) : s_(scene) {}

HachureField HachurePass::field(const View& view, bool light_tone) {
  if (!s_.surface_normal.id())
    throw terrain::Error(
        "internal: the hachures' field needs a renderer made with the hachures layer");
  const int w = s_.width, h = s_.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  if (!prog_.id()) {
    prog_ = build_program(ProgramId::HachureField);
    buf_ = make_buffer(16 * n, nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  // The last frame's block is still in the scene's UBO (render() wrote it).
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, s_.ubo.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_HACHURE_FIELD, buf_.id());
  glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
  glBindTextureUnit(TR_TEX_SURFACE_NORMAL, s_.surface_normal.id());
  glUseProgram(prog_.id());
  const Eigen::Matrix4f inverse = view.view_projection().inverse().cast<float>();
  glProgramUniformMatrix4fv(prog_.id(), TR_LOC_HACHURE_INVERSE, 1, GL_FALSE, inverse.data());
  glProgramUniform1i(prog_.id(), TR_LOC_HACHURE_TONE, light_tone ? 1 : 0);
  glDispatchCompute(dispatch_groups_x(n), dispatch_groups_y(n), 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<Eigen::Vector4f> raw(n);
  glGetNamedBufferSubData(buf_.id(), 0, GLsizeiptr(16 * n), raw.data());
  HachureField f;
  f.width = w, f.height = h;
  f.fall.resize(n), f.slope.resize(n), f.tone.resize(n), f.elevation.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector4f& a = raw[i];  // fall angle, slope (-1: no surface), tone, height
    const bool terrain = a.y() >= 0.0f;
    f.fall[i] =
        a.x() < 3.5f ? Eigen::Vector2f(std::cos(a.x()), std::sin(a.x())) : Eigen::Vector2f::Zero();
    f.slope[i] = terrain ? a.y() : std::numeric_limits<float>::quiet_NaN();
    f.tone[i] = terrain ? a.z() : 0.0f;
    f.elevation[i] = terrain ? a.w() : 0.0f;
  }
  return f;
}

}  // namespace renderer::passes
