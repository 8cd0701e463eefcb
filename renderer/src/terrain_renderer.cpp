#include "renderer/terrain_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "renderer/gl_contract.hpp"
#include "renderer/gl_objects.hpp"
#include "renderer/programs.hpp"
#include "renderer/shader.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"

namespace renderer {

namespace {

void set4(glsl::vec4& d, double a, double b, double c, double e) {
  d = {float(a), float(b), float(c), float(e)};
}

using Clock = std::chrono::steady_clock;

// Rows bottom-up (GL) to top-down, in place.
template <class T>
void flip_rows(std::vector<T>& v, int width, int height, int channels) {
  const std::size_t row = std::size_t(width) * std::size_t(channels);
  for (int r = 0; r < height / 2; ++r)
    std::swap_ranges(v.begin() + long(std::size_t(r) * row), v.begin() + long(std::size_t(r + 1) * row),
                     v.begin() + long(std::size_t(height - 1 - r) * row));
}


}  // namespace

struct TerrainRenderer::Impl {
  int width = 0, height = 0;
  Layers layers;
  Style style;
  bool reversed = true;
  Box box;
  Eigen::Vector3d origin;
  double far_default = 1, lift = 0;
  int max_level = 32;

  GlObject vao, pos_buf, nrm_buf, index_buf, ubo, empty_vao;
  terrain::GridTopology topo;  // the mesh's grid: faces are implicit (grid_mesh.hpp)

  bool has_creases = false;
  bool has_pels = false;
  GlObject corner_buf, varea_buf, tangent_buf, field_buf, maxm_buf, pel_cmd_buf, pel_seg_buf;
  GlObject pel_field_prog, pel_extract_prog, pel_draw_prog;
  GlObject pel_colour, pel_depth, pel_fbo;
  std::size_t n_crease_vertices = 0, n_segments = 0;
  GlObject cv_buf, seg_buf, score_buf, cmd_buf, selected_buf;

  GlObject surface_prog, score_prog, select_prog, crease_prog, sil_prog, lay_prog, capture_prog;

  GlObject tft_colour, toward_depth, away_depth, dm_colour, dm_depth, sil_tex, lay_colour;
  GlObject tft_fbo, aft_fbo, dm_fbo, sil_fbo, lay_fbo;
  GlObject queries[kPassCount];

  void attach(GlObject& fbo, GlObject* colour, GlObject* depth) {
    fbo = GlObject(GlKind::Framebuffer);
    if (colour) glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, colour->id(), 0);
    if (depth) glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth->id(), 0);
    glNamedFramebufferDrawBuffer(fbo.id(), colour ? GL_COLOR_ATTACHMENT0 : GL_NONE);
    if (glCheckNamedFramebufferStatus(fbo.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw terrain::Error("internal: incomplete framebuffer");
  }

  float clear_depth() const { return reversed ? 0.0f : 1.0f; }
  void depth_state() const {
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(reversed ? GL_GREATER : GL_LESS);
    glDepthMask(GL_TRUE);
  }
  void draw_surface(int mode) {
    glUseProgram(surface_prog.id());
    glProgramUniform1i(surface_prog.id(), TR_LOC_SURFACE_MODE, mode);
    glBindVertexArray(vao.id());
    glPatchParameteri(GL_PATCH_VERTICES, 3);
    glDrawElements(GL_PATCHES, GLsizei(3 * topo.n_faces()), GL_UNSIGNED_INT, nullptr);
  }
};

TerrainRenderer::TerrainRenderer(const GlContext& context, const terrain::GridMesh& mesh, const CreaseGeometry* creases,
                                 int width, int height, const Layers& layers, const Style& style)
    : impl_(std::make_unique<Impl>()) {
  auto& m = *impl_;
  if (width < 16 || height < 16 || width > 16384 || height > 16384)
    throw terrain::Error("image size " + std::to_string(width) + " x " + std::to_string(height) +
                         " is outside 16 .. 16384 pixels");
  if (mesh.topo.rows < 2 || mesh.topo.cols < 2) throw terrain::Error("the mesh has no faces");
  if (mesh.n_faces() * 3 > std::size_t(std::numeric_limits<GLsizei>::max()))
    throw terrain::Error("the mesh has too many faces for one draw call");
  if (!(style.exaggeration > 0)) throw terrain::Error("vertical exaggeration must be > 0");
  m.width = width;
  m.height = height;
  m.layers = layers;
  m.topo = mesh.topo;
  if (layers.pels && mesh.voronoi.empty())
    throw terrain::Error("--layers pels needs the mesh's Voronoi weights: make it with denoise-normals "
                         "(--iterations 0 only adds them)");
  m.style = style;
  m.reversed = context.has_clip_control();
  m.origin = {mesh.geo.origin_x, mesh.geo.origin_y, mesh.geo.origin_z};
  m.far_default = default_far_distance(mesh);
  m.lift = style.crease_lift >= 0 ? style.crease_lift : 0.5 * std::min(mesh.geo.dx, mesh.geo.dy);
  GLint max_gen = 64;
  glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &max_gen);
  m.max_level = std::min(32, int(max_gen));

