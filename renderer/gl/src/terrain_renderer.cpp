// The sequencer of a frame: builds the pass objects (passes/passes.hpp) over the scene's
// shared GPU resources, fills the per-frame uniform block and runs the passes in order.
#include "renderer/gl/terrain_renderer.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "passes/passes.hpp"
#include "renderer/core/lod.hpp"
#include "renderer/core/stroke_visibility.hpp"
#include "renderer/gl/gl_contract.hpp"
#include "renderer/gl/programs.hpp"
#include "terrain/error.hpp"
#include "terrain/hillshade.hpp"
#include "terrain/memory.hpp"

namespace renderer {

namespace {

void set4(glsl::vec4& d, double a, double b, double c, double e) {
  d = {float(a), float(b), float(c), float(e)};
}

// Rows bottom-up (GL) to top-down, in place.
template <class T>
void flip_rows(std::vector<T>& v, int width, int height, int channels) {
  const std::size_t row = std::size_t(width) * std::size_t(channels);
  for (int r = 0; r < height / 2; ++r)
    std::swap_ranges(v.begin() + long(std::size_t(r) * row),
                     v.begin() + long(std::size_t(r + 1) * row),
                     v.begin() + long(std::size_t(height - 1 - r) * row));
}

// What the option table cannot know (options.hpp checks every option's range, and
// validate the drawn widths): the mesh, and the frame size for callers without the table.
void check_inputs(const terrain::GridMesh& mesh, int width, int height, const Layers& layers,
                  bool whole) {
  if (width < kMinFrameSide || height < kMinFrameSide || width > kMaxFrameSide ||
      height > kMaxFrameSide)
    throw terrain::Error(fmt::format("image size {} x {} is outside {} .. {} pixels", width, height,
                                     kMinFrameSide, kMaxFrameSide));
  if (mesh.topo.rows < 2 || mesh.topo.cols < 2) throw terrain::Error("the mesh has no faces");
  if (whole && mesh.n_faces() * 3 >
                   std::size_t(std::numeric_limits<GLsizei>::max()))  // one index list of them all
    throw terrain::Error(
        "the mesh has too many faces to draw whole; draw it in levels of detail (--lod-error > 0)");
  if (layers.pels && mesh.voronoi.empty())
    throw terrain::Error(
        "--layers pels needs the mesh's Voronoi weights: make it with denoise-normals "
        "(--iterations 0 only adds them)");
}

// Triangles the Adjacency ID pass can list: 4 per pixel (more are sub-pixel triangles),
// at least 1 M, at most 8 M (48 bytes each).
std::size_t id_capacity(int width, int height) {
  return std::clamp<std::size_t>(4 * std::size_t(width) * std::size_t(height), 1u << 20, 8u << 20);
}

}  // namespace

// Without the PEL and edge layers, which read the whole mesh on the GPU, levels of detail
// keep only the drawn vertices there (SceneGpu::set_lod_mesh).
static bool drawn_vertices_only(const MeshHolding& held, const Style& style, const Layers& layers) {
  return held.uses_lod(style.levels_of_detail()) && !layers.pels && !layers.edges;
}

// Formulated silhouettes are drawn with the Toward/Away silhouettes (SIL reads the drawn
// surface's normals, which TFT then writes).
static bool draws_formulated(const Layers& layers, const Style& style) {
  return layers.silhouettes && !layers.adjacency && style.formulated;
}

// TFT's colour where it draws no surface: the background, opaque, where the composite
// copies TFT's colour as its base (CompositePass::surface_is_base); else transparent black.
static Eigen::Vector4f toward_clear(const Layers& layers, const Style& style) {
  if (!passes::CompositePass::surface_is_base(layers, style)) return Eigen::Vector4f::Zero();
  return {style.background.x(), style.background.y(), style.background.z(), 1.0f};
}

struct TerrainRenderer::Impl {
  // `held`: the mesh against the whole it is part of (MeshHolding of mesh and levels).
  Impl(const GlContext& context, const terrain::GridMesh& mesh, const MeshHolding& held,
       const CreaseGeometry* creases, int width, int height, const Layers& layers,
       const Style& style, std::shared_ptr<const LodHierarchy> levels,
       std::shared_ptr<const std::vector<CreaseLevel>> crease_levels)
      : layers(layers),
        style(style),
        box(held.box(style.exaggeration)),
        origin(mesh.geo.origin_x, mesh.geo.origin_y, mesh.geo.origin_z),
        cell(held.fine_spacing()),
        lift(crease_lift(style, mesh)),
        visibility(stroke_visibility_rule(style, mesh)),
        scene(mesh, width, height, context.has_clip_control(),
              layers.hachures || draws_formulated(layers, style),
              !held.uses_lod(style.levels_of_detail()), !drawn_vertices_only(held, style, layers)),
        toward(scene, style.flat_patches, toward_clear(layers, style)),
        away(scene, layers.silhouettes && !layers.adjacency),
        ids(scene, layers.adjacency, id_capacity(width, height)),
        creases(scene, creases, layers.creases, style.antialias, std::move(crease_levels),
                layers.creases && style.levels_of_detail()),
        pels(scene, mesh, layers.pels, style.pel_width, style.antialias,
             style.pel_min_length * std::min(mesh.geo.dx, mesh.geo.dy), style.pel_smooth),
        edges(scene, layers.edges, style),
        silhouettes(scene, layers.silhouettes,
                    style.antialias ? style.silhouette_min_length * height : 0.0, style,
                    layers.adjacency ? &ids : nullptr, 1e-3 * std::min(cell.x(), cell.y()),
                    held.local_extent()),
        composite(scene, layers, style, this->creases, pels, edges, silhouettes),
        hachures(scene) {
    if (held.uses_lod(style.levels_of_detail())) {
      if (levels && !(terrain::level_count(levels->topo.rows - 1, levels->base) == mesh.topo.rows &&
                      terrain::level_count(levels->topo.cols - 1, levels->base) == mesh.topo.cols))
        throw terrain::Error("internal: levels of detail of another mesh");
      if (levels && levels->base > 0 && !style.levels_of_detail())
        throw terrain::Error(
            "internal: a coarser level of the mesh is held, but --lod-error 0 asks for every cell");
      if (drawn_vertices_only(held, style, layers)) source = &mesh;
      lod = levels ? std::move(levels) : std::make_shared<const LodHierarchy>(build_lod(mesh));
    }
    if (mesh.has_holes()) {
      outside.resize(mesh.n_vertices());
      for (std::size_t i = 0; i < outside.size(); ++i)
        outside[i] = mesh.filled[i] == terrain::kOutside;
    }
    GLint max_gen = 64;
    glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &max_gen);
    max_level = std::min(32, int(max_gen));
  }

