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
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"
#include "terrain/error.hpp"

namespace renderer::passes {

CreasePass::Level CreasePass::upload(const CreaseGeometry& creases,
                                     const SegmentChains& chains) const {
  Level l;
  l.n_vertices = creases.positions.size();
  l.n_segments = creases.n_segments();
  if (creases.share.size() != l.n_vertices ||
      (!creases.area.empty() && creases.area.size() != l.n_vertices))
    throw terrain::Error("crease geometry: one share and one area per vertex expected");
  const bool area = !creases.area.empty();  // none: every vertex drains enough
  std::vector<float> cv(12 *
                        l.n_vertices);  // position, flow, normal, share, area (crease_data.glsl)
  for (std::size_t i = 0; i < l.n_vertices; ++i) {
    const auto& p = creases.positions[i];
    const auto& n = creases.normals[i];
    const float v[12] = {p.x(),
                         p.y(),
                         p.z(),
                         creases.flow[i],
                         n.x(),
                         n.y(),
                         n.z(),
                         creases.share[i],
                         area ? creases.area[i] : FLT_MAX,
                         0.0f,
                         0.0f,
                         0.0f};
    std::memcpy(&cv[12 * i], v, sizeof v);
  }
  l.cv = make_buffer(cv.size() * 4, cv.data(), 0);
  l.seg = make_buffer(creases.segments.size() * 4, creases.segments.data(), 0);
  std::vector<std::uint32_t> chain(2 * l.n_segments);
  for (std::size_t s = 0; s < l.n_segments; ++s)
    chain[2 * s] = chains.prev[s], chain[2 * s + 1] = chains.next[s];
  l.chain = make_buffer(chain.size() * 4, chain.data(), 0);
  return l;
}

CreasePass::CreasePass(const SceneGpu& scene, const CreaseGeometry* creases, bool enabled,
                       bool antialias, std::shared_ptr<const std::vector<CreaseLevel>> levels,
                       bool merged)
    : PassBase(DM),
      s_(scene),
      enabled_(enabled),
      antialias_(antialias),
      tiles_(scene.make_tile_texture()),
      target_(scene, antialias) {
  if (!creases || creases->n_segments() == 0) return;
  levels_.push_back(upload(*creases, segment_chains(*creases)));
  if (merged) {
    if (!levels)
      levels = std::make_shared<const std::vector<CreaseLevel>>(coarser_crease_levels(*creases));
    for (const CreaseLevel& l : *levels) {
      levels_.push_back(upload(l.geometry, l.chains));
      errors_.push_back(l.error_metres);
    }
  }
  const std::size_t nv = levels_[0].n_vertices, ns = levels_[0].n_segments;
  score_buf_ = make_buffer(nv * 4, nullptr, 0);
  opacity_buf_ = make_buffer(ns * 4, nullptr, 0);
  selected_buf_ = make_buffer(ns * 4, nullptr, 0);
  cmd_buf_ = make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
  score_prog_ = build_program(ProgramId::CreaseScore);
  bridge_prog_ = build_program(ProgramId::CreaseBridge);
  select_prog_ = build_program(ProgramId::CreaseSelect);
  draw_prog_ = build_program(ProgramId::CreaseDraw);
  if (antialias_) {
    static_assert(sizeof(SegmentSamples) == 24, "std430 layout of crease_samples.glsl");
    samples_buf_ = make_buffer(ns * sizeof(SegmentSamples), nullptr, 0);
    visibility_prog_ = build_program(ProgramId::CreaseVisibility);
  }
}

void CreasePass::execute(const FrameInputs&) {
  target_.clear(s_);
  glClearTexImage(tiles_.id(), 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
  if (!active()) return;
  const Level& l = levels_[std::size_t(level_)];
  const std::size_t nv = l.n_vertices, ns = l.n_segments;
  const std::uint32_t cmd[4] = {0, 1, 0, 0};
  glNamedBufferSubData(cmd_buf_.id(), 0, sizeof cmd, cmd);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_VERTICES, l.cv.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SEGMENTS, l.seg.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_CHAINS, l.chain.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SCORES, score_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_OPACITY, opacity_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_COMMAND, cmd_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SELECTED, selected_buf_.id());
  glUseProgram(score_prog_.id());
  glDispatchCompute(dispatch_groups_x(nv), dispatch_groups_y(nv), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(bridge_prog_.id());
  glDispatchCompute(dispatch_groups_x(ns), dispatch_groups_y(ns), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(select_prog_.id());
  glDispatchCompute(dispatch_groups_x(ns), dispatch_groups_y(ns), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  if (antialias_) {
    glClearNamedBufferSubData(samples_buf_.id(), GL_R32UI, 0,
                              GLsizeiptr(ns * sizeof(SegmentSamples)), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SAMPLES, samples_buf_.id());
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, s_.toward_depth.id());
    glUseProgram(visibility_prog_.id());
    for (int stage = 0; stage < 3; ++stage) {
      glProgramUniform1i(visibility_prog_.id(), TR_LOC_CREASE_STAGE, stage);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      glDispatchCompute(dispatch_groups_x(ns), dispatch_groups_y(ns), 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  glBindImageTexture(TR_IMG_CREASE_TILES, tiles_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R8);
  target_.draw_indirect(s_, draw_prog_, cmd_buf_);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

std::vector<SegmentSamples> CreasePass::read_samples() const {
  std::vector<SegmentSamples> m;
  if (!active() || !antialias_) return m;
  m.resize(n_segments());
  glGetNamedBufferSubData(samples_buf_.id(), 0, GLsizeiptr(m.size() * sizeof(SegmentSamples)),
                          m.data());
  return m;
}

std::size_t CreasePass::segments_drawn() const {
  return active() ? indirect_segments(cmd_buf_) : 0;
}

}  // namespace renderer::passes