  m.box.lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  m.box.hi = -m.box.lo;
  for (std::size_t i = 0; i < mesh.n_vertices(); ++i) {
    Eigen::Vector3d p = mesh.positions[i].cast<double>();
    p.z() *= style.exaggeration;
    m.box.lo = m.box.lo.cwiseMin(p);
    m.box.hi = m.box.hi.cwiseMax(p);
  }

  // Surface geometry: positions and normals in two buffers, faces as patches of 3.
  m.pos_buf = make_buffer(mesh.n_vertices() * sizeof(Eigen::Vector3f), mesh.positions.data(), 0);
  m.nrm_buf = make_buffer(mesh.n_vertices() * sizeof(Eigen::Vector3f), mesh.normals.data(), 0);
  {
    std::vector<std::uint32_t> idx(mesh.n_faces() * 3);
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
      const auto t = mesh.topo.face(f);
      std::copy(t.begin(), t.end(), idx.begin() + long(3 * f));
    }
    m.index_buf = make_buffer(idx.size() * 4, idx.data(), 0);
  }
  m.vao = GlObject(GlKind::VertexArray);
  for (const auto& [a, buf] : {std::pair<GLuint, const GlObject*>{TR_ATTR_POSITION, &m.pos_buf}, {TR_ATTR_NORMAL, &m.nrm_buf}}) {
    glVertexArrayVertexBuffer(m.vao.id(), a, buf->id(), 0, sizeof(Eigen::Vector3f));
    glVertexArrayAttribFormat(m.vao.id(), a, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(m.vao.id(), a, a);
    glEnableVertexArrayAttrib(m.vao.id(), a);
  }
  glVertexArrayElementBuffer(m.vao.id(), m.index_buf.id());
  m.empty_vao = GlObject(GlKind::VertexArray);
  m.ubo = make_buffer(sizeof(FrameBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);

  if (creases && creases->n_segments() > 0) {
    m.has_creases = true;
    m.n_crease_vertices = creases->positions.size();
    m.n_segments = creases->n_segments();
    std::vector<float> cv(8 * m.n_crease_vertices);
    for (std::size_t i = 0; i < m.n_crease_vertices; ++i) {
      const auto& p = creases->positions[i];
      const auto& n = creases->normals[i];
      const float v[8] = {p.x(), p.y(), p.z(), creases->flow[i], n.x(), n.y(), n.z(), 0.0f};
      std::memcpy(&cv[8 * i], v, sizeof v);
    }
    m.cv_buf = make_buffer(cv.size() * 4, cv.data(), 0);
    m.seg_buf = make_buffer(creases->segments.size() * 4, creases->segments.data(), 0);
    m.score_buf = make_buffer(m.n_crease_vertices * 4, nullptr, 0);
    m.selected_buf = make_buffer(m.n_segments * 4, nullptr, 0);
    m.cmd_buf = make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
  }

  if (layers.pels) {
    m.has_pels = true;
    m.corner_buf = make_buffer(mesh.n_faces() * sizeof(Eigen::Vector3f), mesh.voronoi.corner_areas.data(), 0);
    m.varea_buf = make_buffer(mesh.n_vertices() * sizeof(float), mesh.voronoi.vertex_areas.data(), 0);
    m.tangent_buf = make_buffer(mesh.n_vertices() * sizeof(Eigen::Vector3f), mesh.voronoi.tangents.data(), 0);
    m.field_buf = make_buffer(mesh.n_vertices() * 24, nullptr, 0);
    m.maxm_buf = make_buffer(4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    m.pel_cmd_buf = make_buffer(16, nullptr, GL_DYNAMIC_STORAGE_BIT);
    m.pel_seg_buf = make_buffer(mesh.n_faces() * 48, nullptr, 0);
    m.pel_field_prog = build_program(ProgramId::PelFields);
    m.pel_extract_prog = build_program(ProgramId::PelExtract);
    m.pel_draw_prog = build_program(ProgramId::PelDraw);
  }

  // Programs.
  m.surface_prog = build_program(ProgramId::Surface);
  if (m.has_creases) {
    m.score_prog = build_program(ProgramId::CreaseScore);
    m.select_prog = build_program(ProgramId::CreaseSelect);
    m.crease_prog = build_program(ProgramId::CreaseDraw);
  }
  m.sil_prog = build_program(ProgramId::Silhouette);
  m.lay_prog = build_program(ProgramId::Composite);

  // Targets.
  m.tft_colour = make_texture(GL_RGBA8, width, height);
  m.toward_depth = make_texture(GL_DEPTH_COMPONENT32F, width, height);
  m.away_depth = make_texture(GL_DEPTH_COMPONENT32F, width, height);
  m.dm_colour = make_texture(GL_RGBA8, width, height);
  m.dm_depth = make_texture(GL_DEPTH_COMPONENT32F, width, height);
  m.sil_tex = make_texture(GL_R8, width, height);
  m.lay_colour = make_texture(GL_RGBA8, width, height);
  m.pel_colour = make_texture(GL_RGBA8, width, height);
  m.pel_depth = make_texture(GL_DEPTH_COMPONENT32F, width, height);
  m.attach(m.pel_fbo, &m.pel_colour, &m.pel_depth);
  m.attach(m.tft_fbo, &m.tft_colour, &m.toward_depth);
  m.attach(m.aft_fbo, nullptr, &m.away_depth);
  m.attach(m.dm_fbo, &m.dm_colour, &m.dm_depth);
  m.attach(m.sil_fbo, &m.sil_tex, nullptr);
  m.attach(m.lay_fbo, &m.lay_colour, nullptr);
  for (auto& q : m.queries) q = GlObject(GlKind::Query, GL_TIME_ELAPSED);
  if (m.reversed) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glViewport(0, 0, width, height);
  glDisable(GL_CULL_FACE);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  if (glGetError() != GL_NO_ERROR) throw terrain::Error("OpenGL error while setting up the renderer");
  // Mesa llvmpipe reports a meaningless time for the first GL_TIME_ELAPSED query of a
  // context that has drawn nothing yet: time one small draw first.
  {
    GlObject q(GlKind::Query, GL_TIME_ELAPSED);
    const float zero4[4] = {0, 0, 0, 0};
    glBeginQuery(GL_TIME_ELAPSED, q.id());
    glClearNamedFramebufferfv(m.sil_fbo.id(), GL_COLOR, 0, zero4);
    glBindFramebuffer(GL_FRAMEBUFFER, m.sil_fbo.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, m.ubo.id());
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, m.toward_depth.id());
    glBindTextureUnit(TR_TEX_AWAY_DEPTH, m.away_depth.id());
    glUseProgram(m.sil_prog.id());
    glBindVertexArray(m.empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
  }
}

TerrainRenderer::~TerrainRenderer() = default;

const Box& TerrainRenderer::box() const { return impl_->box; }
Eigen::Vector3d TerrainRenderer::origin() const { return impl_->origin; }

FrameResult TerrainRenderer::render(const FrameParams& frame) {
  auto& m = *impl_;
  if (!(frame.camera.fov > 0 && frame.camera.fov < 180)) throw terrain::Error("fov must be in (0, 180) degrees");
  FrameResult res;
  res.width = m.width;
  res.height = m.height;
  res.view = make_view(frame.camera, m.origin, m.box, m.width, m.height, m.reversed);
  const View& v = res.view;
  const Eigen::Vector3d light = terrain::light_direction(frame.light.azimuth, frame.light.altitude);
  const auto& sp = frame.score;

  FrameBlock fb{};
  const Eigen::Matrix4f vp = v.view_projection().cast<float>();
  std::memcpy(fb.u_view_proj.data(), vp.data(), sizeof fb.u_view_proj);  // column-major, as GLSL
  set4(fb.u_eye, v.eye.x(), v.eye.y(), v.eye.z(), m.style.exaggeration);
  set4(fb.u_light, light.x(), light.y(), light.z(), 0);
  set4(fb.u_viewport, m.width, m.height, m.style.pixels_per_edge, m.max_level);
  set4(fb.u_weights, sp.sw, sp.iw, sp.fw, sp.literal_divisor ? 3.0 : sp.sw + sp.iw + sp.fw);
  set4(fb.u_score, sp.min_score, sp.falloff, sp.far_distance > 0 ? sp.far_distance : m.far_default, m.lift);
  set4(fb.u_lines, m.style.crease_width, m.style.crease_width_max, 0, m.reversed ? 1 : 0);
  set4(fb.u_misc, v.near, double(m.n_segments), double(m.n_crease_vertices), 0);
  glNamedBufferSubData(m.ubo.id(), 0, sizeof fb, &fb);
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, m.ubo.id());

  const float zero4[4] = {0, 0, 0, 0};
  const float far_depth = m.clear_depth();
  const bool do_sil = m.layers.silhouettes;
  const bool do_dm = m.layers.creases && m.has_creases;

  auto timed = [&](int pass, auto&& body) {
    const auto t0 = Clock::now();
    glBeginQuery(GL_TIME_ELAPSED, m.queries[pass].id());
    body();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    res.timings.wall_ms[pass] = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  };
  glFinish();

  timed(TFT, [&] {
    glBindFramebuffer(GL_FRAMEBUFFER, m.tft_fbo.id());
    glClearNamedFramebufferfv(m.tft_fbo.id(), GL_COLOR, 0, zero4);
    glClearNamedFramebufferfv(m.tft_fbo.id(), GL_DEPTH, 0, &far_depth);
    m.depth_state();
    m.draw_surface(0);
  });
  timed(AFT, [&] {
    glBindFramebuffer(GL_FRAMEBUFFER, m.aft_fbo.id());
    glClearNamedFramebufferfv(m.aft_fbo.id(), GL_DEPTH, 0, &far_depth);
    if (do_sil) {
      m.depth_state();
      m.draw_surface(1);
    }
  });
  timed(DM, [&] {
    glClearNamedFramebufferfv(m.dm_fbo.id(), GL_COLOR, 0, zero4);
    glClearNamedFramebufferfv(m.dm_fbo.id(), GL_DEPTH, 0, &far_depth);
    if (!do_dm) return;
    const std::uint32_t cmd[4] = {0, 1, 0, 0};
    glNamedBufferSubData(m.cmd_buf.id(), 0, sizeof cmd, cmd);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_VERTICES, m.cv_buf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SEGMENTS, m.seg_buf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SCORES, m.score_buf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_COMMAND, m.cmd_buf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TR_SSBO_CREASE_SELECTED, m.selected_buf.id());
    glUseProgram(m.score_prog.id());
    glDispatchCompute(dispatch_groups_x(m.n_crease_vertices), dispatch_groups_y(m.n_crease_vertices), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(m.select_prog.id());
    glDispatchCompute(dispatch_groups_x(m.n_segments), dispatch_groups_y(m.n_segments), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, m.dm_fbo.id());
    m.depth_state();
    glUseProgram(m.crease_prog.id());
    glBindVertexArray(m.empty_vao.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m.cmd_buf.id());
    glDrawArraysIndirect(GL_TRIANGLES, nullptr);
  });
  timed(PEL, [&] {
    glClearNamedFramebufferfv(m.pel_fbo.id(), GL_COLOR, 0, zero4);
    glClearNamedFramebufferfv(m.pel_fbo.id(), GL_DEPTH, 0, &far_depth);
    if (!m.has_pels) return;
    const std::uint32_t zero = 0, cmd[4] = {0, 1, 0, 0};
    glNamedBufferSubData(m.maxm_buf.id(), 0, 4, &zero);
    glNamedBufferSubData(m.pel_cmd_buf.id(), 0, sizeof cmd, cmd);
    const std::pair<GLuint, const GlObject*> bufs[] = {
        {TR_SSBO_MESH_POSITIONS, &m.pos_buf},    {TR_SSBO_MESH_NORMALS, &m.nrm_buf},
        {TR_SSBO_CORNER_AREAS, &m.corner_buf},   {TR_SSBO_VERTEX_AREAS, &m.varea_buf},
        {TR_SSBO_TANGENTS, &m.tangent_buf},      {TR_SSBO_PEL_FIELDS, &m.field_buf},
        {TR_SSBO_PEL_MAX_M, &m.maxm_buf},        {TR_SSBO_PEL_COMMAND, &m.pel_cmd_buf},
        {TR_SSBO_PEL_SEGMENTS, &m.pel_seg_buf}};
    for (const auto& [binding, buf] : bufs) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buf->id());
    // The light of f: the headlight (towards the eye) or the frame's light, in the mesh frame.
    const Eigen::Vector3d pel_light = frame.pel.headlight ? Eigen::Vector3d(-v.forward) : light;
    const std::size_t nv = m.topo.n_vertices(), nf = m.topo.n_faces();
    const auto rows = GLuint(m.topo.rows), cols = GLuint(m.topo.cols);
    const GLuint fp = m.pel_field_prog.id();
    glUseProgram(fp);
    glProgramUniform2ui(fp, TR_LOC_PEL_GRID, rows, cols);
    glProgramUniform3f(fp, TR_LOC_PEL_LIGHT, float(pel_light.x()), float(pel_light.y()), float(pel_light.z()));
    for (int stage = 0; stage < 4; ++stage) {
      glProgramUniform1i(fp, TR_LOC_PEL_STAGE, stage);
      glDispatchCompute(dispatch_groups_x(nv), dispatch_groups_y(nv), 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    const GLuint ep = m.pel_extract_prog.id();
    glUseProgram(ep);
    glProgramUniform2ui(ep, TR_LOC_PEL_GRID, rows, cols);
    glProgramUniform1f(ep, TR_LOC_PEL_TAU, float(frame.pel.threshold));
    glDispatchCompute(dispatch_groups_x(nf), dispatch_groups_y(nf), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, m.pel_fbo.id());
    m.depth_state();
    glUseProgram(m.pel_draw_prog.id());
    glProgramUniform1f(m.pel_draw_prog.id(), TR_LOC_PEL_WIDTH, float(m.style.pel_width));
    glBindVertexArray(m.empty_vao.id());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m.pel_cmd_buf.id());
    glDrawArraysIndirect(GL_TRIANGLES, nullptr);
  });
  timed(SIL, [&] {
    glClearNamedFramebufferfv(m.sil_fbo.id(), GL_COLOR, 0, zero4);
    if (!do_sil) return;
    glBindFramebuffer(GL_FRAMEBUFFER, m.sil_fbo.id());
    glDisable(GL_DEPTH_TEST);
    glUseProgram(m.sil_prog.id());
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, m.toward_depth.id());
    glBindTextureUnit(TR_TEX_AWAY_DEPTH, m.away_depth.id());
    glBindVertexArray(m.empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  });
  timed(LAY, [&] {
    glBindFramebuffer(GL_FRAMEBUFFER, m.lay_fbo.id());
    glDisable(GL_DEPTH_TEST);
    const GLuint p = m.lay_prog.id();
    glUseProgram(p);
    glProgramUniform4i(p, TR_LOC_LAYERS, m.layers.shaded, m.layers.mask, m.layers.creases, m.layers.silhouettes);
    glProgramUniform3fv(p, TR_LOC_BACKGROUND, 1, m.style.background.data());
    glProgramUniform3fv(p, TR_LOC_MASK_COLOUR, 1, m.style.mask.data());
    glProgramUniform3fv(p, TR_LOC_CREASE_COLOUR, 1, m.style.crease_colour.data());
    glProgramUniform3fv(p, TR_LOC_SILHOUETTE_COLOUR, 1, m.style.silhouette_colour.data());
    glProgramUniform1i(p, TR_LOC_SILHOUETTE_WIDTH, std::max(1, m.style.silhouette_width));
    glBindTextureUnit(TR_TEX_TOWARD_DEPTH, m.toward_depth.id());
    glBindTextureUnit(TR_TEX_SURFACE_COLOUR, m.tft_colour.id());
    glBindTextureUnit(TR_TEX_CREASE_COLOUR, m.dm_colour.id());
    glBindTextureUnit(TR_TEX_CREASE_DEPTH, m.dm_depth.id());
    glBindTextureUnit(TR_TEX_SILHOUETTE, m.sil_tex.id());
    glBindTextureUnit(TR_TEX_PEL_COLOUR, m.pel_colour.id());
    glBindTextureUnit(TR_TEX_PEL_DEPTH, m.pel_depth.id());
    glProgramUniform3fv(p, TR_LOC_PEL_COLOUR, 1, m.style.pel_colour.data());
    glProgramUniform1i(p, TR_LOC_PELS, m.has_pels ? 1 : 0);
    glBindVertexArray(m.empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
  });

  for (int p = 0; p < kPassCount; ++p) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(m.queries[p].id(), GL_QUERY_RESULT, &ns);
    res.timings.gpu_ms[p] = double(ns) * 1e-6;
  }
  if (do_dm) {
    std::uint32_t cmd[4] = {};
    glGetNamedBufferSubData(m.cmd_buf.id(), 0, sizeof cmd, cmd);
    res.crease_segments = cmd[0] / 6;
  }
  if (m.has_pels) {
    std::uint32_t cmd[4] = {};
    glGetNamedBufferSubData(m.pel_cmd_buf.id(), 0, sizeof cmd, cmd);
    res.pel_segments = cmd[0] / 6;
  }
  res.rgba.resize(std::size_t(m.width) * std::size_t(m.height) * 4);
  glGetTextureImage(m.lay_colour.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(res.rgba.size()), res.rgba.data());
  flip_rows(res.rgba, m.width, m.height, 4);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw terrain::Error(fmt::format("OpenGL error 0x{:x} while rendering", err));
  return res;
}

FrameBuffers TerrainRenderer::read_buffers() const {
  const auto& m = *impl_;
  FrameBuffers b;
  const std::size_t n = std::size_t(m.width) * std::size_t(m.height);
  auto depth = [&](const GlObject& t, std::vector<float>& out) {
    out.resize(n);
    glGetTextureImage(t.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(n * 4), out.data());
    flip_rows(out, m.width, m.height, 1);
  };
  auto red = [&](const GlObject& t, std::vector<std::uint8_t>& out) {
    out.resize(n);
    glGetTextureImage(t.id(), 0, GL_RED, GL_UNSIGNED_BYTE, GLsizei(n), out.data());
    flip_rows(out, m.width, m.height, 1);
    for (auto& x : out) x = x > 0;
  };
  depth(m.toward_depth, b.toward_depth);
  depth(m.away_depth, b.away_depth);
  depth(m.dm_depth, b.crease_depth);
  red(m.sil_tex, b.silhouette);
  red(m.dm_colour, b.crease);
  return b;
}

std::vector<TerrainRenderer::PelSegmentOut> TerrainRenderer::read_pels() const {
  const auto& m = *impl_;
  if (!m.has_pels) return {};
  std::uint32_t cmd[4] = {};
  glGetNamedBufferSubData(m.pel_cmd_buf.id(), 0, sizeof cmd, cmd);
  const std::size_t n = cmd[0] / 6;
  std::vector<float> raw(12 * n);
  if (n) glGetNamedBufferSubData(m.pel_seg_buf.id(), 0, GLsizeiptr(raw.size() * 4), raw.data());
  std::vector<PelSegmentOut> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* r = &raw[12 * i];
    out[i].a = {r[0], r[1], r[2]};
    std::memcpy(&out[i].face, &r[3], 4);
    out[i].b = {r[4], r[5], r[6]};
  }
  return out;
}