  Layers layers;
  Style style;
  Box box;
  Eigen::Vector3d origin;
  Eigen::Vector2d cell;  // the mesh's spacing, metres (level 0's: fine_spacing)
  double lift = 0;
  StrokeVisibilityRule visibility;
  int max_level = 32;
  passes::SceneGpu scene;
  passes::TowardPass toward;
  passes::AwayPass away;
  passes::TriangleIdPass ids;  // replaces AFT in the sequence for Adjacency silhouettes
  passes::CreasePass creases;
  passes::PelPass pels;
  passes::EdgePass edges;
  passes::SilhouettePass silhouettes;
  passes::CompositePass composite;
  passes::HachurePass hachures;  // on demand after a frame (hachure_field), not in the sequence
  GlObject capture_prog;         // built on the first capture_pn
  std::shared_ptr<const LodHierarchy>
      lod;  // levels of detail (style.levels_of_detail(), a mesh of more than one block)
  const terrain::GridMesh* source =
      nullptr;  // the mesh the drawn vertices come from, when only they are on the GPU
  std::vector<std::uint8_t>
      lod_levels;  // the levels scene's patches are at (none before the first frame)
  std::vector<std::uint8_t> lod_facing;  // and the blocks marked facing among them (facing_blocks)
  std::vector<std::uint8_t> outside;     // per vertex: 1 outside the data (its faces not drawn)

