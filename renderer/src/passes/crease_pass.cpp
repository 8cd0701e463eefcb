// DM: Mower's drainage creases. A compute pass scores every crease vertex
// (crease_score.comp.glsl), a second gives every segment its opacity from the scores of
// its ends, bridging short gaps along its chain (crease_bridge.comp.glsl), a third keeps
// the segments of strokes long enough and writes an indirect draw command
// (crease_select.comp.glsl); with anti-aliased lines three more find which samples of
// them show, along their strokes (crease_visibility.comp.glsl); the segments are drawn as
// screen-space quads where they lie, at the depth of their ends lifted towards the eye
// (crease.vert.glsl).
#include <cfloat>
#include <cstring>

#include "passes.hpp"
#include "renderer/gl_contract.hpp"
#include "renderer/programs.hpp"
#include "terrain/error.hpp"

namespace renderer::passes {

CreasePass::CreasePass(const SceneGpu& scene, const CreaseGeometry* creases, bool enabled, bool antialias)
    : PassBase(DM), s_(scene), enabled_(enabled), antialias_(antialias), target_(scene, antialias) {
  if (creases && creases->n_segments() > 0) {
    n_vertices_ = creases->positions.size();
    n_segments_ = creases->n_segments();
    if (creases->share.size() != n_vertices_ || (!creases->area.empty() && creases->area.size() != n_vertices_))
      throw terrain::Error("crease geometry: one share and one area per vertex expected");
    const bool area = !creases->area.empty();  // none: every vertex drains enough
    std::vector<float> cv(12 * n_vertices_);  // position, flow, normal, share, area (crease_data.glsl)
    for (std::size_t i = 0; i < n_vertices_; ++i) {
      const auto& p = creases->positions[i];
      const auto& n = creases->normals[i];
      const float v[12] = {p.x(), p.y(), p.z(), creases->flow[i], n.x(),           n.y(),
                           n.z(), creases->share[i], area ? creases->area[i] : FLT_MAX, 0.0f, 0.0f, 0.0f};
      std::memcpy(&cv[12 * i], v, sizeof v);
    }
    cv_buf_ = make_buffer(cv.size() * 4, cv.data(), 0);
    seg_buf_ = make_buffer(creases->segments.size() * 4, creases->segments.data(), 0);
    const SegmentChains chains = segment_chains(*creases);
    std::vector<std::uint32_t> chain(2 * n_segments_);
    for (std::size_t s = 0; s < n_segments_; ++s) chain[2 * s] = chains.prev[s], chain[2 * s + 1] = chains.next[s];
    chain_buf_ = make_buffer(chain.size() * 4, chain.data(), 0);
    score_buf_ = make_buffer(n_vertices_ * 4, nullptr, 0);
    opacity_buf_ = make_buffer(n_segments_ * 4, nullptr, 0);
    selected_buf_ = make_buffer(n_segments_ * 4, nullptr, 0);
    cmd_buf_ = make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    score_prog_ = build_program(ProgramId::CreaseScore);
    bridge_prog_ = build_program(ProgramId::CreaseBridge);
    select_prog_ = build_program(ProgramId::CreaseSelect);
    draw_prog_ = build_program(ProgramId::CreaseDraw);
    if (antialias_) {
      static_assert(sizeof(SegmentSamples) == 24, "std430 layout of crease_samples.glsl");
      samples_buf_ = make_buffer(n_segments_ * sizeof(SegmentSamples), nullptr, 0);
      visibility_prog_ = build_program(ProgramId::CreaseVisibility);
    }
  }
}

void CreasePass::execute(const FrameInputs&) {
  target_.clear(s_);
  if (!active()) return;
  const std::uint32_t cmd[4] = {0, 1, 0, 0};
  glNamedBufferSubData(cmd_buf_.id(), 0, sizeof cmd, cmd);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_VERTICES, cv_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SEGMENTS, seg_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_CHAINS, chain_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SCORES, score_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_OPACITY, opacity_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_COMMAND, cmd_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SELECTED, selected_buf_.id());
  glUseProgram(score_prog_.id());
  glDispatchCompute(dispatch_groups_x(n_vertices_), dispatch_groups_y(n_vertices_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(bridge_prog_.id());
  glDispatchCompute(dispatch_groups_x(n_segments_), dispatch_groups_y(n_segments_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(select_prog_.id());
  glDispatchCompute(dispatch_groups_x(n_segments_), dispatch_groups_y(n_segments_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  if (antialias_) {
    glClearNamedBufferData(samples_buf_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SAMPLES, samples_buf_.id());
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
    glUseProgram(visibility_prog_.id());
    for (int stage = 0; stage < 3; ++stage) {
      glProgramUniform1i(visibility_prog_.id(), TR_LOC_CREASE_STAGE, stage);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      glDispatchCompute(dispatch_groups_x(n_segments_), dispatch_groups_y(n_segments_), 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  target_.draw_indirect(s_, draw_prog_, cmd_buf_);
}

std::vector<SegmentSamples> CreasePass::read_samples() const {
  std::vector<SegmentSamples> m;
  if (!active() || !antialias_) return m;
  m.resize(n_segments_);
  glGetNamedBufferSubData(samples_buf_.id(), 0, GLsizeiptr(m.size() * sizeof(SegmentSamples)), m.data());
  return m;
}

std::size_t CreasePass::segments_drawn() const {
  return active() ? indirect_segments(cmd_buf_) : 0;
}

}  // namespace renderer::passes
