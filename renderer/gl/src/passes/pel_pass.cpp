// PEL: photic extremum lines (pel.hpp is the CPU reference). Four compute stages over the
// vertices (pel_fields.comp.glsl: f, grad f and m, s, c), one over the faces that appends
// the zero-crossing segments and writes an indirect draw command (pel_extract.comp.glsl),
// with anti-aliased lines stages over the segments that smooth the lines and find their
// pieces and opacity (pel_pieces.comp.glsl); the segments are drawn like creases
// (pel.vert.glsl).
#include <algorithm>

#include "passes.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"

namespace renderer::passes {

PelPass::PelPass(const SceneGpu& scene, const terrain::GridMesh& mesh, bool enabled, double width,
                 bool antialias, double piece_min_m, int smooth)
    : PassBase(PEL),
      s_(scene),
      enabled_(enabled),
      width_(width),
      piece_min_m_(enabled && antialias ? std::max(0.0, piece_min_m) : 0.0),
      smooth_(enabled && antialias ? std::max(0, smooth) : 0),
      target_(scene, antialias) {
  if (enabled_) {
    corner_buf_ =
        make_buffer(mesh.n_faces() * sizeof(Eigen::Vector3f), mesh.voronoi.corner_areas.data(), 0);
    varea_buf_ =
        make_buffer(mesh.n_vertices() * sizeof(float), mesh.voronoi.vertex_areas.data(), 0);
    tangent_buf_ =
        make_buffer(mesh.n_vertices() * sizeof(Eigen::Vector3f), mesh.voronoi.tangents.data(), 0);
    field_buf_ = make_buffer(mesh.n_vertices() * 24, nullptr, 0);
    maxm_buf_ = make_buffer(4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    cmd_buf_ = make_buffer(28, nullptr, GL_DYNAMIC_STORAGE_BIT);  // draw command, pieces dispatch
    seg_buf_ = make_buffer(mesh.n_faces() * 32, nullptr, 0);      // two vec4 a segment
    field_prog_ = build_program(ProgramId::PelFields);
    extract_prog_ = build_program(ProgramId::PelExtract);
    draw_prog_ = build_program(ProgramId::PelDraw);
  }
  if (smooth_ > 0) smoothed_buf_ = make_buffer(mesh.n_faces() * 32, nullptr, 0);
  if (piece_min_m_ > 0 || smooth_ > 0) {
    face_seg_buf_ = make_buffer(mesh.n_faces() * 4, nullptr, 0);
    labels_buf_ = make_buffer(mesh.n_faces() * 4, nullptr, 0);
    sizes_buf_ = make_buffer(mesh.n_faces() * 4, nullptr, 0);
    pieces_prog_ = build_program(ProgramId::PelPieces);
    glProgramUniform2ui(pieces_prog_.id(), TR_LOC_PEL_GRID, GLuint(mesh.topo.rows),
                        GLuint(mesh.topo.cols));
    glProgramUniform1f(pieces_prog_.id(), TR_LOC_PIECE_MIN, float(piece_min_m_));
  }
}

void PelPass::execute(const FrameInputs& in) {
  target_.clear(s_);
  if (!enabled_) return;
  const std::uint32_t zero = 0, cmd[7] = {0, 1, 0, 0, 0, 1, 1};
  glNamedBufferSubData(maxm_buf_.id(), 0, 4, &zero);
  glNamedBufferSubData(cmd_buf_.id(), 0, sizeof cmd, cmd);
  const std::pair<GLuint, const GlObject*> bufs[] = {
      {TR_SSBO_MESH_POSITIONS, &s_.pos_buf}, {TR_SSBO_MESH_NORMALS, &s_.nrm_buf},
      {TR_SSBO_CORNER_AREAS, &corner_buf_},  {TR_SSBO_VERTEX_AREAS, &varea_buf_},
      {TR_SSBO_TANGENTS, &tangent_buf_},     {TR_SSBO_PEL_FIELDS, &field_buf_},
      {TR_SSBO_PEL_MAX_M, &maxm_buf_},       {TR_SSBO_PEL_COMMAND, &cmd_buf_},
      {TR_SSBO_PEL_SEGMENTS, &seg_buf_}};
  for (const auto& [binding, buf] : bufs)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buf->id());
  // The light of f: the headlight (towards the eye) or the frame's light, in the mesh frame.
  const Eigen::Vector3d light =
      in.frame.pel.headlight ? Eigen::Vector3d(-in.view.forward) : in.light;
  const std::size_t nv = s_.topo.n_vertices(), nf = s_.topo.n_faces();
  const auto rows = GLuint(s_.topo.rows), cols = GLuint(s_.topo.cols);
  const GLuint fp = field_prog_.id();
  glUseProgram(fp);
  glProgramUniform2ui(fp, TR_LOC_PEL_GRID, rows, cols);
  glProgramUniform3f(fp, TR_LOC_PEL_LIGHT, float(light.x()), float(light.y()), float(light.z()));
  for (int stage = 0; stage < 4; ++stage) {
    glProgramUniform1i(fp, TR_LOC_PEL_STAGE, stage);
    glDispatchCompute(dispatch_groups_x(nv), dispatch_groups_y(nv), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  const GLuint ep = extract_prog_.id();
  glUseProgram(ep);
  glProgramUniform2ui(ep, TR_LOC_PEL_GRID, rows, cols);
  glProgramUniform1f(ep, TR_LOC_PEL_TAU, float(in.frame.pel.threshold));
  glDispatchCompute(dispatch_groups_x(nf), dispatch_groups_y(nf), 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  if (piece_min_m_ > 0 || smooth_ > 0) pieces();
  glProgramUniform1f(draw_prog_.id(), TR_LOC_PEL_WIDTH, float(width_));
  target_.draw_indirect(s_, draw_prog_, cmd_buf_);
}

void PelPass::pieces() const {
  const GLuint none = TR_SEGMENT_NONE, root = TR_PIECE_ROOT, zero = 0;
  glClearNamedBufferData(face_seg_buf_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
  glClearNamedBufferData(labels_buf_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &root);
  glClearNamedBufferData(sizes_buf_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PEL_FACE_SEGMENTS, face_seg_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PIECE_LABELS, labels_buf_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PIECE_SIZES, sizes_buf_.id());
  if (smooth_ > 0)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_PEL_SMOOTHED, smoothed_buf_.id());
  const GLuint p = pieces_prog_.id();
  glUseProgram(p);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, cmd_buf_.id());
  auto stage = [p](int s) {
    glProgramUniform1i(p, TR_LOC_PIECE_STAGE, s);
    glDispatchComputeIndirect(16);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  };
  stage(0);  // the segment of each face
  for (int i = 0; i < smooth_; ++i) stage(4), stage(5);
  if (piece_min_m_ > 0)
    for (int s = 1; s <= 3; ++s) stage(s);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}

std::size_t PelPass::segments_drawn() const { return enabled_ ? indirect_segments(cmd_buf_) : 0; }

std::vector<float> PelPass::read_segments() const {
  const std::size_t n = segments_drawn();
  std::vector<float> raw(8 * n);
  if (n) glGetNamedBufferSubData(seg_buf_.id(), 0, GLsizeiptr(raw.size() * 4), raw.data());
  return raw;
}

}  // namespace renderer::passes