  // In the order they run.
  std::array<passes::PassBase*, kPassCount> sequence() {
    passes::PassBase* second = layers.adjacency ? static_cast<passes::PassBase*>(&ids) : &away;
    return {&toward, second, &creases, &pels, &edges, &silhouettes, &composite};
  }
  FrameBlock frame_block(const FrameParams& frame, const View& v,
                         const Eigen::Vector3d& light) const;
};

FrameBlock TerrainRenderer::Impl::frame_block(const FrameParams& frame, const View& v,
                                              const Eigen::Vector3d& light) const {
  const CreaseScoreParams sp = resolve_distances(frame.score, box.lo, box.hi, v.viewpoint());
  const StrokeRule strokes = stroke_rule(style, page_scale(v, box));
  FrameBlock fb{};
  const Eigen::Matrix4f vp = v.view_projection().cast<float>();
  std::memcpy(fb.u_view_proj.data(), vp.data(), sizeof fb.u_view_proj);  // column-major, as GLSL
  set4(fb.u_eye, v.eye.x(), v.eye.y(), v.eye.z(), style.exaggeration);
  if (v.orthographic()) set4(fb.u_sight, v.forward.x(), v.forward.y(), v.forward.z(), v.far);
  set4(fb.u_light, light.x(), light.y(), light.z(), 0);
  set4(fb.u_viewport, scene.width, scene.height, style.pixels_per_edge, max_level);
  set4(fb.u_weights, sp.sw, sp.iw, sp.fw, sp.literal_divisor ? 3.0 : sp.sw + sp.iw + sp.fw);
  set4(fb.u_score, sp.min_score, sp.falloff, sp.far_distance, lift);
  set4(fb.u_lines, style.crease_width, style.crease_width_max, 0, scene.reversed ? 1 : 0);
  set4(fb.u_misc, v.near, double(creases.n_segments()), double(creases.n_vertices()),
       strokes.min_length);
  set4(fb.u_style, style.antialias ? 1 : 0, style.antialias ? style.crease_fade : 0,
       sp.near_distance, strokes.bridge);
  const bool aa = style.antialias;  // the visibility stage runs on anti-aliased lines only
  // A patch with an edge longer than a cell's diagonal (1 % over) is a coarse level's.
  const double diagonal2 = 1.0201 * (cell.x() * cell.x() + cell.y() * cell.y());
  set4(fb.u_lod, lod ? diagonal2 : 0, 0, 0, 0);
  set4(fb.u_strokes, aa ? visibility.gap_px : 0, aa ? visibility.gap_depth : 0,
       aa ? visibility.min_peek_px : 0, strokes.min_area);
  return fb;
}

// Memory a frame takes per pixel with every layer (the render targets, the read-back
// buffers): llvmpipe's peak resident memory grew by 64.2 bytes a pixel from 1024 x 1024 to
// 4096 x 4096 (MSH 50 m mesh, default layers).
constexpr double kFrameBytesPerPixel = 64.0;

// The frame size against the device's limits (texture, renderbuffer and viewport sizes)
// and, on a CPU renderer, whose textures are this machine's memory, against the memory
// available now: refused before anything is allocated, naming the largest size that works.
void check_frame_size(const GlContext& context, int width, int height) {
  GLint texture = 0, renderbuffer = 0, viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texture);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  const int max_w = std::min({texture, renderbuffer, viewport[0]}),
            max_h = std::min({texture, renderbuffer, viewport[1]});
  if (max_w > 0 && max_h > 0 && (width > max_w || height > max_h))
    throw terrain::Error(
        fmt::format("a {} x {} frame is larger than this OpenGL device ({}) draws: at most {} x {} "
                    "(GL_MAX_TEXTURE_SIZE, GL_MAX_RENDERBUFFER_SIZE, GL_MAX_VIEWPORT_DIMS)",
                    width, height, context.info().renderer, max_w, max_h));
  if (!context.info().software)
    return;  // a GPU's own memory: GL_OUT_OF_MEMORY is checked after allocation
  const double bytes = double(width) * double(height) * kFrameBytesPerPixel,
               available = terrain::available_memory();
  if (available > 0 && bytes > available) {
    const double shrink = std::sqrt(available / bytes);
    throw terrain::Error(fmt::format(
        "a {} x {} frame needs about {} on {} (a CPU renderer: its textures are this machine's "
        "memory), more "
        "than the memory available now ({}); the largest frame of this shape that fits is about {} "
        "x {}",
        width, height, terrain::bytes_text(bytes), context.info().renderer,
        terrain::bytes_text(available), int(double(width) * shrink), int(double(height) * shrink)));
  }
}