std::vector<TerrainRenderer::PnSample> TerrainRenderer::capture_pn(const std::vector<std::uint32_t>& faces, int level) {
  auto& m = *impl_;
  if (level < 1 || level > m.max_level) throw terrain::Error("capture level out of range");
  if (!m.capture_prog.id())
    m.capture_prog = build_program(ProgramId::PnCapture);
  std::vector<std::uint32_t> idx;
  for (const auto f : faces) {
    if (f >= m.topo.n_faces()) throw terrain::Error("capture face out of range");
    const auto t = m.topo.face(f);
    idx.insert(idx.end(), t.begin(), t.end());
  }
  GlObject tmp_index = make_buffer(idx.size() * 4, idx.data(), 0);
  const std::size_t max_vertices = faces.size() * 3 * std::size_t(level + 2) * std::size_t(level + 2);
  GlObject out = make_buffer(max_vertices * sizeof(PnSample), nullptr, 0);

  FrameBlock fb{};
  const Eigen::Matrix4f id = Eigen::Matrix4f::Identity();
  std::memcpy(fb.u_view_proj.data(), id.data(), sizeof fb.u_view_proj);
  set4(fb.u_eye, 0, 0, 0, 1.0);
  set4(fb.u_viewport, m.width, m.height, m.style.pixels_per_edge, m.max_level);
  set4(fb.u_lines, 0, 0, level, m.reversed ? 1 : 0);
  GlObject ubo = make_buffer(sizeof fb, &fb, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, ubo.id());

  glVertexArrayElementBuffer(m.vao.id(), tmp_index.id());
  GlObject written(GlKind::Query, GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
  glEnable(GL_RASTERIZER_DISCARD);
  glUseProgram(m.capture_prog.id());
  glBindVertexArray(m.vao.id());
  glPatchParameteri(GL_PATCH_VERTICES, 3);
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, out.id());
  glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, written.id());
  glBeginTransformFeedback(GL_TRIANGLES);
  glDrawElements(GL_PATCHES, GLsizei(idx.size()), GL_UNSIGNED_INT, nullptr);
  glEndTransformFeedback();
  glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
  glDisable(GL_RASTERIZER_DISCARD);
  glVertexArrayElementBuffer(m.vao.id(), m.index_buf.id());
  GLuint prims = 0;
  glGetQueryObjectuiv(written.id(), GL_QUERY_RESULT, &prims);
  std::vector<PnSample> samples(std::size_t(prims) * 3);
  glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(samples.size() * sizeof(PnSample)), samples.data());
  for (auto& s : samples) s.face = faces.at(s.face);
  if (glGetError() != GL_NO_ERROR) throw terrain::Error("OpenGL error during the PN capture");
  return samples;
}

}  // namespace renderer
