// EDGE: object-space feature edges (McGuire & Hughes 2004; feature_edges.hpp is the CPU
// reference). The edge buffer and the edges of each vertex are built once; per frame, one
// compute dispatch classifies every edge and appends the drawn ones (edge_classify.comp.glsl,
// stage 0) and, for exact caps, an indirect dispatch over the drawn edges only finds their
// joins (stage 1). One indirect draw then draws them as quads (edge.vert.glsl) into the
// edge layer, which the composite hides behind the PN surface.
#include <cmath>
#include <numbers>

#include "passes.hpp"
#include "renderer/core/feature_edges.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"

namespace renderer::passes {

static_assert(kContourEdge == TR_EDGE_CONTOUR && kBoundaryEdge == TR_EDGE_BOUNDARY &&
              kCreaseEdge == TR_EDGE_CREASE && kFacingEye == TR_EDGE_FACING &&
              kVertexEdgeSlots == TR_EDGE_SLOTS && MeshEdge::kNoVertex == TR_EDGE_NONE);
static_assert(int(EdgeCaps::None) == TR_CAPS_NONE && int(EdgeCaps::Cheap) == TR_CAPS_CHEAP &&
              int(EdgeCaps::Exact) == TR_CAPS_EXACT);

EdgePass::EdgePass(const SceneGpu& scene, bool enabled, const Style& style)
    : PassBase(EDGE), s_(scene), enabled_(enabled), style_(style), target_(scene) {
  if (!enabled_) return;
  const std::vector<MeshEdge> edges = mesh_edges(scene.topo);
  n_edges_ = edges.size();
  static_assert(sizeof(MeshEdge) == 16);
  edge_buf_ = make_buffer(n_edges_ * sizeof(MeshEdge), edges.data(), 0);
  kinds_buf_ = make_buffer(n_edges_ * 4, nullptr, 0);
  if (style_.edge_caps == EdgeCaps::Exact) {
    const std::vector<std::uint32_t> slots = vertex_edges(edges, scene.topo.n_vertices());
    slots_buf_ = make_buffer(slots.size() * 4, slots.data(), 0);
  } else {
    slots_buf_ = make_buffer(4, nullptr, 0);  // bound, never read
  }
  cmd_buf_ =
      make_buffer(28, nullptr, GL_DYNAMIC_STORAGE_BIT);  // draw command, then dispatch command
  list_buf_ = make_buffer(n_edges_ * 16, nullptr, 0);
  classify_prog_ = build_program(ProgramId::EdgeClassify);
  draw_prog_ = build_program(ProgramId::EdgeDraw);
  const GLuint cp = classify_prog_.id(), dp = draw_prog_.id();
  glProgramUniform1ui(cp, TR_LOC_EDGE_MASK, style_.edge_kinds);
  glProgramUniform1ui(cp, TR_LOC_EDGE_COUNT, GLuint(n_edges_));
  glProgramUniform1f(cp, TR_LOC_EDGE_COS,
                     float(std::cos(style_.crease_angle * std::numbers::pi / 180.0)));
  glProgramUniform1i(cp, TR_LOC_EDGE_CAPS, int(style_.edge_caps));
  glProgramUniform1i(dp, TR_LOC_EDGE_CAPS, int(style_.edge_caps));
  glProgramUniform1f(dp, TR_LOC_EDGE_WIDTH, float(style_.edge_width));
}

void EdgePass::execute(const FrameInputs&) {
  target_.clear(s_);
  if (!enabled_) return;
  const std::uint32_t cmd[7] = {0, 1, 0, 0, 0, 1, 1};
  glNamedBufferSubData(cmd_buf_.id(), 0, sizeof cmd, cmd);
  const std::pair<GLuint, const GlObject*> bufs[] = {
      {TR_SSBO_MESH_POSITIONS, &s_.pos_buf}, {TR_SSBO_MESH_NORMALS, &s_.nrm_buf},
      {TR_SSBO_EDGES, &edge_buf_},           {TR_SSBO_EDGE_KINDS, &kinds_buf_},
      {TR_SSBO_VERTEX_EDGES, &slots_buf_},   {TR_SSBO_EDGE_COMMAND, &cmd_buf_},
      {TR_SSBO_EDGE_LIST, &list_buf_}};
  for (const auto& [binding, buf] : bufs)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buf->id());
  const GLuint cp = classify_prog_.id();
  glUseProgram(cp);
  glProgramUniform1i(cp, TR_LOC_EDGE_STAGE, 0);
  glDispatchCompute(dispatch_groups_x(n_edges_), dispatch_groups_y(n_edges_), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  if (style_.edge_caps == EdgeCaps::Exact) {
    glProgramUniform1i(cp, TR_LOC_EDGE_STAGE, 1);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, cmd_buf_.id());
    glDispatchComputeIndirect(16);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  target_.draw_indirect(s_, draw_prog_, cmd_buf_);
}

std::size_t EdgePass::edges_drawn() const { return enabled_ ? indirect_segments(cmd_buf_) : 0; }

std::vector<std::uint32_t> EdgePass::read_kinds() const {
  std::vector<std::uint32_t> kinds(enabled_ ? n_edges_ : 0);
  if (!kinds.empty())
    glGetNamedBufferSubData(kinds_buf_.id(), 0, GLsizeiptr(kinds.size() * 4), kinds.data());
  return kinds;
}

std::vector<std::array<std::uint32_t, 4>> EdgePass::read_drawn() const {
  std::vector<std::array<std::uint32_t, 4>> drawn(edges_drawn());
  if (!drawn.empty())
    glGetNamedBufferSubData(list_buf_.id(), 0, GLsizeiptr(drawn.size() * 16), drawn.data());
  return drawn;
}

}  // namespace renderer::passes