TerrainRenderer::TerrainRenderer(const GlContext& context, const terrain::GridMesh& mesh,
                                 const CreaseGeometry* creases, int width, int height,
                                 const Layers& layers, const Style& style,
                                 std::shared_ptr<const LodHierarchy> levels,
                                 std::shared_ptr<const std::vector<CreaseLevel>> crease_levels) {
  const MeshHolding held(mesh, levels.get());
  check_inputs(mesh, width, height, layers, !drawn_vertices_only(held, style, layers));
  check_frame_size(context, width, height);
  const auto out_of_memory = [&] {
    return terrain::Error(fmt::format(
        "cannot allocate a {} x {} frame on this OpenGL device ({}): out of its memory; "
        "give a smaller --size",
        width, height, context.info().renderer));
  };
  try {
    impl_ = std::make_unique<Impl>(context, mesh, held, creases, width, height, layers, style,
                                   std::move(levels), std::move(crease_levels));
  } catch (const terrain::Error& e) {  // a render target the device could not allocate
    if (std::string(e.what()).find("incomplete framebuffer") == std::string::npos &&
        glGetError() != GL_OUT_OF_MEMORY)
      throw;
    throw out_of_memory();
  }
  if (glGetError() == GL_OUT_OF_MEMORY) throw out_of_memory();
  if (impl_->scene.reversed) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glViewport(0, 0, width, height);
  glDisable(GL_CULL_FACE);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  if (glGetError() != GL_NO_ERROR)
    throw terrain::Error("OpenGL error while setting up the renderer");
  impl_->silhouettes.warm_up_timer();
}

TerrainRenderer::~TerrainRenderer() = default;

const Box& TerrainRenderer::box() const { return impl_->box; }
Eigen::Vector3d TerrainRenderer::origin() const { return impl_->origin; }

FrameResult TerrainRenderer::render(const FrameParams& frame) {
  auto& m = *impl_;
  if (!(frame.camera.fov > 0 && frame.camera.fov < 180))
    throw terrain::Error("fov must be in (0, 180) degrees");
  FrameResult res;
  res.width = m.scene.width;
  res.height = m.scene.height;
  res.view = make_view(frame.camera, m.origin, m.box, res.width, res.height, m.scene.reversed);
  if (m.lod) {
    std::vector<std::uint8_t> levels =
        select_lod(*m.lod, res.view, m.style.exaggeration, m.style.lod_error, lod_cell_px(m.style));
    std::vector<std::uint8_t> facing =
        facing_blocks(*m.lod, res.view, m.style.exaggeration, levels);
    if (levels != m.lod_levels || facing != m.lod_facing) {
      if (m.source) {
        LodMesh lm = lod_mesh(*m.lod, levels, facing);
        drop_outside_patches(lm.patches, m.outside, &lm.vertices, &lm.may_face_away);
        m.scene.set_lod_mesh(lm, *m.source);
      } else {
        std::size_t may_face_away = 0;
        std::vector<std::uint32_t> patches = lod_patches(*m.lod, levels, facing, &may_face_away);
        drop_outside_patches(patches, m.outside, nullptr, &may_face_away);
        m.scene.set_patches(patches, may_face_away);
      }
      m.lod_levels = std::move(levels), m.lod_facing = std::move(facing);
    }
  }
  res.patches = m.scene.n_patches;
  if (!m.creases.level_errors().empty())
    m.creases.set_level(select_crease_level(
        m.creases.level_errors(),
        nearest_pixel_metres(m.lod.get(), m.box, res.view, m.style.exaggeration),
        kCreaseErrorPerLod * m.style.lod_error));
  res.crease_level = m.creases.level();
  const Eigen::Vector3d light = terrain::light_direction(frame.light.azimuth, frame.light.altitude);
  const FrameBlock fb = m.frame_block(frame, res.view, light);
  glNamedBufferSubData(m.scene.ubo.id(), 0, sizeof fb, &fb);
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, m.scene.ubo.id());

  // Several renderers may share a context (terrain-view's full and cheap frames): the
  // viewport is this renderer's own at every frame.
  glViewport(0, 0, m.scene.width, m.scene.height);
  glFinish();
  const passes::FrameInputs in{frame, res.view, light};
  for (passes::PassBase* pass : m.sequence()) pass->run(in, res.timings);
  for (passes::PassBase* pass : m.sequence()) pass->read_timer(res.timings);
  res.crease_segments = m.creases.segments_drawn();
  res.pel_segments = m.pels.segments_drawn();
  res.edges = m.edges.edges_drawn();
  res.rgba.resize(std::size_t(res.width) * std::size_t(res.height) * 4);
  glGetTextureImage(m.composite.colour().id(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                    GLsizei(res.rgba.size()), res.rgba.data());
  flip_rows(res.rgba, res.width, res.height, 4);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR)
    throw terrain::Error(fmt::format("OpenGL error 0x{:x} while rendering", err));
  return res;
}

HachureField TerrainRenderer::hachure_field(const View& view, bool light_tone) const {
  return impl_->hachures.field(view, light_tone);
}

FrameBuffers TerrainRenderer::read_buffers(bool normals) const {
  const auto& m = *impl_;
  const int w = m.scene.width, h = m.scene.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  FrameBuffers b;
  auto depth = [&](const GlObject& t, std::vector<float>& out) {
    out.resize(n);
    glGetTextureImage(t.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(n * 4), out.data());
    flip_rows(out, w, h, 1);
  };
  auto bytes = [&](const GlObject& t, std::vector<std::uint8_t>& out) {
    out.resize(n);
    glGetTextureImage(t.id(), 0, GL_RED, GL_UNSIGNED_BYTE, GLsizei(n), out.data());
    flip_rows(out, w, h, 1);
  };
  auto red = [&](const GlObject& t, std::vector<std::uint8_t>& out) {
    bytes(t, out);
    for (auto& x : out) x = x > 0;
  };
  depth(m.scene.toward_depth, b.toward_depth);
  depth(m.scene.away_depth, b.away_depth);
  red(m.silhouettes.mask(), b.silhouette);
  bytes(m.silhouettes.opacity(), b.silhouette_opacity);
  red(m.creases.colour(), b.crease);
  red(m.edges.colour(), b.edge);
  if (normals && m.scene.surface_normal.id()) {
    b.surface_normal.resize(4 * n);
    glGetTextureImage(m.scene.surface_normal.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(16 * n),
                      b.surface_normal.data());
    flip_rows(b.surface_normal, w, h, 4);
  }
  b.surface_rgba.resize(4 * n);
  glGetTextureImage(m.scene.surface_colour.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(4 * n),
                    b.surface_rgba.data());
  flip_rows(b.surface_rgba, w, h, 4);
  if (m.layers.adjacency) {
    b.triangle_id.resize(n);
    glGetTextureImage(m.ids.ids().id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(n * 4),
                      b.triangle_id.data());
    flip_rows(b.triangle_id, w, h, 1);
    const std::size_t k = std::min(m.ids.triangles_drawn(), m.ids.capacity());
    std::vector<float> raw(12 * k);
    if (k)
      glGetNamedBufferSubData(m.ids.triangles().id(), 16, GLsizeiptr(raw.size() * 4), raw.data());
    b.triangles.resize(9 * k);
    for (std::size_t t = 0; t < 3 * k; ++t) std::copy_n(&raw[4 * t], 3, &b.triangles[3 * t]);
  }
  return b;
}

std::vector<TerrainRenderer::PelSegmentOut> TerrainRenderer::read_pels() const {
  const std::vector<float> raw = impl_->pels.read_segments();
  std::vector<PelSegmentOut> out(raw.size() / 8);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float* r = &raw[8 * i];
    out[i].a = {r[0], r[1], r[2]};
    std::memcpy(&out[i].face, &r[3], 4);
    out[i].b = {r[4], r[5], r[6]};
    out[i].opacity = r[7];
  }
  return out;
}

TerrainRenderer::EdgesOut TerrainRenderer::read_edges() const {
  return {impl_->edges.read_kinds(), impl_->edges.read_drawn()};
}

std::vector<SegmentSamples> TerrainRenderer::read_crease_samples() const {
  return impl_->creases.read_samples();
}

std::vector<TerrainRenderer::PnSample> TerrainRenderer::capture_pn(
    const std::vector<std::uint32_t>& faces, int level) {
  auto& m = *impl_;
  const auto& s = m.scene;
  if (level < 1 || level > m.max_level) throw terrain::Error("capture level out of range");
  if (m.source)
    throw terrain::Error(
        "internal: the PN capture needs the whole mesh on the GPU (--lod-error 0)");
  if (!m.capture_prog.id()) m.capture_prog = build_program(ProgramId::PnCapture);
  std::vector<std::uint32_t> idx;
  for (const auto f : faces) {
    if (f >= s.topo.n_faces()) throw terrain::Error("capture face out of range");
    const auto t = s.topo.face(f);
    idx.insert(idx.end(), t.begin(), t.end());
  }
  GlObject tmp_index = make_buffer(idx.size() * 4, idx.data(), 0);
  const std::size_t max_vertices =
      faces.size() * 3 * std::size_t(level + 2) * std::size_t(level + 2);
  GlObject out = make_buffer(max_vertices * sizeof(PnSample), nullptr, 0);

  FrameBlock fb{};
  const Eigen::Matrix4f id = Eigen::Matrix4f::Identity();
  std::memcpy(fb.u_view_proj.data(), id.data(), sizeof fb.u_view_proj);
  set4(fb.u_eye, 0, 0, 0, 1.0);
  set4(fb.u_viewport, s.width, s.height, m.style.pixels_per_edge, m.max_level);
  set4(fb.u_lines, 0, 0, level, s.reversed ? 1 : 0);
  GlObject ubo = make_buffer(sizeof fb, &fb, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, TR_UBO_FRAME, ubo.id());

  glVertexArrayElementBuffer(s.vao.id(), tmp_index.id());
  GlObject written(GlKind::Query, GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
  glEnable(GL_RASTERIZER_DISCARD);
  glUseProgram(m.capture_prog.id());
  glBindVertexArray(s.vao.id());
  glPatchParameteri(GL_PATCH_VERTICES, 3);
  glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, out.id());
  glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, written.id());
  glBeginTransformFeedback(GL_TRIANGLES);
  glDrawElements(GL_PATCHES, GLsizei(idx.size()), GL_UNSIGNED_INT, nullptr);
  glEndTransformFeedback();
  glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
  glDisable(GL_RASTERIZER_DISCARD);
  glVertexArrayElementBuffer(s.vao.id(), s.index_buf.id());
  GLuint prims = 0;
  glGetQueryObjectuiv(written.id(), GL_QUERY_RESULT, &prims);
  std::vector<PnSample> samples(std::size_t(prims) * 3);
  glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(samples.size() * sizeof(PnSample)),
                          samples.data());
  for (auto& sample : samples) sample.face = faces.at(sample.face);
  if (glGetError() != GL_NO_ERROR) throw terrain::Error("OpenGL error during the PN capture");
  return samples;
}

}  // namespace renderer
